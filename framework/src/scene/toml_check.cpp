#include "scene/toml_check.hpp"

#include "stratum/enum_names.hpp"
#include "suggest.hpp"

#include <charconv>
#include <cmath>
#include <sstream>

namespace stratum::io {

SourceLocation location(const toml::source_region& r) {
  return {r.path ? *r.path : std::string(), static_cast<int>(r.begin.line), static_cast<int>(r.begin.column)};
}

SourceLocation location(const toml::node& n) { return location(n.source()); }

std::string show(const toml::node& n) {
  if (n.is_table()) return "{...}";
  std::ostringstream o;
  if (auto a = n.as_array()) {
    o << '[';
    for (std::size_t i = 0; i < a->size(); ++i) o << (i ? ", " : "") << show(*a->get(i));
    o << ']';
    return o.str();
  }
  n.visit([&](const auto& v) {
    if constexpr (toml::is_string<decltype(v)>) {
      o << '"' << v.get() << '"';
    } else if constexpr (toml::is_floating_point<decltype(v)>) {
      char buf[64];
      auto r = std::to_chars(buf, buf + sizeof buf, v.get()); // shortest form that reads back exactly
      o << std::string_view(buf, static_cast<std::size_t>(r.ptr - buf));
    } else if constexpr (toml::is_integer<decltype(v)> || toml::is_boolean<decltype(v)>) {
      o << v;
    } else {
      o << "(value)";
    }
  });
  return o.str();
}

const char* type_name(const toml::node& n) {
  // In the order of toml::node_type: none, table, array, string, integer, floating_point,
  // boolean, date, time, date_time.
  static constexpr std::array<const char*, 10> names{
      "a date or time", "a table",   "an array",       "a string",       "an integer",
      "a number",       "a boolean", "a date or time", "a date or time", "a date or time"};
  return enum_name(n.type(), names, "a date or time");
}

double number(const toml::node& n) {
  if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
  return n.as_floating_point()->get();
}

namespace {

/// The largest magnitude of a real number in a scene (check_table).
constexpr double largest_real = 1e20;

std::string expected(const ParamSpec& s) {
  static constexpr std::array<const char*, 5> names{"a number", "an integer", "true or false", "a string",
                                                    "an array of numbers (or one number)"};
  return enum_name(s.type, names);
}

std::string show_number(double x) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, static_cast<std::size_t>(r.ptr - buf));
}

[[noreturn]] void wrong_type(const toml::node& v, const std::string& ctx, const ParamSpec& s) {
  throw Error(location(v), ctx + " " + s.name + " = " + show(v) + " has the wrong type: expected " +
                               expected(s) + ", got " + type_name(v));
}

} // namespace

namespace {

/// A default declared in kN, m, kPa, in the scene's units (unchanged when they are the default).
ParamValue default_in(const ParamSpec& s, const Units& units, const std::string& context,
                      const toml::table& table) {
  ParamValue v = *s.fallback;
  if (units.is_default() || (s.type != ParamType::real && s.type != ParamType::real_list)) return v;
  if (is_sentinel_default(s)) return v; // "-1: none" is a flag, not a quantity
  const auto f = units.factor(s.unit);
  if (auto* x = std::get_if<double>(&v)) {
    if (*x == 0.0) return v;
    if (!f)
      throw Error(location(table), context + " " + s.name + " is not given, and its default " +
                                       show_number(*x) + " (" + s.unit +
                                       ", in kN, m, kPa) cannot be converted to [units] " + units.describe() +
                                       "; allowed: give " + s.name + " in the table");
    *x *= *f;
  } else if (auto* xs = std::get_if<std::vector<double>>(&v)) {
    bool zero = true;
    for (double e : *xs) zero = zero && e == 0.0;
    if (zero) return v;
    if (!f)
      throw Error(location(table), context + " " + s.name + " is not given, and its default (" + s.unit +
                                       ", in kN, m, kPa) cannot be converted to [units] " + units.describe() +
                                       "; allowed: give " + s.name + " in the table");
    for (double& e : *xs) e *= *f;
  }
  return v;
}

/// The spec with its range bounds in the scene's units (they are declared in kN, m, kPa).
ParamSpec in_units(const ParamSpec& s, const Units& units) {
  ParamSpec c = s;
  if (units.is_default() || (s.type != ParamType::real && s.type != ParamType::real_list)) return c;
  const auto f = units.factor(s.unit);
  if (!f || *f == 1.0) return c;
  if (c.lower && !is_sentinel_default(s)) *c.lower *= *f;
  if (c.upper) *c.upper *= *f;
  return c;
}

} // namespace

