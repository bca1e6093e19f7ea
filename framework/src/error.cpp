#include "stratum/error.hpp"
#include "stratum/enum_names.hpp"

namespace stratum {

std::string SourceLocation::str() const {
  if (file.empty()) return {};
  if (line <= 0) return file;
  return file + ":" + std::to_string(line) + ":" + std::to_string(column > 0 ? column : 1);
}

Error::Error(const std::string& message) : std::runtime_error(message), message_(message) {}

Error::Error(SourceLocation where, const std::string& message)
    : std::runtime_error(where.known() ? where.str() + " " + message : message), where_(std::move(where)),
      message_(message) {}

const char* to_string(Status s) {
  static constexpr std::array<const char*, 7> names{
      "ok", "not converged", "material failure", "singular matrix", "NaN or Inf", "diverged", "fatal error"};
  return enum_name(s, names, "unknown");
}

} // namespace stratum
