// SUNDIALS KINSOL (6.x) as a Solver plugin: one load step R(u, lambda) = 0 solved
// by KINSOL's Newton with line search, Picard, or fixed-point iteration with
// Anderson acceleration. KINSOL solves F(u) = 0 with F = -R, so its Jacobian
// dF/du is our tangent K; the linear systems go to the problem's sparse
// factorization (stratum/linear_solver.hpp) through a custom SUNLinearSolver of
// type DIRECT and a SUNMatrix shell holding the tangent, filled by a user-supplied
// Jacobian function.
//
//   newton:      K(u_k) p = -F(u_k), u_(k+1) = u_k + s p (s from KINSOL's line search)
//   picard:      L p = -F(u_k) with L = K(u_0) (the tangent at the step start), KINSOL's
//                Picard iteration (with Anderson acceleration when anderson > 0)
//   fixed_point: u_(k+1) = G(u_k) = u_k + K(u_0)^-1 R(u_k), accelerated by Anderson (depth
//                `anderson`)
//
// KINSOL's own stopping test stays (it iterates inside KINSol, so the shared per-iterate
// check of stratum/iteration.hpp cannot run between its iterations); its tolerance is
// derived from iteration::force_bound, the bound of every solver's force test. Before
// KINSOL starts and after it returns, the residual is evaluated and the shared force test
// (iteration::force_test) decides; KINSOL's return flags become statuses. The energy and
// displacement tests of [convergence] are not applied (README.md).
#include "stratum/iteration.hpp"
#include "stratum/plugin.hpp"

#include <kinsol/kinsol.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include <cmath>
#include <sstream>

namespace {

using namespace stratum;

enum class Strategy { newton, picard, fixed_point };

/// Everything the C callbacks need (user data of KINSOL, content of the matrix and solver).
struct Callbacks {
  NonlinearProblem* problem = nullptr;
  double lambda = 0;
  SparseMatrix k;
  LinearSolver* ls = nullptr;
  StepReport* rep = nullptr;
  Outcome failure; ///< the first failure inside a callback
  bool fixed_point = false;
  bool freeze = false; ///< picard: keep the first tangent and its factorization
  int tangents = 0, factorizations = 0;
  Eigen::VectorXd r, du; ///< scratch
};

Eigen::Map<Eigen::VectorXd> view(N_Vector v) {
  return {N_VGetArrayPointer(v), static_cast<Eigen::Index>(N_VGetLength(v))};
}

/// F(u) = -R(u) (newton, picard) or G(u) = u + K0^-1 R(u) (fixed point).
int system_fn(N_Vector uu, N_Vector fval, void* user) {
  auto& c = *static_cast<Callbacks*>(user);
  const Eigen::VectorXd u = view(uu);
  const Outcome o = c.problem->evaluate(u, c.lambda, c.r, nullptr);
  if (!o.ok() || !c.r.allFinite()) {
    if (c.failure.ok()) c.failure = o.ok() ? Outcome{Status::non_finite, "residual is NaN or Inf"} : o;
    return -1; // unrecoverable: KINSOL stops and we report the status
  }
  c.rep->residual_norms.push_back(c.r.norm());
  auto f = view(fval);
  if (c.fixed_point) {
    ++c.rep->solves;
    if (const Outcome s = c.ls->solve(c.r, c.du); !s.ok()) {
      if (c.failure.ok()) c.failure = s;
      return -1;
    }
    f = u + c.du;
  } else {
    f = -c.r;
  }
  return 0;
}

/// The Jacobian dF/du = K at uu, kept in the Callbacks (the SUNMatrix is a shell).
int jacobian_fn(N_Vector uu, N_Vector, SUNMatrix, void* user, N_Vector, N_Vector) {
  auto& c = *static_cast<Callbacks*>(user);
  if (c.freeze && c.tangents > 0) return 0;
  ++c.tangents;
  const Eigen::VectorXd u = view(uu);
  const Outcome o = c.problem->evaluate(u, c.lambda, c.r, &c.k);
  if (!o.ok()) {
    if (c.failure.ok()) c.failure = o;
    return -1;
  }
  return 0;
}

// ---- the SUNMatrix shell: KINSOL only zeroes it before calling jacobian_fn
SUNMatrix_ID matrix_id(SUNMatrix) { return SUNMATRIX_CUSTOM; }
int matrix_zero(SUNMatrix) { return 0; }
void matrix_destroy(SUNMatrix a) { SUNMatFreeEmpty(a); }

// ---- the SUNLinearSolver: setup factorizes K, solve back-substitutes
SUNLinearSolver_Type ls_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
SUNLinearSolver_ID ls_id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
int ls_setup(SUNLinearSolver s, SUNMatrix) {
  auto& c = *static_cast<Callbacks*>(s->content);
  if (c.freeze && c.factorizations > 0) return SUNLS_SUCCESS;
  ++c.factorizations;
  ++c.rep->factorizations;
  if (const Outcome o = c.ls->factorize(c.k); !o.ok()) {
    if (c.failure.ok()) c.failure = o;
    return SUNLS_LUFACT_FAIL;
  }
  return SUNLS_SUCCESS;
}
int ls_solve(SUNLinearSolver s, SUNMatrix, N_Vector x, N_Vector b, realtype) {
  auto& c = *static_cast<Callbacks*>(s->content);
  ++c.rep->solves;
  const Eigen::VectorXd rhs = view(b);
  if (const Outcome o = c.ls->solve(rhs, c.du); !o.ok()) {
    if (c.failure.ok()) c.failure = o;
    return SUNLS_PACKAGE_FAIL_UNREC;
  }
  view(x) = c.du;
  return SUNLS_SUCCESS;
}
int ls_free(SUNLinearSolver s) {
  s->content = nullptr;
  SUNLinSolFreeEmpty(s);
  return 0;
}

void quiet(int, const char*, const char*, char*, void*) {}

/// KINSOL's failure flags as our statuses: the status and the message of each flag; a message
/// marked `numbered` ends with the flag's number.
struct FlagMeaning {
  int flag;
  Status status;
  const char* message;
  bool numbered;
};
constexpr FlagMeaning flag_meanings[] = {
    {KIN_LINESEARCH_NONCONV, Status::not_converged,
     "the line search could not find an acceptable step (KIN_LINESEARCH_NONCONV)", false},
    {KIN_MAXITER_REACHED, Status::not_converged, "maximum number of iterations reached (KIN_MAXITER_REACHED)",
     false},
    {KIN_MXNEWT_5X_EXCEEDED, Status::diverged,
     "five consecutive steps exceeded the maximum Newton step (KIN_MXNEWT_5X_EXCEEDED)", false},
    {KIN_LINESEARCH_BCFAIL, Status::not_converged,
     "the line search failed the beta condition repeatedly (KIN_LINESEARCH_BCFAIL)", false},
    {KIN_LINSOLV_NO_RECOVERY, Status::singular, "the linear solver failed", true},
    {KIN_LSETUP_FAIL, Status::singular, "the linear solver failed", true},
    {KIN_LSOLVE_FAIL, Status::singular, "the linear solver failed", true},
    {KIN_SYSFUNC_FAIL, Status::material_failure, "the residual evaluation failed", true},
    {KIN_FIRST_SYSFUNC_ERR, Status::material_failure, "the residual evaluation failed", true},
    {KIN_REPTD_SYSFUNC_ERR, Status::material_failure, "the residual evaluation failed", true},
};

Outcome translate(int flag) {
  std::ostringstream m;
  m << "KINSOL: ";
  for (const FlagMeaning& f : flag_meanings)
    if (f.flag == flag) {
      m << f.message;
      if (f.numbered) m << " (flag " << flag << ")";
      return {f.status, m.str()};
    }
  m << "failed with flag " << flag;
  return {Status::not_converged, m.str()};
}

class Kinsol final : public Solver {
public:
  explicit Kinsol(const Params& p)
      : strategy_(p.text("strategy") == "picard"        ? Strategy::picard
                  : p.text("strategy") == "fixed_point" ? Strategy::fixed_point
                                                        : Strategy::newton),
        anderson_(p.integer("anderson")), damping_(p.real("damping")) {}

