// Crisfield's arc-length method for one step of a path-following analysis, with
// the switch to the constant external-work increment near a limit load (thesis
// (4.13)-(4.18)). The load factor is an unknown: the step solves
//
//   R(u_n + du, lambda_n + dl) = 0  and  g(du, dl) = 0,
//
// where R = lambda F_ref - F_int(u) and g is the constraint
//   arc length (4.15)-(4.16):  du.du + psi^2 dl^2 = s^2
//     (cylindrical: psi = 0; spherical: psi > 0, in m per unit load factor),
//   external work (4.17)-(4.18): first iterate (lambda_n + dl/2) F.du = W, then every
//     correction does no work: (lambda + dlambda/2) F.ddu = 0.
#include "common/solver_steps.hpp"
#include "stratum/plugin.hpp"

#include <Eigen/SparseLU>

#include <cmath>
#include <sstream>

namespace {

using namespace stratum;
using solver_steps::fail;

class ArcLength final : public Solver {
public:
  explicit ArcLength(const Params& p)
      : spherical_(p.text("constraint") == "spherical"), psi_(p.real("psi")),
        full_newton_(p.text("tangent") == "full"), work_switch_(p.real("work_switch")),
        determinant_sign_(p.text("predictor_sign") == "determinant"),
        residual_roots_(p.text("root") == "residual") {}

  [[nodiscard]] bool path_following() const override { return true; }

