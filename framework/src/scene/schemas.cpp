#include "scene/schemas.hpp"

#include "stratum/linear_solver.hpp"
#include "stratum/solver.hpp"
#include "stratum/step_control.hpp"
#include "stratum/units.hpp"

#include <string>
#include <vector>

namespace stratum::scene {

TableKeys top_keys() {
  TableKeys k;
  k.schema.text("title", {}, "a title for the scene (printed nowhere else; for the reader of the file)")
      .defaults_to(std::string());
  k.other = {
      {"include", "string or list of strings",
       "scene files merged in first, relative to this file (stratum describe include)"},
      {"units", "table", "[units]"},
      {"analysis", "table", "[analysis]"},
      {"convergence", "table", "[convergence]"},
      {"solver", "table", "[solver]"},
      {"mesh", "table", "[mesh] (required)"},
      {"materials", "table of tables", "[materials.<name>]"},
      {"domains", "array of tables", "[[domains]] (at least one)"},
      {"constraints", "array of tables", "[[constraints]]"},
      {"loads", "array of tables", "[[loads]] (a scene without stages)"},
      {"stages", "array of tables", "[[stages]]"},
      {"output", "table", "[output]"},
      {"plugins", "table", "[plugins]"},
      {"contact_laws", "table of tables", "[contact_laws.<name>]"},
      {"interfaces", "array of tables", "[[interfaces]]"},
      {"checks", "array of tables", "[[checks]]"},
  };
  return k;
}

Schema units_schema() {
  Schema s;
  std::vector<std::string> force, length;
  for (auto u : Units::force_units()) force.emplace_back(u);
  for (auto u : Units::length_units()) length.emplace_back(u);
  s.text("force", force,
         "force unit of every value the scene writes and every label it gets (loads, reactions, "
         "axial forces); the scene's numbers are not converted, they are read in these units")
      .defaults_to(std::string("kN"));
  s.text("length", length,
         "length unit (coordinates, displacements, mesh sizes); stress is force/length^2 (N, mm: MPa; "
         "kN, m: kPa; N, m: Pa); settlements and slips in tables are in mm when length = \"m\", "
         "otherwise in the length unit")
      .defaults_to(std::string("m"));
  std::vector<std::string> time;
  for (auto u : Units::time_units()) time.emplace_back(u);
  s.text("time", time,
         "time unit of consolidation: stage durations, permeability (length/time), the analysis time "
         "of consolidation stages")
      .defaults_to(std::string("s"));
  s.text("stress", {},
         "optional: the stress unit as a check of what force/length^2 gives (kPa, Pa, MPa, GPa, or "
         "e.g. \"N/mm2\"); plugins' defaults (p_a = 100 kPa, gamma_w = 9.81 kN/m3) are converted "
         "into the scene's units, and a plugin that cannot follow them refuses the scene")
      .defaults_to(std::string("(derived)"));
  return s;
}

Schema analysis_schema() {
  Schema s;
  s.text("formulation", {"axisymmetric", "plane_strain"}, "2D idealisation of the whole scene")
      .defaults_to(std::string("axisymmetric"));
  s.text("solver", {}, "solver plugin that solves each load step; its parameters go in [solver]")
      .defaults_to(std::string("newton"));
  s.text("linear_solver", linear_solver_names(), "sparse direct solver; auto = by size and symmetry")
      .defaults_to(std::string("auto"));
  s.boolean("reuse_linear_stiffness",
            "compute the stiffness of cells with a linear material once per stage (false: at every "
            "assembly; the results are the same, for measuring what the reuse saves)")
      .defaults_to(true);
  s.boolean("reuse_symbolic",
            "analyze the sparsity pattern of the stage's matrix once and reuse it in every "
            "factorization (false: analyze before each one; the results are the same, for measuring "
            "what the reuse saves)")
      .defaults_to(true);
  s.integer("threads", "-",
            "threads that evaluate the elements and materials (0 = all of the machine's; the results "
            "are the same for any count)")
      .at_least(0)
      .at_most(256)
      .defaults_to(0LL);
  s.integer("steps", "-", "number of equal load increments from load factor 0 to 1")
      .at_least(1)
      .defaults_to(1LL);
  s.integer("max_cutbacks", "-", "how many times a failed step may be halved before the run stops")
      .at_least(0)
      .at_most(30)
      .defaults_to(4LL);
  // Step control (stratum/step_control.hpp).
  StepSettings d;
  s.real_list("increments", "-", "explicit load-factor increments (the last one repeats); replaces steps")
      .defaults_to(std::vector<double>{});
  s.boolean("automatic", "grow the increment after fast convergence").defaults_to(false);
  s.integer("fast_iterations", "-", "a step converged in at most this many iterations counts as fast")
      .at_least(1)
      .defaults_to(static_cast<long long>(d.fast_iterations));
  s.real("growth", "-", "increment (arc length) factor after a fast step").at_least(1).defaults_to(d.growth);
  s.real("max_increment", "-", "largest grown load increment; 0: the whole range")
      .at_least(0)
      .defaults_to(0.0);
  s.real("arc_length", "-", "path-following solvers: first step size; 0: from the first increment")
      .at_least(0)
      .defaults_to(0.0);
  s.real("max_arc_length", "-", "path-following solvers: largest grown step size; 0: unbounded")
      .at_least(0)
      .defaults_to(0.0);
  s.real("error_tolerance", "-",
         "load control: largest local error estimate of the materials' updates per step (relative "
         "stress, Material::step_error); a step above it is repeated smaller, and the next step is "
         "sized from it, never beyond the listed increments; 0: off (steps as listed)")
      .at_least(0)
      .defaults_to(0.0);
  s.integer("max_steps", "-", "accepted steps at most (path following stops there, load control fails)")
      .at_least(1)
      .defaults_to(static_cast<long long>(d.max_steps));
  return s;
}

Schema convergence_schema() {
  Schema s;
  Convergence c;
  s.real("force_rtol", "-", "residual force relative to the force scale")
      .greater_than(0)
      .defaults_to(c.force_rtol);
  s.real("force_atol", "kN", "absolute residual force bound").at_least(0).defaults_to(c.force_atol);
  s.real("disp_rtol", "-", "displacement correction relative to the step's displacement")
      .at_least(0)
      .defaults_to(c.disp_rtol);
  s.real("disp_atol", "m", "absolute displacement correction bound").at_least(0).defaults_to(c.disp_atol);
  s.real("energy_rtol", "-", "energy criterion (4.21) of the thesis; 0 disables it")
      .at_least(0)
      .defaults_to(0.0);
  s.real("energy_atol", "kN m", "absolute bound of the energy criterion").at_least(0).defaults_to(0.0);
  s.boolean("displacement_test", "also require the displacement-correction test").defaults_to(false);
  s.integer("max_iterations", "-", "iterations per step before it counts as failed")
      .at_least(1)
      .defaults_to(static_cast<long long>(c.max_iterations));
  return s;
}

std::vector<std::string_view> TableKeys::other_names() const {
  std::vector<std::string_view> v;
  for (const auto& k : other) v.emplace_back(k.name);
  return v;
}

std::vector<std::string_view> key_names(const Schema& schema) {
  std::vector<std::string_view> v;
  for (const auto& p : schema.specs()) v.emplace_back(p.name);
  return v;
}

TableKeys mesh_keys() {
  TableKeys k;
  Schema& s = k.schema;
  s.text("generator", {},
         "blocks (structured graded blocks), gmsh (a Gmsh file), or a mesh generator: axisymmetric_pile "
         "(the bored pile, [mesh.pile]) or a plugin's (its parameters in [mesh.<generator>])");
  s.text("file", {}, "Gmsh .msh 4.1 ASCII file, relative to the scene file").defaults_to(std::string());
  s.integer("nodes_per_cell", "-", "4 (bilinear) or 8 (serendipity) for generated blocks")
      .at_least(4)
      .at_most(8)
      .defaults_to(8LL);
  s.text("transform", {"none", "polar"},
         "polar maps generated (x, y) to (x cos y, x sin y) with y in degrees: rings and sectors")
      .defaults_to(std::string("none"));
  k.other.push_back({"blocks", "array of tables", "generator = \"blocks\": the blocks, [[mesh.blocks]]"});
  k.other.push_back(
      {"<generator>", "table",
       "a mesh generator's parameters, [mesh.<generator>] ([mesh.pile] for axisymmetric_pile)"});
  return k;
}

Schema block_schema() {
  Schema s;
  s.text("name", {}, "cell set name of the block; its edges become <name>.left/right/bottom/top");
  s.real_list("x", "m", "[x0, x1] extent (axisymmetric: radius)");
  s.real_list("y", "m", "[y0, y1] extent (axisymmetric: height)");
  s.integer("nx", "-", "cells along x").at_least(1).defaults_to(1LL);
  s.integer("ny", "-", "cells along y").at_least(1).defaults_to(1LL);
  s.real("grade_x", "-", "last/first cell size along x").greater_than(0).defaults_to(1.0);
  s.real("grade_y", "-", "last/first cell size along y").greater_than(0).defaults_to(1.0);
  return s;
}

TableKeys output_keys() {
  TableKeys k;
  Schema& s = k.schema;
  s.boolean("vtk", "write .vtu/.pvd files").defaults_to(true);
  s.boolean("integration_points", "write the integration-point cloud (.vtp)").defaults_to(true);
  s.integer("every", "-", "write every n-th step (the last step is always written)")
      .at_least(1)
      .defaults_to(1LL);
  s.text("pile_cells", {}, "cell set of the pile: curves/axial_force.csv").defaults_to(std::string());
  s.real("tables_every", "s (wall clock)",
         "diagnostics.csv and the curves are rewritten (atomically) at every stage's end and at most "
         "this often during a stage, so that they grow while a long run goes on; 0: after every step")
      .at_least(0)
      .defaults_to(5.0);
  k.other.push_back({"history", "array of tables", "recorders, [[output.history]]"});
  return k;
}

TableKeys plugins_keys() {
  TableKeys k;
  k.other.push_back({"path", "list of strings",
                     "folders searched for plugin libraries before STRATUM_PLUGIN_PATH and the program's "
                     "own plugin folder, relative to the scene file"});
  return k;
}

Schema constraint_schema() {
  Schema s;
  s.text("nodes", {}, "node or edge set whose nodes are fixed or moved");
  s.real("ux", "m", "prescribed x (radial) displacement at load factor 1; left out: the component is free")
      .defaults_to_computed(0.0, "free (not prescribed)");
  s.real("uy", "m", "prescribed y (vertical) displacement at load factor 1; left out: the component is free")
      .defaults_to_computed(0.0, "free (not prescribed)");
  s.text("field", {},
         "another unknown the domains' elements declare, by name (e.g. p, a pore pressure; `stratum check` "
         "lists the scene's fields), prescribed to `value`")
      .defaults_to(std::string());
  s.real("value", "-", "prescribed value of `field`, in that field's unit in the scene's [units]")
      .defaults_to(0.0);
  return s;
}

Schema domain_schema() {
  Schema s;
  s.text("cells", {}, "cell set of the domain; every cell of the mesh belongs to exactly one domain");
  s.text("element", {}, "element plugin (stratum plugins: kind element); its parameters go in this table");
  s.text("material", {},
         "name of a [materials.<name>] table (required unless the element takes none, e.g. an element of a "
         "scalar field with its own conductivity)")
      .defaults_to(std::string());
  s.text("drainage", {"drained", "undrained", "undrained_total", "non_porous"},
         "the pore water of a displacement domain (docs/groundwater.md): drained (none acts), undrained "
         "(effective-stress parameters, the pore fluid's stiffness `fluid_stiffness` added, an excess pore "
         "pressure per point), undrained_total (total-stress parameters, e.g. c = s_u: no pore pressure is "
         "computed) or non_porous (concrete, steel); a porous element (quad8p4, tri6p3) models its water "
         "itself and takes drained only")
      .defaults_to(std::string("drained"));
  s.real("fluid_stiffness", "kPa",
         "drainage = undrained: K_w / n, the pore fluid's bulk modulus over the porosity (water: 2.2e6 / n)")
      .greater_than(0)
      .defaults_to_computed(0.0, "required with drainage = \"undrained\"");
  return s;
}

Schema material_schema() {
  Schema s;
  s.text("model", {},
         "material plugin (stratum plugins: kind material); its parameters go in this table "
         "(stratum plugins --describe <model>)");
  return s;
}

Schema contact_law_schema() {
  Schema s;
  s.text("model", {},
         "contact-law plugin (stratum plugins: kind contact_law); its parameters go in this table "
         "(stratum plugins --describe <model>)");
  return s;
}

Schema interface_schema() {
  Schema s;
  s.text("edges", {}, "edge set along which the mesh is split into two sides");
  s.text("element", {},
         "interface element plugin: one whose cells are node pairs (e.g. contact2) or interface lines (e.g. "
         "interface_line); its parameters go in this table");
  s.text("law", {}, "name of a [contact_laws.<name>] table");
  s.text("name", {}, "name of the interface: its cell set, <name>.side1/.side2 node sets, curves file")
      .defaults_to(std::string("<edges>"));
  s.text("cells", {}, "cell set of body 2, whose nodes on the edges are moved to the new side")
      .defaults_to(std::string());
  s.boolean("csv", "write the interface's traction and jump as curves/<name>.csv").defaults_to(true);
  return s;
}

TableKeys stage_keys(long long max_cutbacks, double error_tolerance, bool vtk, long long every) {
  TableKeys k;
  Schema& s = k.schema;
  s.text("name", {}, "stage name (checkpoints and output are named after it)");
  s.text("type", {"static", "consolidation"},
         "static: the stage takes no physical time and nothing flows (porous domains load undrained); "
         "consolidation: the stage lasts `duration` and the pore water flows (its load factor is the "
         "fraction of the duration elapsed, loads grow linearly in time)")
      .defaults_to(std::string("static"));
  s.real("duration", "s", "physical time of a consolidation stage").greater_than(0).defaults_to(1.0);
  s.real("until_excess_pressure", "kPa",
         "consolidation: end the stage (normally, the next stage follows) once the largest excess pore "
         "pressure |p| at any node is below this value; 0: run the whole duration")
      .at_least(0)
      .defaults_to(0.0);
  s.integer("steps", "-", "equal load increments of the stage").at_least(1).defaults_to(1LL);
  s.real_list("increments", "-", "load-factor increments summing to 1 (instead of steps)")
      .defaults_to(std::vector<double>{});
  s.integer("max_cutbacks", "-", "halvings of a failed step before the stage fails (default: [analysis])")
      .at_least(0)
      .at_most(30)
      .defaults_to(max_cutbacks);
  s.real("error_tolerance", "-",
         "error-controlled load steps in this stage ([analysis] error_tolerance: the meaning and "
         "the default); 0: the steps as listed")
      .at_least(0)
      .defaults_to(error_tolerance);
  s.boolean("until_failure", "a step failing after its cut-backs ends the run normally (loading to failure)")
      .defaults_to(false);
  s.real("collapse_stiffness", "-",
         "with until_failure: the stop counts as a collapse when the least current stiffness of the "
         "steps over the last tenth of the load reached (Bergan's parameter: dlambda / (F_ref . du) "
         "under load control) is below this fraction of the stage's first step, or (load control) "
         "when the failed step's last attempt, at its smallest increment, found no equilibrium while "
         "its iterates went further along the load than that stiffness allows (a plateau); "
         "otherwise it is a numerical failure (exit 4)")
      .greater_than(0)
      .at_most(1)
      .defaults_to(0.1);
  s.real("stop_settlement", "m", "stop once the mean settlement of `monitor` exceeds this (0: never)")
      .at_least(0)
      .defaults_to(0.0);
  s.text("monitor", {}, "edge or node set whose mean downward displacement is the settlement")
      .defaults_to(std::string());
  s.boolean("vtk", "write VTK output during this stage (default: [output] vtk)").defaults_to(vtk);
  s.integer("every", "-", "write every n-th step (default: [output] every)").at_least(1).defaults_to(every);
  s.boolean("checkpoint", "write a checkpoint at the end of the stage").defaults_to(true);
  k.other.push_back({"actions", "array of tables", "what the stage does when it starts, [[stages.actions]]"});
  return k;
}

Schema action_schema() {
  Schema s;
  s.text("type", {}, "the stage action (stratum describe stages.actions); its keys go in this table");
  return s;
}

Schema loads_schema() {
  Schema s;
  s.text("type", {"pressure", "force", "gravity"},
         "the load; its keys are those of the stage action of that type (stratum describe stages.actions)");
  return s;
}

TableKeys recorder_keys() {
  TableKeys k;
  Schema& s = k.schema;
  s.text("name", {}, "recorder name: the file history/<name>.csv");
  s.text("kind", {"node", "nodes", "point", "global", "interface"},
         "one node at `at`, a node or edge `set` (mean displacement, summed reaction), the "
         "integration point nearest to `at`, global quantities, or the points of an interface "
         "(traction and jump along it, one row per point)");
  s.text("set", {},
         "nodes: the node or edge set; interface: the [[interfaces]] name (by default its edge set's)")
      .defaults_to(std::string());
  s.real_list("at", "m", "node, point: the location [x, y]").defaults_to(std::vector<double>{});
  k.other.push_back({"quantities", "list of strings", "the columns to record (default: all of the kind's)"});
  return k;
}

Schema check_schema() {
  Schema s;
  s.text("recorder", {}, "name of an [[output.history]] recorder");
  s.text("quantity", {}, "one of the recorder's quantities; its value at the last recorded step is checked");
  s.real("expected", "-", "the expected value (in the quantity's unit), e.g. from a closed form");
  s.real("rtol", "-", "relative tolerance").at_least(0).defaults_to(0.0);
  s.real("atol", "-", "absolute tolerance (the quantity's unit)").at_least(0).defaults_to(0.0);
  return s;
}

} // namespace stratum::scene
