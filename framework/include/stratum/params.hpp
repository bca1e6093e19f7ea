// Parameter schemas and validated parameter values.
//
// Every plugin factory declares its parameters once (name, unit, meaning, range,
// default). The scene reader checks the TOML against the schema before anything
// runs and hands the plugin a Params object in which every value is present
// (given or defaulted), of the declared type and inside the declared range.
#pragma once

#include "stratum/error.hpp"

#include <map>
#include <optional>
#include <set>
#include <string>
#include <variant>
#include <vector>

namespace stratum {

enum class ParamType { real, integer, boolean, text, real_list };

[[nodiscard]] const char* to_string(ParamType t);

using ParamValue = std::variant<double, long long, bool, std::string, std::vector<double>>;

/// One declared parameter. Setters return *this so a declaration reads as one line.
struct ParamSpec {
  std::string name;
  ParamType type = ParamType::real;
  std::string unit;    ///< "kPa", "-", "kN/m3", ... ("-" for dimensionless)
  std::string meaning; ///< one sentence
  std::optional<double> lower, upper;
  bool lower_open = false, upper_open = false;
  std::optional<ParamValue> fallback; ///< the default; none means required
  std::vector<std::string> choices;   ///< for text parameters: the allowed values
  /// When the value used in the parameter's absence is not the fallback itself but computed by the
  /// plugin (e.g. from other parameters): what it is, for the reference and `--describe`.
  std::string default_note;

  ParamSpec& at_least(double v) {
    lower = v;
    lower_open = false;
    return *this;
  }
  ParamSpec& greater_than(double v) {
    lower = v;
    lower_open = true;
    return *this;
  }
  ParamSpec& at_most(double v) {
    upper = v;
    upper_open = false;
    return *this;
  }
  ParamSpec& less_than(double v) {
    upper = v;
    upper_open = true;
    return *this;
  }
  ParamSpec& defaults_to(ParamValue v) {
    fallback = std::move(v);
    return *this;
  }

  /// Absent: computed by the plugin as `note` says (the fallback only marks it optional).
  ParamSpec& defaults_to_computed(ParamValue placeholder, std::string note) {
    fallback = std::move(placeholder);
    default_note = std::move(note);
    return *this;
  }

  [[nodiscard]] bool required() const { return !fallback.has_value(); }
  /// "[0, 0.5)", "(0, inf)", "one of: a, b" or "any".
  [[nodiscard]] std::string allowed() const;
  /// True when a number lies inside the declared range.
  [[nodiscard]] bool in_range(double v) const;
};

/// The ordered list of a factory's parameters.
class Schema {
public:
  ParamSpec& real(std::string name, std::string unit, std::string meaning);
  ParamSpec& integer(std::string name, std::string unit, std::string meaning);
  ParamSpec& boolean(std::string name, std::string meaning);
  ParamSpec& text(std::string name, std::vector<std::string> choices, std::string meaning);
  ParamSpec& real_list(std::string name, std::string unit, std::string meaning);

  [[nodiscard]] const std::vector<ParamSpec>& specs() const { return specs_; }
  [[nodiscard]] const ParamSpec* find(const std::string& name) const;

private:
  ParamSpec& add(ParamSpec s);
  std::vector<ParamSpec> specs_;
};

/// Validated values: every declared parameter is present, typed and in range.
/// Accessors throw stratum::Error for undeclared names (a plugin bug).
class Params {
public:
  Params() = default;

  void set(const std::string& name, ParamValue value, SourceLocation where = {});

  [[nodiscard]] double real(const std::string& name) const;
  [[nodiscard]] long long integer(const std::string& name) const;
  [[nodiscard]] bool flag(const std::string& name) const;
  [[nodiscard]] const std::string& text(const std::string& name) const;
  [[nodiscard]] const std::vector<double>& real_list(const std::string& name) const;
  [[nodiscard]] bool has(const std::string& name) const { return values_.count(name) != 0; }
  /// A real_list parameter written as a TOML array (`K = [500.0]`), not as one number (`K = 500.0`):
  /// a plugin that broadcasts a number must not broadcast a list of one.
  [[nodiscard]] bool written_as_list(const std::string& name) const { return lists_.count(name) != 0; }
  void mark_written_as_list(const std::string& name) { lists_.insert(name); }
  /// Where the value was written (unknown for defaults); for error messages of plugins.
  [[nodiscard]] SourceLocation where(const std::string& name) const;
  /// The context of this block, e.g. "[materials.soil]", for messages.
  std::string context;
  /// The parameters read so far through real(), integer(), flag(), text() or real_list() (has()
  /// and where() do not count). A parameter a factory declares but never reads when a scene sets
  /// it would be silently ignored: tests/test_params_read.cpp holds every factory to reading all.
  /// Not synchronized: read parameters where the object is created, not in parallel updates.
  [[nodiscard]] const std::set<std::string>& read_names() const { return read_; }

private:
  const ParamValue& get(const std::string& name) const;
  std::map<std::string, std::pair<ParamValue, SourceLocation>> values_;
  std::set<std::string> lists_;
  mutable std::set<std::string> read_;
};

} // namespace stratum
