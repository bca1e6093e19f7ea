// Displacement control for one step of a path-following analysis: the load factor
// is an unknown and the mean displacement of chosen free DOFs (a node set's x or y
// component, or one free unknown) advances by a given increment:
//
//   R(u_n + du, lambda_n + dl) = 0,   c.du = d,   c = (1/n) over the chosen DOFs.
//
// Each iteration solves K ur = R and K uf = F_ref (one factorization) and takes
// the load-factor correction that keeps c.du = d (a bordered system by two solves).
// Where the controlled displacement cannot grow (a snap-back turning point) the
// step does not converge and comes back as a status.
#include "common/solver_steps.hpp"
#include "stratum/model.hpp"
#include "stratum/plugin.hpp"

#include <cmath>

namespace {

using namespace stratum;
using solver_steps::fail;

class DisplacementControl final : public Solver {
public:
  explicit DisplacementControl(const Params& p)
      : p_(p), nodes_(p.text("nodes")), component_(p.text("component") == "x" ? 0 : 1),
        dof_(p.integer("dof")), increment_(p.real("increment")) {
    if (increment_ == 0.0)
      throw Error(p.where("increment"), "displacement_control increment = 0 would never move the controlled "
                                        "displacement; give its change per step (m), its sign the direction");
    if (!nodes_.empty() && p.where("dof").known())
      throw Error(p.where("dof"), "displacement_control: give nodes or dof, not both");
  }

  [[nodiscard]] bool path_following() const override { return true; }

  void check(const SolverCheck& stage) const override {
    const Model& m = stage.model;
    if (!nodes_.empty()) {
      if (!m.mesh.node_sets.count(nodes_)) {
        std::string known;
        for (const auto& [name, set] : m.mesh.node_sets) known += (known.empty() ? "" : ", ") + name;
        throw Error(p_.where("nodes"),
                    "displacement_control nodes = \"" + nodes_ +
                        "\" is not a node set of the mesh; node sets: " + (known.empty() ? "(none)" : known));
      }
      if (m.node_set_free_dofs(nodes_, component_).empty())
        throw Error(p_.where("nodes"), stage.context + ": displacement_control nodes = \"" + nodes_ +
                                           "\" has no free " + (component_ ? "y" : "x") +
                                           " displacement (all held by constraints, or on no active cell)");
      return;
    }
    if (dof_ < 0)
      throw Error(p_.where("increment"),
                  "displacement_control needs nodes = \"<node set>\" (or dof = <index of a free unknown>)");
    if (dof_ >= m.dofs.free_count)
      throw Error(p_.where("dof"), stage.context + ": displacement_control dof = " + std::to_string(dof_) +
                                       " is not a free unknown; allowed: 0 to " +
                                       std::to_string(m.dofs.free_count - 1) +
                                       " (better: nodes = a node set)");
  }

