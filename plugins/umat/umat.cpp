// Plugin entry point of the "umat" material: the schema, the checks of the scene's values and
// the loading of the user's library (at `stratum check` time, so a missing library or symbol
// is a located error before anything runs). The material itself: umat_material.hpp.
#include "umat_material.hpp"

#include "stratum/plugin.hpp"
#include "stratum/units.hpp"

#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using stratum::Error;
using stratum::Params;
namespace um = stratum::umat;

/// Names separated by commas and/or blanks.
std::vector<std::string> split_names(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == ',' || c == ' ' || c == '\t') {
      if (!cur.empty()) out.push_back(cur), cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

/// "soil" from "[materials.soil]", "material" from "[material]".
std::string material_name(const std::string& context) {
  std::string s = context;
  if (!s.empty() && s.front() == '[') s.erase(0, 1);
  if (!s.empty() && s.back() == ']') s.pop_back();
  if (const auto dot = s.rfind('.'); dot != std::string::npos) s.erase(0, dot + 1);
  return s.empty() ? std::string("umat") : s;
}

std::unique_ptr<stratum::Material> create(const Params& p) {
  const std::string ctx = p.context.empty() ? std::string() : p.context + " ";
  // Compiled code whose constants stratum cannot see (an atmospheric pressure, a tolerance in
  // kPa): in other [units] than kN, m, kPa only when the user vouches for it (stratum/units.hpp).
  if (!p.flag("any_units"))
    stratum::require_default_units(
        p, "a UMAT is compiled code whose constants stratum cannot convert (set "
           "any_units = true when every dimensional constant of it comes from props)");
  um::Settings s;
  s.name = material_name(p.context);
  s.props = p.real_list("props");
  s.nstatv = static_cast<int>(p.integer("nstatv"));
  s.celent = p.real("celent");
  s.stage_time = p.real("stage_time");
  s.nstatv_at = p.where("nstatv").str();
  s.props_at = p.where("props").str();
  s.symmetric = p.flag("symmetric_tangent");
  s.thread_safe = p.flag("thread_safe");

  s.ntens = static_cast<int>(p.integer("ntens"));
  if (s.ntens != 0 && s.ntens != 4 && s.ntens != 6)
    throw Error(p.where("ntens"),
                ctx + "ntens = " + std::to_string(s.ntens) +
                    " is not allowed; allowed: 0 (automatic), 4 (11, 22, 33, 12) or 6 (3D)");

  s.prop_names = split_names(p.text("prop_names"));
  if (!s.prop_names.empty() && s.prop_names.size() != s.props.size())
    throw Error(p.where("prop_names"), ctx + "prop_names names " + std::to_string(s.prop_names.size()) +
                                           " properties but props has " + std::to_string(s.props.size()) +
                                           "; give one name per entry of props (or none)");

  s.statev = p.real_list("statev");
  if (s.statev.empty()) s.statev.assign(static_cast<std::size_t>(s.nstatv), 0.0);
  if (static_cast<int>(s.statev.size()) != s.nstatv)
    throw Error(p.where("statev"), ctx + "statev has " + std::to_string(s.statev.size()) +
                                       " initial values but nstatv = " + std::to_string(s.nstatv) +
                                       "; give nstatv values (or none for zeros)");

  s.statev_names = split_names(p.text("statev_names"));
  if (s.statev_names.empty())
    for (int i = 1; i <= s.nstatv; ++i) s.statev_names.push_back("statev_" + std::to_string(i));
  if (static_cast<int>(s.statev_names.size()) != s.nstatv)
    throw Error(p.where("statev_names"), ctx + "statev_names names " + std::to_string(s.statev_names.size()) +
                                             " state variables but nstatv = " + std::to_string(s.nstatv) +
                                             "; give one name per state variable (or none)");
  std::set<std::string> seen;
  for (const auto& n : s.statev_names) {
    if (n == "stress" || n == "strain" || n == "plastic" || n.rfind("interface_", 0) == 0)
      throw Error(p.where("statev_names"),
                  ctx + "statev_names: '" + n +
                      "' is the name of a built-in output field; choose another (not stress, strain, "
                      "plastic or interface_*)");
    if (!seen.insert(n).second)
      throw Error(p.where("statev_names"), ctx + "statev_names: '" + n + "' appears twice");
  }

  // The library, relative to the scene file that names it.
  const auto where = p.where("library");
  fs::path lib = p.text("library");
  if (lib.is_relative() && where.known()) lib = fs::path(where.file).parent_path() / lib;
  std::error_code ec;
  if (!fs::is_regular_file(lib, ec))
    throw Error(where, ctx + "library = \"" + p.text("library") + "\": no such file '" + lib.string() +
                           "' (a path relative to the scene file, or absolute)");
  std::shared_ptr<const um::Library> handle;
  try {
    handle = std::make_shared<const um::Library>(lib.string(), p.text("symbol"));
  } catch (const Error& e) {
    throw Error(where, ctx + "library = \"" + p.text("library") + "\": " + e.message());
  }
  return std::make_unique<um::UmatMaterial>(std::move(handle), std::move(s));
}

} // namespace

STRATUM_PLUGIN(registry) {
  stratum::Factory<stratum::Material> f;
  f.name = "umat";
  f.summary = "a user's Abaqus UMAT subroutine from a shared library (Fortran or C), small strains";
  auto& s = f.schema;
  s.text("library", {}, "shared library (.so) with the UMAT; a path relative to the scene file, or absolute");
  s.text("symbol", {}, "name of the UMAT in the library (gfortran: 'umat_'; C: the function's name)")
      .defaults_to(std::string("umat_"));
  s.real_list("props", "-", "PROPS: the material constants, in the order the UMAT reads them")
      .defaults_to(std::vector<double>{});
  s.text("prop_names", {}, "names of the props (commas or blanks between), for messages; one per entry")
      .defaults_to(std::string());
  s.integer("nstatv", "-", "NSTATV: number of state variables").at_least(0).at_most(100000).defaults_to(0LL);
  s.real_list("statev", "-", "initial STATEV of every point (nstatv values; empty: zeros)")
      .defaults_to(std::vector<double>{});
  s.text("statev_names", {}, "output names of the state variables (default statev_1 .. statev_n)")
      .defaults_to(std::string());
  s.integer("ntens", "-",
            "NTENS: 0 automatic (4 when the out-of-plane shears yz, zx are zero, else 6), 4 or 6")
      .at_least(0)
      .at_most(6)
      .defaults_to(0LL);
  s.real("celent", "m",
         "CELENT: 0 passes the cell's characteristic length (sqrt of its area, cbrt of its volume); > 0 "
         "this length at every point")
      .at_least(0.0)
      .defaults_to(0.0);
  s.real(
       "stage_time", "-",
       "the UMAT's time per stage: TIME and DTIME are the pseudo-time (load factor, 1 per stage) times this")
      .greater_than(0.0)
      .defaults_to(1.0);
  s.boolean("symmetric_tangent", "true: the UMAT's DDSDDE is symmetric (Cholesky); false: LU")
      .defaults_to(false);
  s.boolean("thread_safe", "true: the UMAT may run on several threads at once; false: one call at a time")
      .defaults_to(false);
  s.boolean("any_units",
            "true: the UMAT computes in any consistent units (its dimensional constants all come from "
            "props); false: a scene whose [units] are not kN, m, kPa is refused")
      .defaults_to(false);
  f.create = create;
  registry.add(std::move(f));
}