  StepReport solve(NonlinearProblem& problem, const StepRequest& req, Eigen::VectorXd& u) const override {
    StepReport rep;
    rep.lambda = req.lambda;
    const Convergence& conv = req.convergence;
    Callbacks cb;
    cb.problem = &problem;
    cb.lambda = req.lambda;
    cb.k = problem.make_tangent();
    cb.ls = &problem.linear_solver();
    cb.rep = &rep;
    cb.fixed_point = strategy_ == Strategy::fixed_point;
    cb.freeze = strategy_ == Strategy::picard;
    const auto n = problem.size();

    // The residual at the start fixes the force bound; picard and fixed point factorize K(u_0).
    if (auto o = problem.evaluate(u, req.lambda, cb.r, &cb.k); !o.ok()) return fail(rep, o);
    const double scale0 = problem.force_scale(req.lambda);
    const double bound0 = iteration::force_bound(conv, scale0);
    if (iteration::force_test(conv, cb.r.norm(), scale0)) {
      rep.residual_norms.push_back(cb.r.norm());
      return rep;
    }
    double fp_tol = 0;
    if (cb.fixed_point) {
      ++rep.factorizations;
      if (auto o = cb.ls->factorize(cb.k); !o.ok()) return fail(rep, o);
      ++rep.solves;
      if (auto o = cb.ls->solve(cb.r, cb.du); !o.ok()) return fail(rep, o);
      // |G(u) - u| = |K0^-1 R|: the force bound through the initial compliance.
      fp_tol = 1e-3 * bound0 * cb.du.lpNorm<Eigen::Infinity>() / cb.r.lpNorm<Eigen::Infinity>();
    }

    SUNContext ctx = nullptr;
    if (SUNContext_Create(nullptr, &ctx) != 0) return fail(rep, {Status::singular, "KINSOL: no SUNContext"});
    N_Vector uu = N_VNew_Serial(static_cast<sunindextype>(n), ctx);
    N_Vector scale = N_VNew_Serial(static_cast<sunindextype>(n), ctx);
    view(uu) = u;
    N_VConst(1.0, scale);
    void* mem = KINCreate(ctx);
    SUNMatrix shell = nullptr;
    SUNLinearSolver ls = nullptr;
    int flag = 0;
    auto check = [&flag](int f) {
      if (f != 0 && flag == 0) flag = f;
    };
    check(KINSetErrHandlerFn(mem, quiet, nullptr));
    if (anderson_ > 0 && strategy_ != Strategy::newton) check(KINSetMAA(mem, anderson_));
    check(KINInit(mem, system_fn, uu));
    check(KINSetUserData(mem, &cb));
    check(KINSetNumMaxIters(mem, conv.max_iterations));
    if (strategy_ != Strategy::newton && anderson_ > 0 && damping_ < 1) check(KINSetDampingAA(mem, damping_));
    if (cb.fixed_point) {
      check(KINSetFuncNormTol(mem, fp_tol));
    } else {
      // KINSOL's test is on the max norm: |F|_inf <= bound / sqrt(n) implies |R|_2 <= bound.
      check(KINSetFuncNormTol(mem, 0.5 * bound0 / std::sqrt(static_cast<double>(n))));
      check(KINSetScaledStepTol(mem, 1e-300));
      if (strategy_ == Strategy::newton) check(KINSetMaxSetupCalls(mem, 1)); // exact Newton
      shell = SUNMatNewEmpty(ctx);
      shell->ops->getid = matrix_id;
      shell->ops->zero = matrix_zero;
      shell->ops->destroy = matrix_destroy;
      ls = SUNLinSolNewEmpty(ctx);
      ls->content = &cb;
      ls->ops->gettype = ls_type;
      ls->ops->getid = ls_id;
      ls->ops->setup = ls_setup;
      ls->ops->solve = ls_solve;
      ls->ops->free = ls_free;
      check(KINSetLinearSolver(mem, ls, shell));
      check(KINSetJacFn(mem, jacobian_fn));
    }
    if (flag != 0) {
      rep.outcome = {Status::singular, "KINSOL: setting up failed with flag " + std::to_string(flag)};
    } else {
      const int strategy = strategy_ == Strategy::newton   ? KIN_LINESEARCH
                           : strategy_ == Strategy::picard ? KIN_PICARD
                                                           : KIN_FP;
      flag = KINSol(mem, uu, strategy, scale, scale);
      long iters = 0;
      KINGetNumNonlinSolvIters(mem, &iters);
      rep.iterations = static_cast<int>(iters);
      u = view(uu);
      if (flag < 0) {
        rep.outcome = cb.failure.ok() ? translate(flag) : cb.failure;
        if (!cb.failure.ok()) rep.outcome.message += " (inside KINSOL, flag " + std::to_string(flag) + ")";
      }
    }
    KINFree(&mem);
    if (ls) SUNLinSolFree(ls);
    if (shell) SUNMatDestroy(shell);
    N_VDestroy(uu);
    N_VDestroy(scale);
    SUNContext_Free(&ctx);
    if (!rep.outcome.ok()) return rep;

    // Our own test at KINSOL's answer (this evaluation also leaves the trial states there).
    if (auto o = problem.evaluate(u, req.lambda, cb.r, nullptr); !o.ok()) return fail(rep, o);
    const double rn = cb.r.norm();
    rep.residual_norms.push_back(rn);
    const double force_scale = problem.force_scale(req.lambda);
    if (!iteration::force_test(conv, rn, force_scale)) {
      std::ostringstream m;
      m << "KINSOL stopped (flag " << flag << ") at |R| = " << rn << " above the bound "
        << iteration::force_bound(conv, force_scale);
      return fail(rep, {Status::not_converged, m.str()});
    }
    return rep;
  }

private:
  static StepReport& fail(StepReport& rep, Outcome o) {
    rep.outcome = std::move(o);
    return rep;
  }
  Strategy strategy_;
  long long anderson_;
  double damping_;
};

} // namespace

STRATUM_PLUGIN(registry) {
  Schema s;
  s.text("strategy", {"newton", "picard", "fixed_point"},
         "KINSOL strategy: Newton with line search, Picard with the step-start tangent, or fixed point")
      .defaults_to(std::string("newton"));
  s.integer("anderson", "-", "Anderson acceleration depth for picard and fixed_point (0: none)")
      .at_least(0)
      .at_most(50)
      .defaults_to(5LL);
  s.real("damping", "-", "Anderson damping factor (1: undamped)").greater_than(0).at_most(1).defaults_to(1.0);
  registry.add(Factory<Solver>{.name = "kinsol",
                               .summary = "SUNDIALS KINSOL: Newton with line search, Picard, or fixed point "
                                          "with Anderson acceleration",
                               .schema = std::move(s),
                               .create = [](const Params& p) { return std::make_unique<Kinsol>(p); },
                               .library = {}});
}