Params check_table(const toml::table& table, const Schema& schema, const std::string& context,
                   const std::vector<std::string_view>& extra, const Units& units) {
  for (auto&& [key, value] : table) {
    const std::string k(key.str());
    bool ok = schema.find(k) != nullptr;
    for (auto e : extra) ok = ok || e == k;
    if (!ok) {
      std::string allowed;
      std::vector<std::string_view> names(extra.begin(), extra.end());
      for (auto e : extra) allowed += (allowed.empty() ? "" : ", ") + std::string(e);
      for (const auto& s : schema.specs()) {
        allowed += (allowed.empty() ? "" : ", ") + s.name;
        names.emplace_back(s.name);
      }
      throw Error(location(key.source()), context + " unknown key '" + k +
                                              "'; allowed: " + (allowed.empty() ? "(none)" : allowed) +
                                              did_you_mean(k, names));
    }
  }
  Params p;
  p.context = context;
  if (!units.is_default())
    p.set(units_param, units.force() + " " + units.length() + " " + units.time(), units.declared_at);
  for (const auto& declared : schema.specs()) {
    const ParamSpec s = in_units(declared, units);
    const toml::node* v = table.get(s.name);
    if (!v) {
      if (s.required())
        throw Error(location(table), context + " missing required parameter '" + s.name + "' (" + s.meaning +
                                         (s.unit.empty() || s.unit == "-" ? "" : ", " + units.label(s.unit)) +
                                         ")");
      p.set(s.name, default_in(s, units, context, table));
      continue;
    }
    const auto where = location(*v);
    auto check_number = [&](double x) {
      if (!std::isfinite(x) || !s.in_range(x))
        throw Error(where, context + " " + s.name + " = " + show(*v) + " is outside " + s.allowed());
    };
    // Beyond the declared range, a bound for every real number: stiffnesses, forces and lengths
    // are multiplied together, and a value near the largest double (E = 1e308) overflows into
    // a NaN long after the scene was read.
    auto check_magnitude = [&](double x, const toml::node& at) {
      if (std::abs(x) > largest_real)
        throw Error(location(at),
                    context + " " + s.name + " = " + show(at) + " is larger in magnitude than " +
                        "1e20, the largest number a scene may give (products of such numbers overflow)");
    };
    switch (s.type) {
    case ParamType::real: {
      if (!v->is_number()) wrong_type(*v, context, s);
      const double x = number(*v);
      check_number(x);
      check_magnitude(x, *v);
      p.set(s.name, x, where);
      break;
    }
    case ParamType::integer: {
      if (!v->is_integer()) wrong_type(*v, context, s);
      const auto x = v->as_integer()->get();
      check_number(static_cast<double>(x));
      p.set(s.name, static_cast<long long>(x), where);
      break;
    }
    case ParamType::boolean:
      if (!v->is_boolean()) wrong_type(*v, context, s);
      p.set(s.name, v->as_boolean()->get(), where);
      break;
    case ParamType::text: {
      if (!v->is_string()) wrong_type(*v, context, s);
      std::string x = v->as_string()->get();
      if (!s.choices.empty()) {
        bool found = false;
        for (const auto& c : s.choices) found = found || c == x;
        if (!found)
          throw Error(where,
                      context + " " + s.name + " = " + show(*v) + " is not allowed; allowed: " + s.allowed());
      }
      p.set(s.name, std::move(x), where);
      break;
    }
    case ParamType::real_list: {
      std::vector<double> xs;
      if (v->is_number()) { // a single number is a list of one
        const double x = number(*v);
        if (!std::isfinite(x) || !s.in_range(x))
          throw Error(location(*v), context + " " + s.name + " = " + show(*v) + " is outside " + s.allowed());
        check_magnitude(x, *v);
        p.set(s.name, std::vector<double>{x}, where);
        break;
      }
      const auto* a = v->as_array();
      if (!a) wrong_type(*v, context, s);
      for (const auto& e : *a) {
        if (!e.is_number()) wrong_type(*v, context, s);
        const double x = number(e);
        if (!std::isfinite(x) || !s.in_range(x))
          throw Error(location(e),
                      context + " " + s.name + " contains " + show(e) + ", outside " + s.allowed());
        check_magnitude(x, e);
        xs.push_back(x);
      }
      p.set(s.name, std::move(xs), where);
      p.mark_written_as_list(s.name);
      break;
    }
    }
  }
  return p;
}

std::string require_string(const toml::table& table, std::string_view key, const std::string& context) {
  const toml::node* v = table.get(key);
  if (!v) throw Error(location(table), context + " missing required key '" + std::string(key) + "'");
  if (!v->is_string())
    throw Error(location(*v), context + " " + std::string(key) + " = " + show(*v) +
                                  " has the wrong type: expected a string, got " + type_name(*v));
  return v->as_string()->get();
}

void require_read(const Params& p, const Schema& schema, const std::string& context) {
  for (const auto& spec : schema.specs())
    if (p.where(spec.name).known() && !p.read_names().count(spec.name))
      throw Error(p.where(spec.name), context + " " + spec.name +
                                          " has no effect in this scene (the reader of the table does not "
                                          "use it here); remove it");
}

} // namespace stratum::io
