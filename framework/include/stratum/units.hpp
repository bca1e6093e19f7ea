// The unit system of a scene: [units] force and length; stress is force / length^2.
//
// The framework's equations hold in any consistent units, so a scene written in N and mm
// computes in N and mm: nothing is converted on the way in, every value a scene writes is in
// its units. What the framework converts are the numbers that come from elsewhere: the
// defaults of parameters, which plugins and the framework declare in kN, m, kPa (the default
// system) with a unit string ("kPa", "kN/m3", "m", "1/kPa", "-", "deg", ...). The unit string
// is read as a dimension (force^a length^b) and the default is scaled into the scene's units;
// the same string names the unit in the scene's units for labels ("kPa" -> "MPa" in N, mm).
// A plugin whose model holds dimensional numbers it cannot rescale refuses a scene in other
// units (require_default_units). docs/design.md, "Units", explains the whole path.
#pragma once

#include "stratum/params.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace stratum {

/// A unit string read as force^force * length^length times `scale` (the value in kN and m of
/// one of the unit). Angles, "-" and seconds are dimensionless here (nothing converts them).
struct Dimension {
  int force = 0, length = 0, time = 0;
  double scale = 1.0; ///< in kN, m and s
  [[nodiscard]] bool dimensionless() const { return force == 0 && length == 0 && time == 0; }
};

/// The dimension of a unit string such as "kPa", "kN/m3", "kN m", "1/kPa", "kPa/m", "m^2",
/// "N/mm2", "-", "deg"; none when the string is not a unit the framework understands.
[[nodiscard]] std::optional<Dimension> parse_unit(std::string_view unit);

class Units {
public:
  /// kN, m (stress kPa): the framework's default system, the one plugins declare defaults in.
  Units() = default;
  /// Throws Error (without a location; the reader adds it) for a unit not allowed.
  Units(std::string force, std::string length, std::string time = "s");

  [[nodiscard]] static const std::vector<std::string_view>& force_units();  ///< N, kN, MN
  [[nodiscard]] static const std::vector<std::string_view>& length_units(); ///< mm, cm, m
  [[nodiscard]] static const std::vector<std::string_view>& time_units();   ///< s, min, h, day

  [[nodiscard]] const std::string& force() const { return force_; }
  [[nodiscard]] const std::string& length() const { return length_; }
  /// The time unit of consolidation (durations, permeability in length/time): s by default.
  [[nodiscard]] const std::string& time() const { return time_; }
  /// The stress unit: kPa, Pa, MPa, GPa, or force/length2 where there is no name (kN/cm2).
  [[nodiscard]] std::string stress() const;
  /// kN, m: true for every scene without [units].
  [[nodiscard]] bool is_default() const { return force_ == "kN" && length_ == "m" && time_ == "s"; }
  /// "N, mm, MPa": for messages and the VTK field data.
  [[nodiscard]] std::string describe() const;

  /// The factor that turns a value written in `unit` (a unit string of the default system, as
  /// plugins declare them) into this system; none when the unit string is not understood.
  [[nodiscard]] std::optional<double> factor(std::string_view unit) const;
  /// `unit` spelt in this system: "kPa" -> "MPa", "kN/m3" -> "N/mm3", "1/kPa" -> "1/MPa";
  /// dimensionless units and strings not understood are returned as they are.
  [[nodiscard]] std::string label(std::string_view unit) const;

  /// A CSV column or field-data name: `name`_`unit` with the unit spelt in this system
  /// ("load", "kN" -> load_N in N, mm); '/' becomes "_per_" (kN/cm2 -> kN_per_cm2).
  [[nodiscard]] std::string column(std::string_view name, std::string_view unit) const;

  /// Settlements, slips and other small displacements in tables: mm when the length unit is m
  /// (x 1000, as the thesis tabulates them), otherwise in the length unit itself (mm stays mm,
  /// cm stays cm). The unit and the factor from the length unit.
  [[nodiscard]] std::string small_length() const { return length_ == "m" ? "mm" : length_; }
  [[nodiscard]] double small_length_factor() const { return length_ == "m" ? 1e3 : 1.0; }

  /// kN per force unit and m per length unit (N: 1e-3; mm: 1e-3).
  [[nodiscard]] double force_in_kN() const;
  [[nodiscard]] double length_in_m() const;
  [[nodiscard]] double time_in_s() const;

  /// The same force and length (where they were declared does not count).
  [[nodiscard]] bool operator==(const Units& o) const {
    return force_ == o.force_ && length_ == o.length_ && time_ == o.time_;
  }

  /// Where the scene declares them ([units] force), for messages; unknown for the default.
  SourceLocation declared_at;

private:
  std::string force_ = "kN", length_ = "m", time_ = "s";
};

/// A "-1: none" default: a negative number that is also the parameter's lower bound (tension = -1,
/// c_A = -1: "computed"). It is a flag, not a quantity: it and that bound are never converted.
[[nodiscard]] bool is_sentinel_default(const ParamSpec& spec);

/// A parameter's declaration as a scene in `units` sees it: its unit spelt in them, its default
/// and range bounds converted (a default that cannot be converted keeps its number, and the unit
/// then reads "<unit> (kN, m, kPa)"). For `stratum plugins --describe NAME --scene FILE`.
[[nodiscard]] ParamSpec spec_in_units(const ParamSpec& spec, const Units& units);

/// The [units] of a scene file (and its includes), checked as `stratum run` checks them; kN, m
/// when it declares none. Throws a located Error for a bad [units] table.
[[nodiscard]] Units scene_units(const std::string& scene_path);

/// The name under which the framework hands a plugin the scene's units among its Params: the
/// text "force length" (e.g. "N mm"), located at the scene's [units] table when it has one.
inline constexpr const char* units_param = "[units]";

/// The scene's units as the framework handed them to a plugin (kN, m when none were handed).
[[nodiscard]] Units units_of(const Params& p);

/// For a plugin whose model holds dimensional numbers that no parameter declares (compiled
/// constants, tables in kPa): throws a located Error when the scene's units are not kN, m, kPa,
/// saying `why`. Call it in the factory's create.
void require_default_units(const Params& p, const std::string& why);

} // namespace stratum
