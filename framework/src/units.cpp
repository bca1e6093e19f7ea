#include "stratum/units.hpp"

#include "suggest.hpp"

#include <cctype>
#include <cmath>
#include <sstream>

namespace stratum {

namespace {

struct Base {
  std::string_view name;
  int force, length, time;
  double scale; // in kN, m and s
};

constexpr Base bases[] = {
    {"N", 1, 0, 0, 1e-3},   {"kN", 1, 0, 0, 1.0},      {"MN", 1, 0, 0, 1e3},   {"mm", 0, 1, 0, 1e-3},
    {"cm", 0, 1, 0, 1e-2},  {"m", 0, 1, 0, 1.0},       {"Pa", 1, -2, 0, 1e-3}, {"kPa", 1, -2, 0, 1.0},
    {"MPa", 1, -2, 0, 1e3}, {"GPa", 1, -2, 0, 1e6},    {"s", 0, 0, 1, 1.0},    {"min", 0, 0, 1, 60.0},
    {"h", 0, 0, 1, 3600.0}, {"day", 0, 0, 1, 86400.0},
};

const Base* find_base(std::string_view name) {
  for (const auto& b : bases)
    if (b.name == name) return &b;
  return nullptr;
}

bool is_dimensionless_word(std::string_view u) {
  // "s (wall clock)": a time the program measures (progress tables), not one of the scene's
  return u.empty() || u == "-" || u == "1" || u == "deg" || u == "degree" || u == "degrees" || u == "rad" ||
         u == "s (wall clock)";
}

bool letter(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; }
bool digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

} // namespace

std::optional<Dimension> parse_unit(std::string_view unit) {
  if (is_dimensionless_word(unit)) return Dimension{};
  Dimension d;
  int sign = 1; // after '/': the denominator
  int slashes = 0;
  std::size_t i = 0;
  bool any = false;
  while (i < unit.size()) {
    const char c = unit[i];
    if (c == ' ' || c == '*' || c == '.') {
      ++i;
      continue;
    }
    if (c == '/') {
      if (++slashes > 1) return std::nullopt;
      sign = -1;
      ++i;
      continue;
    }
    if (c == '1' && (i + 1 == unit.size() || unit[i + 1] == '/')) { // "1/kPa"
      ++i;
      any = true;
      continue;
    }
    if (!letter(c)) return std::nullopt;
    std::size_t j = i;
    while (j < unit.size() && letter(unit[j])) ++j;
    const Base* b = find_base(unit.substr(i, j - i));
    if (!b) return std::nullopt;
    if (j < unit.size() && unit[j] == '^') ++j;
    int power = 1;
    if (j < unit.size() && digit(unit[j])) {
      power = 0;
      while (j < unit.size() && digit(unit[j])) power = 10 * power + (unit[j++] - '0');
      if (power == 0 || power > 9) return std::nullopt;
    }
    d.force += sign * power * b->force;
    d.length += sign * power * b->length;
    d.time += sign * power * b->time;
    d.scale *= std::pow(b->scale, sign * power);
    any = true;
    i = j;
  }
  if (!any) return std::nullopt;
  return d;
}

const std::vector<std::string_view>& Units::force_units() {
  static const std::vector<std::string_view> v{"N", "kN", "MN"};
  return v;
}
const std::vector<std::string_view>& Units::length_units() {
  static const std::vector<std::string_view> v{"mm", "cm", "m"};
  return v;
}
const std::vector<std::string_view>& Units::time_units() {
  static const std::vector<std::string_view> v{"s", "min", "h", "day"};
  return v;
}

namespace {
std::string list(const std::vector<std::string_view>& v) {
  std::string s;
  for (auto x : v) s += (s.empty() ? "" : ", ") + std::string(x);
  return s;
}
bool among(const std::vector<std::string_view>& v, const std::string& x) {
  for (auto e : v)
    if (e == x) return true;
  return false;
}
} // namespace

Units::Units(std::string force, std::string length, std::string time)
    : force_(std::move(force)), length_(std::move(length)), time_(std::move(time)) {
  if (!among(time_units(), time_))
    throw Error("time = \"" + time_ + "\" is not a time unit; allowed: " + list(time_units()) +
                did_you_mean(time_, time_units()));
  if (!among(force_units(), force_))
    throw Error("force = \"" + force_ + "\" is not a force unit; allowed: " + list(force_units()) +
                did_you_mean(force_, force_units()));
  if (!among(length_units(), length_))
    throw Error("length = \"" + length_ + "\" is not a length unit; allowed: " + list(length_units()) +
                did_you_mean(length_, length_units()));
}

double Units::force_in_kN() const { return find_base(force_)->scale; }
double Units::length_in_m() const { return find_base(length_)->scale; }
double Units::time_in_s() const { return find_base(time_)->scale; }

std::string Units::stress() const {
  // The pascal multiples that force / length^2 happens to be; otherwise spelt out.
  const double kpa = force_in_kN() / (length_in_m() * length_in_m());
  for (const auto& b : bases)
    if (b.force == 1 && b.length == -2 && std::abs(b.scale / kpa - 1.0) < 1e-12) return std::string(b.name);
  return force_ + "/" + length_ + "2";
}

std::string Units::describe() const {
  return force_ + ", " + length_ + ", " + stress() + (time_ == "s" ? "" : ", " + time_);
}

std::optional<double> Units::factor(std::string_view unit) const {
  const auto d = parse_unit(unit);
  if (!d) return std::nullopt;
  if (d->dimensionless()) return 1.0;
  return d->scale / (std::pow(force_in_kN(), d->force) * std::pow(length_in_m(), d->length) *
                     std::pow(time_in_s(), d->time));
}

std::string Units::label(std::string_view unit) const {
  const auto d = parse_unit(unit);
  if (!d || d->dimensionless() || is_default()) return std::string(unit);
  std::string out;
  std::size_t i = 0;
  while (i < unit.size()) {
    if (!letter(unit[i])) {
      out += unit[i++];
      continue;
    }
    std::size_t j = i;
    while (j < unit.size() && letter(unit[j])) ++j;
    const Base* b = find_base(unit.substr(i, j - i));
    const bool powered = j < unit.size() && (unit[j] == '^' || digit(unit[j]));
    if (b->time == 1)
      out += time_;
    else if (b->force == 1 && b->length == 0)
      out += force_;
    else if (b->force == 0 && b->length == 1)
      out += length_;
    else {
      const std::string s = stress();
      const bool compound = s.find('/') != std::string::npos;
      out += compound && (powered || i > 0 || j < unit.size()) ? "(" + s + ")" : s;
    }
    i = j;
  }
  return out;
}

bool is_sentinel_default(const ParamSpec& s) {
  if (s.type != ParamType::real || !s.fallback || !s.lower) return false;
  const auto* x = std::get_if<double>(&*s.fallback);
  return x && *x < 0.0 && *x == *s.lower;
}

ParamSpec spec_in_units(const ParamSpec& spec, const Units& units) {
  ParamSpec c = spec;
  if (units.is_default() || (c.type != ParamType::real && c.type != ParamType::real_list)) return c;
  const auto f = units.factor(c.unit);
  if (!f) {
    c.unit += " (kN, m, kPa)";
    return c;
  }
  c.unit = units.label(c.unit);
  if (is_sentinel_default(spec)) {
    if (c.upper) *c.upper *= *f;
    return c;
  }
  if (c.lower) *c.lower *= *f;
  if (c.upper) *c.upper *= *f;
  if (c.fallback) {
    if (auto* x = std::get_if<double>(&*c.fallback)) *x *= *f;
    if (auto* xs = std::get_if<std::vector<double>>(&*c.fallback))
      for (double& e : *xs) e *= *f;
  }
  return c;
}

std::string Units::column(std::string_view name, std::string_view unit) const {
  std::string s(name);
  s += '_';
  for (char c : label(unit)) {
    if (c == '/')
      s += "_per_";
    else if (c != '(' && c != ')' && c != ' ')
      s += c;
  }
  return s;
}

Units units_of(const Params& p) {
  if (!p.has(units_param)) return {};
  std::istringstream words(p.text(units_param)); // "force length time"
  std::string force, length, time = "s";
  words >> force >> length >> time;
  return {force, length, time};
}

void require_default_units(const Params& p, const std::string& why) {
  const Units u = units_of(p);
  if (u.force() == "kN" && u.length() == "m") return; // the time unit changes none of kN, m, kPa
  throw Error(p.where(units_param), (p.context.empty() ? std::string() : p.context + " ") +
                                        "cannot compute in [units] " + u.describe() + ": " + why +
                                        "; allowed: kN, m, kPa (remove [units] or use another model)");
}

} // namespace stratum
