#include "scene/schemas.hpp"

#include "stratum/linear_solver.hpp"
#include "stratum/solver.hpp"
#include "stratum/step_control.hpp"

#include <string>
#include <vector>

namespace stratum::scene {

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

Schema mesh_schema() {
  Schema s;
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
  return s;
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

Schema output_schema() {
  Schema s;
  s.boolean("vtk", "write .vtu/.pvd files").defaults_to(true);
  s.boolean("integration_points", "write the integration-point cloud (.vtp)").defaults_to(true);
  s.integer("every", "-", "write every n-th step (the last step is always written)")
      .at_least(1)
      .defaults_to(1LL);
  s.text("pile_head", {}, "edge set of the loaded pile head: curves/load_settlement.csv")
      .defaults_to(std::string());
  s.text("pile_cells", {}, "cell set of the pile: curves/axial_force.csv").defaults_to(std::string());
  s.real("tables_every", "s",
         "diagnostics.csv and the curves are rewritten (atomically) at every stage's end and at most "
         "this often during a stage, so that they grow while a long run goes on; 0: after every step")
      .at_least(0)
      .defaults_to(5.0);
  return s;
}

} // namespace stratum::scene
