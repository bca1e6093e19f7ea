// The helpers the in-tree plugins share (plugins/common): each tested on its own here; the
// plugins' tests exercise them in use.
#include "common/contact_history.hpp"
#include "common/material_checks.hpp"
#include "common/solver_steps.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

namespace test_plugin_common {

using namespace stratum;

TEST_CASE("plugin common: a NaN or Inf residual ends the step, a finite one is recorded", "[common]") {
  StepReport rep;
  CHECK(solver_steps::record_residual(rep, 2.5).ok());
  const Outcome o = solver_steps::record_residual(rep, std::numeric_limits<double>::quiet_NaN());
  CHECK(o.status == Status::non_finite);
  REQUIRE(rep.residual_norms.size() == 2);
  CHECK(rep.residual_norms[0] == 2.5);
  CHECK(solver_steps::fail(rep, o).outcome.status == Status::non_finite);
}

TEST_CASE("plugin common: divergence needs two iterations and a residual above factor x max(r0, atol)",
          "[common]") {
  Convergence c;
  c.force_atol = 1.0;
  // r0 = 0.1 < atol: the bound is factor x atol = 10.
  CHECK(solver_steps::divergence("newton", 10.0, c, 1, 1e6, 0.1).ok()); // the first iterations never diverge
  CHECK(solver_steps::divergence("newton", 10.0, c, 2, 9.9, 0.1).ok());
  const Outcome o = solver_steps::divergence("newton", 10.0, c, 2, 10.1, 0.1);
  CHECK(o.status == Status::diverged);
  CHECK(o.message.find("newton diverged: |R| = 10.1 after 2 iterations") == 0);
  // r0 = 5 > atol: the bound is 50.
  CHECK(solver_steps::divergence("newton", 10.0, c, 3, 49.0, 5.0).ok());
  CHECK_FALSE(solver_steps::divergence("newton", 10.0, c, 3, 51.0, 5.0).ok());
}

TEST_CASE("plugin common: the iteration limit is max_iterations", "[common]") {
  Convergence c;
  c.max_iterations = 5;
  CHECK(solver_steps::iteration_limit("newton", c, 4, 1.0, 1.0).ok());
  const Outcome o = solver_steps::iteration_limit("newton", c, 5, 1.0, 1.0);
  CHECK(o.status == Status::not_converged);
}

TEST_CASE("plugin common: a material's input check names the point", "[common]") {
  Vec6 stress = Vec6::Zero();
  const Vec6 strain = Vec6::Zero(), dstrain = Vec6::Zero();
  const MaterialInput in{stress, strain, {}, dstrain, PointContext{7, 2}};
  CHECK(material_checks::finite_input(in, "lade").ok());
  stress[3] = std::numeric_limits<double>::infinity(); // in.stress_n refers to it
  const Outcome o = material_checks::finite_input(in, "lade");
  CHECK(o.status == Status::non_finite);
  CHECK(o.message == "lade: non-finite strain increment or stress at element 7, point 2");
}

TEST_CASE("plugin common: a contact state stored as a number reads back, rounded", "[common]") {
  std::vector<double> h(4, -1.0);
  contact_history::store(h, {1.5, 2.0, static_cast<double>(ContactState::slip)});
  CHECK(h == std::vector<double>{1.5, 2.0, static_cast<double>(ContactState::slip), -1.0});
  CHECK(contact_history::state(h[2]) == ContactState::slip);
  CHECK(contact_history::state(static_cast<double>(ContactState::open) - 0.3) == ContactState::open);
  CHECK(contact_history::state(0.2) == ContactState::stick);
}

} // namespace test_plugin_common