  StepReport solve(NonlinearProblem& problem, const StepRequest& req, Eigen::VectorXd& u) const override {
    StepReport rep;
    const Convergence& c = req.convergence;
    const Eigen::VectorXd& f = problem.reference_load();
    LinearSolver& ls = problem.linear_solver();
    SparseMatrix k = problem.make_tangent();
    const Eigen::VectorXd u_n = u;
    const double lambda_n = req.lambda_n;
    Eigen::VectorXd r, uf, ur;

    // ---- predictor: tangent direction uf = K^-1 F at the converged state
    if (auto o = problem.evaluate(u, lambda_n, r, &k); !o.ok()) return fail(rep, o);
    if (auto o = factor(ls, k, rep); !o.ok()) return fail(rep, o);
    if (auto o = solve(ls, f, uf, rep); !o.ok()) return fail(rep, o);
    const double psi = !spherical_ ? 0.0 : (psi_ > 0 ? psi_ : uf.norm()); // m per unit load factor
    const double psi2 = psi * psi;
    const double norm_f = std::sqrt(uf.squaredNorm() + psi2);
    if (!(norm_f > 0) || !std::isfinite(norm_f))
      return fail(rep, {Status::singular, "arc length: tangent direction K^-1 F is zero or not finite"});
    double s = req.arc_length;
    if (!(s > 0)) s = std::abs(req.lambda - lambda_n) * norm_f;
    rep.arc_length = s; // replaced by the measured size on success
    // Predictor sign. "displacement" (Feng): the new direction makes an acute angle with the
    // last step. "determinant": the load factor moves in the stage's direction while det K > 0
    // and against it while det K < 0 (past a limit point); needs a sparse LU of K (extra cost).
    double sign = req.lambda >= lambda_n ? 1.0 : -1.0;
    if (determinant_sign_) {
      Eigen::SparseLU<SparseMatrix> lu;
      lu.analyzePattern(k);
      lu.factorize(k);
      if (lu.info() != Eigen::Success) return fail(rep, {Status::singular, "arc length: det K: LU failed"});
      if (lu.signDeterminant() < 0) sign = -sign;
    } else if (req.previous_increment && req.previous_increment->size() == uf.size()) {
      const double d = req.previous_increment->dot(uf) + psi2 * req.previous_dlambda;
      if (d != 0) sign = d > 0 ? 1.0 : -1.0;
    }
    // Near a limit load the constant external-work increment (4.17)-(4.18) replaces the arc
    // length. "Near" is measured by Bergan's current stiffness parameter from the last step's
    // secant, S = (F.uf)_first / (F.du_prev / dl_prev): 1 while elastic, 0 at a limit load. (The
    // predictor's own tangent cannot tell: at a converged state the material points see a zero
    // strain increment and return their elastic tangent.)
    const double fu = f.dot(uf);
    if (first_fu_ == 0 && fu != 0) first_fu_ = fu; // the first step's F.K^-1 F
    double stiffness = 1.0;
    if (req.previous_increment && req.previous_dlambda != 0 && first_fu_ != 0) {
      const double secant = f.dot(*req.previous_increment) / req.previous_dlambda; // F.du / dl
      stiffness = secant != 0 ? first_fu_ / secant : 0.0;
    } else if (req.previous_increment && req.previous_dlambda == 0) {
      stiffness = 0.0;
    }
    const bool work = work_switch_ > 0 && req.previous_increment && std::abs(stiffness) < work_switch_;
    double dl = 0;
    if (work) {
      // W = work of the last step, (lambda_n - dl_prev / 2) F.du_prev, scaled with the ratio of this
      // step's size to the last one's (so that cut-back and growth act on it); the first iterate
      // satisfies (lambda_n + dl / 2) F.(dl uf) = W, i.e. fu/2 dl^2 + lambda_n fu dl - W = 0.
      const Eigen::VectorXd& dp = *req.previous_increment;
      const double s_prev = std::sqrt(dp.squaredNorm() + psi2 * req.previous_dlambda * req.previous_dlambda);
      const double w =
          std::abs((lambda_n - 0.5 * req.previous_dlambda) * f.dot(dp)) * (s_prev > 0 ? s / s_prev : 1.0);
      const double disc = lambda_n * lambda_n * fu * fu + 2 * fu * w;
      if (disc < 0 || fu == 0)
        return fail(rep, {Status::not_converged, "constant-work predictor has no real root"});
      const double r1 = (-lambda_n * fu + std::sqrt(disc)) / fu, r2 = (-lambda_n * fu - std::sqrt(disc)) / fu;
      // The root in the direction of the path; of two such, the one nearer zero.
      const bool ok1 = r1 * sign > 0, ok2 = r2 * sign > 0;
      if (ok1 != ok2)
        dl = ok1 ? r1 : r2;
      else
        dl = std::abs(r1) < std::abs(r2) ? r1 : r2;
    } else {
      dl = sign * s / norm_f;
    }
    Eigen::VectorXd du = dl * uf;

    // ---- corrector
    double r0 = -1.0, e0 = -1.0;
    Eigen::VectorXd ddu;
    for (int it = 0;; ++it) {
      const double lambda = lambda_n + dl;
      u = u_n + du;
      const bool tangent = full_newton_;
      if (auto o = problem.evaluate(u, lambda, r, tangent ? &k : nullptr); !o.ok()) return fail(rep, o);
      const double rn = r.norm();
      if (auto o = solver_steps::record_residual(rep, rn); !o.ok()) return fail(rep, o);
      const auto chk = solver_steps::check(c, it, rn, problem.force_scale(lambda), ddu, r, du.norm(), e0);
      if (chk.converged()) {
        rep.lambda = lambda;
        rep.arc_length = std::sqrt(du.squaredNorm() + psi2 * dl * dl); // measured: thesis (4.19)
        return rep;
      }
      if (r0 < 0) r0 = std::max(rn, c.force_atol);
      if (auto o = solver_steps::iteration_limit_at("arc length", c, it, rn, lambda); !o.ok())
        return fail(rep, o);
      if (it > 1 && rn > 1e6 * r0) return fail(rep, {Status::diverged, "arc length diverged"});
      if (tangent)
        if (auto o = factor(ls, k, rep); !o.ok()) return fail(rep, o);
      if (auto o = solve(ls, r, ur, rep); !o.ok()) return fail(rep, o);
      if (tangent)
        if (auto o = solve(ls, f, uf, rep); !o.ok()) return fail(rep, o);
      ++rep.iterations;
      double dlam = 0;
      if (work) {
        // (4.18): the correction does no external work, F.(ur + dlam uf) = 0.
        const double fuf = f.dot(uf);
        if (fuf == 0) return fail(rep, {Status::singular, "constant-work corrector: F.K^-1 F = 0"});
        dlam = -f.dot(ur) / fuf;
      } else {
        // (4.15)-(4.16): |du + ur + dlam uf|^2 + psi^2 (dl + dlam)^2 = s^2.
        const Eigen::VectorXd a0 = du + ur;
        const double qa = uf.squaredNorm() + psi2;
        const double qb = 2 * (uf.dot(a0) + psi2 * dl);
        const double qc = a0.squaredNorm() + psi2 * dl * dl - s * s;
        const double disc = qb * qb - 4 * qa * qc;
        if (disc < 0) {
          std::ostringstream m;
          m << "arc-length constraint has no real root at iteration " << it + 1 << " (load factor " << lambda
            << ")";
          return fail(rep, {Status::not_converged, m.str()});
        }
        // Both roots; keep the one whose increment makes the smaller angle with the current one
        // (Crisfield's criterion), which does not turn the path back on itself.
        const double q = -0.5 * (qb + (qb >= 0 ? 1 : -1) * std::sqrt(disc));
        const double x1 = q / qa, x2 = q != 0 ? qc / q : -x1;
        auto cosine = [&](double x) { return (du.dot(a0 + x * uf) + psi2 * dl * (dl + x)); };
        dlam = cosine(x1) >= cosine(x2) ? x1 : x2;
        if (residual_roots_ && x1 != x2) {
          // At kinks and sharp snap-backs the angle criterion can pick the extension of a branch
          // behind the kink and cycle: keep the angle's root unless its iterate's residual is more
          // than twice the other's.
          const double other = dlam == x1 ? x2 : x1;
          Eigen::VectorXd ra, rb;
          const bool ok_a =
              problem.evaluate(u_n + a0 + dlam * uf, lambda + dlam, ra, nullptr).ok() && ra.allFinite();
          const bool ok_b =
              problem.evaluate(u_n + a0 + other * uf, lambda + other, rb, nullptr).ok() && rb.allFinite();
          if (ok_b && (!ok_a || ra.norm() > 2 * rb.norm())) dlam = other;
        }
      }
      ddu = ur + dlam * uf;
      if (e0 < 0) e0 = std::abs(ddu.dot(r));
      du += ddu;
      dl += dlam;
    }
  }

private:
  static Outcome factor(LinearSolver& ls, const SparseMatrix& k, StepReport& rep) {
    ++rep.factorizations;
    return ls.factorize(k);
  }
  static Outcome solve(LinearSolver& ls, const Eigen::VectorXd& b, Eigen::VectorXd& x, StepReport& rep) {
    ++rep.solves;
    Outcome o = ls.solve(b, x);
    if (o.ok() && !x.allFinite()) return {Status::singular, "linear solve gave NaN or Inf"};
    return o;
  }
  bool spherical_;
  double psi_;
  bool full_newton_;
  double work_switch_;
  bool determinant_sign_;
  bool residual_roots_;
  mutable double first_fu_ = 0; ///< F.K^-1 F at the first step: reference of the stiffness parameter
};

} // namespace

