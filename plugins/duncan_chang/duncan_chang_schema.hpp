// The parameter schema of the hyperbolic family (duncan_chang, variable_kg) and its reading into
// duncan_chang::Constants, with the checks that need more than one parameter.
#pragma once

#include "duncan_chang.hpp"

#include "stratum/error.hpp"
#include "stratum/params.hpp"

#include <string>
#include <vector>

namespace stratum::duncan_chang {

/// Which factory the schema is for.
enum class Family { duncan_chang, variable_kg };

/// Whether a level-dependent parameter belongs to a family's schema.
inline bool uses(Family fam, const SetParameter& sp) {
  if (fam == Family::variable_kg) return sp.needs == Needs::all || sp.needs == Needs::K_G;
  return sp.needs != Needs::K_G;
}
/// Whether a form needs a level-dependent parameter.
inline bool needs(Form form, const SetParameter& sp) {
  return sp.needs == Needs::all || (sp.needs == Needs::E_nu && form == Form::E_nu) ||
         (sp.needs == Needs::E_B && form == Form::E_B) || (sp.needs == Needs::K_G && form == Form::K_G);
}

inline void declare(Schema& s, Family fam) {
  const std::string list = " (a number, or a list with one value per sigma3_levels entry)";
  if (fam == Family::duncan_chang) {
    s.text("form", {"E_nu", "E_B"},
           "E_nu: E_t (2.31) and nu_t (2.35); E_B: E_t (2.31) and the bulk modulus B_t (2.36), nu_t (2.39)")
        .defaults_to(std::string("E_nu"));
    s.text("update", {"recovery", "incremental", "explicit"},
           "recovery: the author's stress from total strain (4.46)-(4.49) while loading; incremental: "
           "substepped tangent integration; explicit: one forward-Euler step with the moduli of the "
           "step's start (the classical load-step method)")
        .defaults_to(std::string("incremental"));
    s.text("branch", {"increment", "step_start"},
           "explicit update: increment = E_ur when the increment's E_ur trial stays below the criterion's "
           "maximum (split where it crosses it); step_start = E_ur when the step's start state is below "
           "its maximum, else E_t, for every iterate of the step (the classical load-step rule)")
        .defaults_to(std::string("increment"));
    s.text("branch_iteration", {"free", "consistent"},
           "explicit update, branch = increment: free = every evaluation decides E_ur / split / E_t "
           "from its own increment (the original iteration); consistent = each point decides at the "
           "step's first evaluation and keeps that branch while the solver iterates, the solver "
           "re-checks every decision at convergence and solves again where one changed (needs a "
           "solver that renews decisions: newton); the converged states are the same rule's")
        .defaults_to(std::string("free"));
  }
  s.text("unloading", {"F_sr", "max_deviator"},
         "unload/reload with E_ur when the stress level F_sr (4.50) or the deviator is below its maximum so "
         "far")
      .defaults_to(std::string("F_sr"));
  for (const SetParameter& sp : set_parameters) {
    if (!uses(fam, sp)) continue;
    ParamSpec& spec = s.real_list(sp.name, sp.unit, sp.meaning + list);
    if (sp.lower > -unbounded) sp.lower_open ? spec.greater_than(sp.lower) : spec.at_least(sp.lower);
    if (sp.upper < unbounded) sp.upper_open ? spec.less_than(sp.upper) : spec.at_most(sp.upper);
    if (sp.fallback == Fallback::none) spec.defaults_to(std::vector<double>{});
    if (sp.fallback == Fallback::zero) spec.defaults_to(std::vector<double>{0.0});
  }
  const std::vector<double> none;
  s.real_list("sigma3_levels", "kPa",
              "sigma_3 of the parameter sets, increasing; below the first the first set, above the last "
              "the last, linear interpolation of every parameter in sigma_3 in between")
      .greater_than(0.0)
      .defaults_to(none);
  s.real("p_a", "kPa", "atmospheric pressure").greater_than(0.0).defaults_to(100.0);
  if (fam == Family::duncan_chang) {
    s.text("bulk_stress", {"sigma_m", "sigma_3"},
           "the stress of B_t (2.36): sigma_m as printed in the thesis, or sigma_3 (Duncan et al. 1980)")
        .defaults_to(std::string("sigma_m"));
    s.real("nu_max", "-", "upper bound of nu_t").greater_than(0.0).less_than(0.5).defaults_to(0.49);
    s.real("nu_min", "-", "lower bound of nu_t").at_least(0.0).less_than(0.5).defaults_to(0.0);
  }
  s.real("sigma3_floor", "-", "smallest sigma_3 used in the moduli and strength, as a fraction of p_a")
      .greater_than(0.0)
      .defaults_to(0.01);
  s.real("tangent_stabilization", "kPa",
         "isotropic modulus added to the iteration matrix only (not to the stress); 0: the exact tangent")
      .at_least(0)
      .defaults_to(0.0);
  s.real("residual", "-", "E_t/E_i at and beyond failure (stress level F_sr >= 1), and the floor of E_t")
      .greater_than(0.0)
      .less_than(1.0)
      .defaults_to(1e-3);
  s.boolean("tension_cutoff", "set tensile principal stresses to zero after each substep").defaults_to(true);
  s.real("max_substep_strain", "-", "incremental update: largest strain component change per substep")
      .greater_than(0.0)
      .defaults_to(1e-4);
  s.integer("max_substeps", "-",
            "incremental update: most substeps per increment; a larger strain increment (a wild iterate or "
            "too large a load step) fails, so the step is cut back instead of integrated at great cost")
      .at_least(1)
      .at_most(100000)
      .defaults_to(1000LL);
  if (fam == Family::duncan_chang) {
    s.real("recovery_min_strain", "-",
           "recovery: the major compressive strain below which the step is integrated incrementally")
        .greater_than(0.0)
        .defaults_to(1e-6);
    s.text("recovery_origin", {"initial_stress", "zero"},
           "recovery: total strains count from the strain of a CID path to the initial stress "
           "(initial_stress; none for an isotropic one) or from zero (zero, the thesis as printed)")
        .defaults_to(std::string("initial_stress"));
  }
}

/// Reads validated Params into Constants; throws Error (with the location) on inconsistent input.
inline Constants read(const Params& p, Family fam) {
  const std::string prefix = p.context.empty() ? std::string() : p.context + " ";
  auto fail = [&](const std::string& name, const std::string& msg) {
    throw Error(p.where(name), prefix + msg);
  };
  Constants c;
  if (fam == Family::duncan_chang) {
    c.form = p.text("form") == "E_B" ? Form::E_B : Form::E_nu;
    const std::string up = p.text("update");
    c.update = up == "recovery"   ? Update::recovery
               : up == "explicit" ? Update::explicit_step
                                  : Update::incremental;
    c.branch = p.text("branch") == "step_start" ? Branch::step_start : Branch::increment;
    c.keep_decisions = p.text("branch_iteration") == "consistent";
    c.bulk_stress = p.text("bulk_stress") == "sigma_3" ? BulkStress::sigma_3 : BulkStress::sigma_m;
    c.nu_max = p.real("nu_max");
    c.nu_min = p.real("nu_min");
    c.recovery_min_strain = p.real("recovery_min_strain");
    c.origin_at_initial_stress = p.text("recovery_origin") == "initial_stress";
    if (c.nu_min > c.nu_max) fail("nu_min", "nu_min must not exceed nu_max");
  } else {
    c.form = Form::K_G;
  }
  c.unloading = p.text("unloading") == "max_deviator" ? Unloading::max_deviator : Unloading::F_sr;
  c.p_a = p.real("p_a");
  c.sigma3_floor = p.real("sigma3_floor");
  c.residual = p.real("residual");
  c.tangent_stabilization = p.real("tangent_stabilization");
  c.tension_cutoff = p.flag("tension_cutoff");
  c.max_substep_strain = p.real("max_substep_strain");
  c.max_substeps = static_cast<int>(p.integer("max_substeps"));
  c.levels = p.real_list("sigma3_levels");

  // Which parameters this form needs: those of every form first, then the form's own.
  std::vector<std::string> needed;
  for (const Needs group : {Needs::all, Needs::E_nu, Needs::E_B, Needs::K_G})
    for (const SetParameter& sp : set_parameters)
      if (sp.needs == group && needs(c.form, sp)) needed.emplace_back(sp.name);
  std::size_t N = 1;
  std::string longest;
  for (const auto& name : needed) {
    const auto& v = p.real_list(name);
    if (v.empty()) {
      if (fam == Family::variable_kg) fail(name, name + " must not be an empty list");
      fail(p.where(name).known() ? name : std::string("form"),
           name + " is required for form = \"" + (c.form == Form::E_nu ? "E_nu" : "E_B") + "\"");
    }
    if (v.size() > 1 && N == 1)
      N = v.size(), longest = name;
    else if (v.size() > 1 && v.size() != N)
      fail(name, name + " has " + std::to_string(v.size()) + " values but " + longest + " has " +
                     std::to_string(N) + "; every list must have one value per sigma3_levels entry");
  }
  for (const Needs group : {Needs::E_nu, Needs::E_B})
    for (const SetParameter& sp : set_parameters)
      if (sp.needs == group && fam == Family::duncan_chang && !needs(c.form, sp) &&
          !p.real_list(sp.name).empty()) {
        const std::string form = group == Needs::E_nu ? "E_nu" : "E_B";
        fail(sp.name, std::string(sp.name) + " belongs to form = \"" + form +
                          "\"; remove it or set form = \"" + form + "\"");
      }
  // A list of one value is a list (README: a number applies to every level, a list gives one
  // value per level): K = [500.0] beside two levels is an error, not a broadcast.
  if (N > 1)
    for (const auto& name : needed)
      if (p.written_as_list(name) && p.real_list(name).size() == 1)
        fail(name, name + " is a list of 1 value but " + longest + " has " + std::to_string(N) +
                       "; give one value per sigma3_levels entry, or write it as a plain number (no "
                       "brackets) to use it for every level");
  if (N > 1 && c.levels.size() != N)
    fail(c.levels.empty() ? longest : "sigma3_levels",
         longest + " has " + std::to_string(N) + " values, so sigma3_levels must list " + std::to_string(N) +
             " increasing sigma_3 values (kPa), one per set");
  if (N == 1 && !c.levels.empty())
    fail("sigma3_levels", "sigma3_levels is given but no parameter is a list; give lists with one value per "
                          "level or remove sigma3_levels");
  for (std::size_t i = 1; i < c.levels.size(); ++i)
    if (!(c.levels[i] > c.levels[i - 1])) fail("sigma3_levels", "sigma3_levels must be strictly increasing");
  c.sets.assign(N, Set{});
  for (const SetParameter& sp : set_parameters) {
    if (!uses(fam, sp)) continue;
    const auto& v = p.real_list(sp.name);
    if (v.empty()) continue;
    for (std::size_t i = 0; i < N; ++i) c.sets[i].*sp.member = v.size() == 1 ? v[0] : v[i];
  }
  if (c.branch == Branch::step_start && c.update != Update::explicit_step)
    fail("branch", "branch = \"step_start\" belongs to update = \"explicit\" (one step per increment); the "
                   "substepped updates decide the branch per substep");
  if (c.keep_decisions && c.update != Update::explicit_step)
    fail("branch_iteration", "branch_iteration = \"consistent\" belongs to update = \"explicit\" (one "
                             "step per increment)");
  if (c.keep_decisions && c.branch != Branch::increment)
    fail("branch_iteration", "branch_iteration = \"consistent\" needs branch = \"increment\" (with "
                             "step_start the branch does not depend on the increment)");
  if (c.update == Update::recovery) {
    if (c.form != Form::E_nu)
      fail("update", "update = \"recovery\" needs form = \"E_nu\": the recovery (4.49) inverts the "
                     "lateral-strain law (2.32) of that form");
    for (const auto& s : c.sets)
      if (!(s.F > 0.0))
        fail("F",
             "update = \"recovery\" needs F > 0: sigma_3 is recovered from nu_i = G - F log10(sigma_3/p_a)");
  }
  return c;
}

} // namespace stratum::duncan_chang
