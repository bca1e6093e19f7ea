#include "stratum/error.hpp"

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
  switch (s) {
  case Status::ok:
    return "ok";
  case Status::not_converged:
    return "not converged";
  case Status::material_failure:
    return "material failure";
  case Status::singular:
    return "singular matrix";
  case Status::non_finite:
    return "NaN or Inf";
  case Status::diverged:
    return "diverged";
  }
  return "unknown";
}

} // namespace stratum