STRATUM_PLUGIN(registry) {
  Schema s;
  s.text("constraint", {"cylindrical", "spherical"},
         "arc-length constraint: displacements only, or displacements and load factor (weighted by psi)")
      .defaults_to(std::string("cylindrical"));
  s.real("psi", "m", "spherical: weight of the load factor in the constraint; 0: |K^-1 F| of each step")
      .at_least(0)
      .defaults_to(0.0);
  s.text("tangent", {"full", "modified"}, "re-form the tangent every iteration, or keep the predictor's")
      .defaults_to(std::string("full"));
  s.real("work_switch", "-",
         "switch to the constant-work increment (4.17)-(4.18) when the current stiffness parameter "
         "(last step's secant against the first tangent) falls below this (near a limit load); 0: never")
      .at_least(0)
      .at_most(1)
      .defaults_to(0.0);
  s.text("predictor_sign", {"displacement", "determinant"},
         "direction of the predictor: acute angle with the last step, or the sign change of det K "
         "(follows sharp snap-backs; costs a sparse LU per step)")
      .defaults_to(std::string("displacement"));
  s.text("root", {"angle", "residual"},
         "root of the constraint: smaller angle with the current increment (Crisfield), or smaller residual "
         "(two extra residual evaluations per iteration; robust at kinks and sharp snap-backs)")
      .defaults_to(std::string("angle"));
  registry.add(
      Factory<Solver>{.name = "arc_length",
                      .summary = "Crisfield arc length with the constant-work switch near limit loads",
                      .schema = std::move(s),
                      .create = [](const Params& p) { return std::make_unique<ArcLength>(p); },
                      .library = {}});
}