  StepReport solve(NonlinearProblem& problem, const StepRequest& req, Eigen::VectorXd& u) const override {
    StepReport rep;
    const Convergence& c = req.convergence;
    std::vector<Eigen::Index> dofs;
    if (!nodes_.empty()) {
      dofs = problem.node_set_dofs(nodes_, component_);
      if (dofs.empty())
        return fail(rep, {Status::singular, "displacement control: node set '" + nodes_ +
                                                "' has no free DOF in that component (or is unknown)"});
    } else if (dof_ >= 0 && dof_ < problem.size()) {
      dofs.push_back(static_cast<Eigen::Index>(dof_));
    } else {
      return fail(rep, {Status::singular, "displacement control: give nodes (a node set) or a valid dof"});
    }
    const double w = 1.0 / static_cast<double>(dofs.size());
    auto mean = [&](const Eigen::VectorXd& v) {
      double m = 0;
      for (auto d : dofs) m += v[d];
      return w * m;
    };
    const double target = req.arc_length > 0 ? (increment_ >= 0 ? 1.0 : -1.0) * req.arc_length : increment_;
    rep.arc_length = std::abs(target);
    const Eigen::VectorXd& f = problem.reference_load();
    LinearSolver& ls = problem.linear_solver();
    SparseMatrix k = problem.make_tangent();
    const Eigen::VectorXd u_n = u;
    Eigen::VectorXd r, uf, ur, ddu;
    if (auto o = problem.evaluate(u, req.lambda_n, r, &k); !o.ok()) return fail(rep, o);
    if (auto o = step(ls, k, f, uf, rep); !o.ok()) return fail(rep, o);
    const double cf0 = mean(uf);
    if (!(std::abs(cf0) > 0) || !std::isfinite(cf0))
      return fail(rep,
                  {Status::singular, "displacement control: the controlled DOFs do not move under the load"});
    double dl = target / cf0;
    Eigen::VectorXd du = dl * uf;
    double r0 = -1.0, e0 = -1.0;
    for (int it = 0;; ++it) {
      const double lambda = req.lambda_n + dl;
      u = u_n + du;
      if (auto o = problem.evaluate(u, lambda, r, &k); !o.ok()) return fail(rep, o);
      const double rn = r.norm();
      if (auto o = solver_steps::record_residual(rep, rn); !o.ok()) return fail(rep, o);
      const auto chk = solver_steps::check(c, it, rn, problem.force_scale(lambda), ddu, r, du.norm(), e0);
      if (chk.converged()) {
        rep.lambda = lambda;
        rep.arc_length = std::abs(mean(du));
        return rep;
      }
      if (r0 < 0) r0 = std::max(rn, c.force_atol);
      if (auto o =
              solver_steps::iteration_limit_at("displacement control", c, it, rn, lambda,
                                               " (beyond a turning point of the controlled displacement?)");
          !o.ok())
        return fail(rep, o);
      if (it > 1 && rn > 1e6 * r0) return fail(rep, {Status::diverged, "displacement control diverged"});
      if (auto o = step(ls, k, f, uf, rep); !o.ok()) return fail(rep, o);
      ++rep.solves;
      if (auto o = ls.solve(r, ur); !o.ok()) return fail(rep, o);
      ++rep.iterations;
      const double cf = mean(uf);
      if (!(std::abs(cf) > 0) || !std::isfinite(cf))
        return fail(rep, {Status::singular, "displacement control: c.K^-1 F vanished"});
      // Keep c.du = target: c.(du + ur + dlam uf) = target.
      const double dlam = (target - mean(du) - mean(ur)) / cf;
      ddu = ur + dlam * uf;
      if (e0 < 0) e0 = std::abs(ddu.dot(r));
      du += ddu;
      dl += dlam;
    }
  }

private:
  static Outcome step(LinearSolver& ls, const SparseMatrix& k, const Eigen::VectorXd& f, Eigen::VectorXd& uf,
                      StepReport& rep) {
    ++rep.factorizations;
    if (auto o = ls.factorize(k); !o.ok()) return o;
    ++rep.solves;
    return ls.solve(f, uf);
  }
  Params p_; ///< for the locations of check()'s messages
  std::string nodes_;
  int component_;
  long long dof_;
  double increment_;
};

} // namespace

STRATUM_PLUGIN(registry) {
  Schema s;
  s.text("nodes", {}, "node set whose mean displacement is controlled (empty: use dof)")
      .defaults_to(std::string());
  s.text("component", {"x", "y"}, "controlled component of the node set").defaults_to(std::string("y"));
  s.integer("dof", "-", "index of the controlled free unknown when no node set is given").defaults_to(-1LL);
  s.real("increment", "m",
         "controlled displacement per step (its sign gives the direction; [analysis] arc_length overrides "
         "its size)");
  registry.add(
      Factory<Solver>{.name = "displacement_control",
                      .summary = "load factor as unknown, a DOF's (node set's mean) displacement prescribed",
                      .schema = std::move(s),
                      .create = [](const Params& p) { return std::make_unique<DisplacementControl>(p); },
                      .library = {}});
}
