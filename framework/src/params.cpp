#include "stratum/params.hpp"
#include "stratum/enum_names.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace stratum {

const char* to_string(ParamType t) {
  static constexpr std::array<const char*, 5> names{"number", "integer", "boolean", "string",
                                                    "array of numbers"};
  return enum_name(t, names);
}

namespace {
std::string number(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream o;
  if (v == std::floor(v) && std::abs(v) < 1e15)
    o << static_cast<long long>(v); // integer bounds in full: 2147483647, not 2.14748e+09
  else
    o << v;
  return o.str();
}
} // namespace

std::string ParamSpec::allowed() const {
  if (!choices.empty()) {
    std::string s = "one of: ";
    for (std::size_t i = 0; i < choices.size(); ++i) s += (i ? ", " : "") + choices[i];
    return s;
  }
  if (type == ParamType::boolean) return "true or false";
  if (!lower && !upper) return "any " + std::string(to_string(type));
  std::string s = lower ? (lower_open ? "(" : "[") + number(*lower) : "(-inf";
  s += ", ";
  s += upper ? number(*upper) + (upper_open ? ")" : "]") : "inf)";
  return s;
}

bool ParamSpec::in_range(double v) const {
  if (std::isnan(v)) return false;
  if (lower && (lower_open ? !(v > *lower) : !(v >= *lower))) return false;
  if (upper && (upper_open ? !(v < *upper) : !(v <= *upper))) return false;
  return true;
}

ParamSpec& Schema::add(ParamSpec s) {
  if (find(s.name)) throw Error("schema declares parameter '" + s.name + "' twice");
  specs_.push_back(std::move(s));
  return specs_.back();
}

namespace {
ParamSpec make(std::string name, ParamType type, std::string unit, std::string meaning) {
  ParamSpec s;
  s.name = std::move(name);
  s.type = type;
  s.unit = std::move(unit);
  s.meaning = std::move(meaning);
  return s;
}
} // namespace

ParamSpec& Schema::real(std::string name, std::string unit, std::string meaning) {
  return add(make(std::move(name), ParamType::real, std::move(unit), std::move(meaning)));
}
ParamSpec& Schema::integer(std::string name, std::string unit, std::string meaning) {
  // Integers are used as int (counts, indices): a value is checked against the int range
  // unless the declaration narrows it, so that 2^32 + 8 is refused rather than cut to 8.
  return add(make(std::move(name), ParamType::integer, std::move(unit), std::move(meaning)))
      .at_least(static_cast<double>(std::numeric_limits<int>::min()))
      .at_most(static_cast<double>(std::numeric_limits<int>::max()));
}
ParamSpec& Schema::boolean(std::string name, std::string meaning) {
  return add(make(std::move(name), ParamType::boolean, "-", std::move(meaning)));
}
ParamSpec& Schema::text(std::string name, std::vector<std::string> choices, std::string meaning) {
  auto s = make(std::move(name), ParamType::text, "-", std::move(meaning));
  s.choices = std::move(choices);
  return add(std::move(s));
}
ParamSpec& Schema::real_list(std::string name, std::string unit, std::string meaning) {
  return add(make(std::move(name), ParamType::real_list, std::move(unit), std::move(meaning)));
}

const ParamSpec* Schema::find(const std::string& name) const {
  for (const auto& s : specs_)
    if (s.name == name) return &s;
  return nullptr;
}

void Params::set(const std::string& name, ParamValue value, SourceLocation where) {
  values_[name] = {std::move(value), std::move(where)};
}

const ParamValue& Params::get(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) throw Error(context + " parameter '" + name + "' was not declared by the plugin");
  read_.insert(name);
  return it->second.first;
}

double Params::real(const std::string& name) const {
  const auto& v = get(name);
  if (auto p = std::get_if<double>(&v)) return *p;
  if (auto p = std::get_if<long long>(&v)) return static_cast<double>(*p);
  throw Error(context + " parameter '" + name + "' is not a number");
}
long long Params::integer(const std::string& name) const {
  if (auto p = std::get_if<long long>(&get(name))) return *p;
  throw Error(context + " parameter '" + name + "' is not an integer");
}
bool Params::flag(const std::string& name) const {
  if (auto p = std::get_if<bool>(&get(name))) return *p;
  throw Error(context + " parameter '" + name + "' is not a boolean");
}
const std::string& Params::text(const std::string& name) const {
  if (auto p = std::get_if<std::string>(&get(name))) return *p;
  throw Error(context + " parameter '" + name + "' is not a string");
}
const std::vector<double>& Params::real_list(const std::string& name) const {
  if (auto p = std::get_if<std::vector<double>>(&get(name))) return *p;
  throw Error(context + " parameter '" + name + "' is not an array of numbers");
}
SourceLocation Params::where(const std::string& name) const {
  auto it = values_.find(name);
  return it == values_.end() ? SourceLocation{} : it->second.second;
}

} // namespace stratum
