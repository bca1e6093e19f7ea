// Tests of the von Mises material (plugins/von_mises): derivatives of the model, the pure-shear
// closed form, the consistent tangent of the closest-point return against central differences
// (verification.md M5), and the Material wrapper with its schema.
#include "von_mises/von_mises.hpp"

#include "stratum/plasticity/integrate.hpp"
#include "stratum/plasticity/invariants.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace test_von_mises {

namespace {

using stratum::Mat6;
using stratum::Vec6;
namespace pl = stratum::plasticity;
namespace vm = stratum::von_mises;

vm::Constants steel_like() {
  vm::Constants c;
  c.E = 2.0e4;
  c.nu = 0.3;
  c.sigma_y = 100.0;
  c.H = 2.0e3;
  return c;
}

pl::Settings settings_for(pl::Scheme s) {
  pl::Settings st;
  st.scheme = s;
  return st;
}

/// Pure shear in xy under strain control, gamma from 0 up to gamma_max and back:
/// elastic tau = G (gamma - gamma_p); plastic sqrt(3) |tau| = sigma_y + H e with e = eps_bar_p and
/// d gamma_p = sqrt(3) sign(tau) d e (r_xy = 3 s_xy / q_eq = sqrt(3) sign(tau), h = 1). Loading:
///   e = (sqrt(3) G gamma - sigma_y) / (3 G + H)   for gamma > gamma_y = sigma_y / (sqrt(3) G)
/// Reverse loading after e1 = e(gamma_max), gamma_p1 = sqrt(3) e1:
///   e (3 G + H) = 3 G e1 - sigma_y - sqrt(3) G (gamma - gamma_p1)   once reverse yield is reached.
struct ShearExact {
  double G, sy, H;
  [[nodiscard]] double loading_e(double gamma) const {
    return std::max(0.0, (std::sqrt(3.0) * G * gamma - sy) / (3.0 * G + H));
  }
  /// tau and e at gamma on the path 0 -> gamma_max -> gamma (gamma <= gamma_max on the way back).
  void at(double gamma, double gamma_max, bool returning, double& tau, double& e) const {
    if (!returning) {
      e = loading_e(gamma);
      tau = G * (gamma - std::sqrt(3.0) * e);
      return;
    }
    const double e1 = loading_e(gamma_max), gp1 = std::sqrt(3.0) * e1;
    const double tau_el = G * (gamma - gp1);
    if (std::sqrt(3.0) * std::abs(tau_el) <= sy + H * e1 || tau_el > 0.0) {
      e = e1, tau = tau_el;
      return;
    }
    e = (3.0 * G * e1 - sy - std::sqrt(3.0) * G * (gamma - gp1)) / (3.0 * G + H);
    tau = -(sy + H * e) / std::sqrt(3.0);
  }
};

/// Central-difference tangent of integrate() at (sigma_n, q_n, de).
Mat6 fd_tangent(const vm::VonMisesModel& m, const pl::Settings& s, const Vec6& sigma_n, double q_n,
                const Vec6& de) {
  Mat6 T;
  const double h = 1e-7 * de.cwiseAbs().maxCoeff();
  for (int j = 0; j < 6; ++j) {
    Vec6 sp, sm;
    Mat6 dummy;
    double qp[1] = {q_n}, qm[1] = {q_n};
    REQUIRE(pl::integrate(m, s, sigma_n, de + h * Vec6::Unit(j), sp, qp, dummy).outcome.ok());
    REQUIRE(pl::integrate(m, s, sigma_n, de - h * Vec6::Unit(j), sm, qm, dummy).outcome.ok());
    T.col(j) = (sp - sm) / (2.0 * h);
  }
  return T;
}

double rel_max(const Mat6& a, const Mat6& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

} // namespace

TEST_CASE("von_mises: gradients and second derivatives match finite differences", "[point]") {
  const vm::VonMisesModel m(steel_like());
  Vec6 s;
  s << 120.0, -30.0, 15.0, 40.0, -25.0, 10.0;
  const double q[1] = {0.01};
  CHECK(m.yield(0, s, q) == Approx(pl::q_mises(s) - (100.0 + 2.0e3 * 0.01)).epsilon(1e-14));
  const Vec6 n = m.yield_gradient(0, s, q);
  const Mat6 G = m.flow_gradient(0, s, q);
  Vec6 n_fd;
  Mat6 G_fd;
  const double h = 1e-5;
  for (int j = 0; j < 6; ++j) {
    const Vec6 sp = s + h * Vec6::Unit(j), sm = s - h * Vec6::Unit(j);
    n_fd[j] = (m.yield(0, sp, q) - m.yield(0, sm, q)) / (2 * h);
    G_fd.col(j) = (m.flow(0, sp, q) - m.flow(0, sm, q)) / (2 * h);
  }
  CHECK((n - n_fd).cwiseAbs().maxCoeff() < 1e-8);
  CHECK((G - G_fd).cwiseAbs().maxCoeff() < 1e-8 * G.cwiseAbs().maxCoeff());
  CHECK((G - G.transpose()).cwiseAbs().maxCoeff() < 1e-15);
  CHECK((m.flow(0, s, q) - n).norm() == 0.0);            // associated
  CHECK(n.head<3>().sum() == Approx(0.0).margin(1e-14)); // isochoric flow
  // h = 1: the flow r has sqrt(2/3 r:r) = 1 (tensor norm with the engineering shear halved)
  const Vec6 r_tensor = (Vec6() << n.head<3>(), 0.5 * n.tail<3>()).finished();
  const double rr = r_tensor.head<3>().squaredNorm() + 2.0 * r_tensor.tail<3>().squaredNorm();
  CHECK(std::sqrt(2.0 / 3.0 * rr) == Approx(1.0).epsilon(1e-14));
  CHECK(m.hardening(0, s, q)[0] == 1.0);
  CHECK(m.yield_gradient_q(0, s, q)[0] == -2.0e3);
  CHECK(m.stress_scale(s, q) == Approx(120.0));
  // n . dsigma is the first-order change of f, including shear entries
  const Vec6 ds = 1e-6 * (Vec6() << 1, -2, 0.5, 3, -1, 2).finished();
  CHECK(m.yield(0, s + ds, q) - m.yield(0, s, q) == Approx(n.dot(ds)).epsilon(1e-6));
  // hydrostatic axis: f < 0, finite derivatives
  const Vec6 p = -50.0 * pl::identity();
  CHECK(m.yield(0, p, q) < 0);
  CHECK(m.yield_gradient(0, p, q).allFinite());
  CHECK(m.flow_gradient(0, p, q).allFinite());
  const double negative[1] = {-1e-3};
  CHECK_FALSE(m.admissible(s, negative));
}

TEST_CASE("von_mises: pure shear path follows the closed form", "[point]") {
  const vm::Constants c = steel_like();
  const vm::VonMisesModel m(c);
  const ShearExact ex{c.G(), c.sigma_y, c.H};
  const double gy = c.sigma_y / (std::sqrt(3.0) * c.G());
  // loading to 8 gamma_y in unequal increments (the first crosses the yield point), then back to
  // -8 gamma_y; the first return increment unloads elastically from the surface and yields again
  // in reverse within the same increment
  const std::vector<double> up = {0.6, 1.7, 2.0, 4.5, 8.0};
  const std::vector<double> down = {-1.5, -3.0, -8.0};
  for (pl::Scheme scheme : {pl::Scheme::closest_point, pl::Scheme::forward_euler, pl::Scheme::modified_euler,
                            pl::Scheme::trapezoidal, pl::Scheme::midpoint, pl::Scheme::cutting_plane}) {
    INFO(pl::to_string(scheme));
    pl::Settings s = settings_for(scheme);
    s.substeps = 100;
    const double tol = scheme == pl::Scheme::closest_point   ? 1e-8
                       : scheme == pl::Scheme::forward_euler ? 1e-3
                                                             : 1e-6;
    Vec6 sigma = Vec6::Zero();
    double q[1] = {0.0};
    double gamma = 0.0;
    bool returning = false;
    std::vector<double> path = up;
    path.insert(path.end(), down.begin(), down.end());
    for (std::size_t i = 0; i < path.size(); ++i) {
      returning = i >= up.size();
      const double g1 = path[i] * gy;
      Vec6 de = Vec6::Zero();
      de[stratum::voigt::xy] = g1 - gamma;
      Vec6 out;
      Mat6 T;
      const pl::Result r = pl::integrate(m, s, sigma, de, out, q, T);
      INFO("gamma / gamma_y = " << path[i] << ": " << r.outcome.message);
      REQUIRE(r.outcome.ok());
      sigma = out, gamma = g1;
      double tau, e;
      ex.at(gamma, up.back() * gy, returning, tau, e);
      CHECK(sigma[stratum::voigt::xy] == Approx(tau).epsilon(tol));
      CHECK(q[0] == Approx(e).epsilon(tol).margin(1e-15));
      // no normal stresses arise in pure shear
      CHECK(sigma.head<3>().cwiseAbs().maxCoeff() < 1e-9 * c.sigma_y);
      CHECK(r.plastic == (path[i] > 1.0 || path[i] < -1.0));
    }
  }
  // the closed form itself: monotonic loading at 4.5 gamma_y
  double tau, e;
  ex.at(4.5 * gy, 8.0 * gy, false, tau, e);
  CHECK(std::sqrt(3.0) * tau == Approx(c.sigma_y + c.H * e).epsilon(1e-14));
}

TEST_CASE("von_mises: consistent tangent of closest_point matches central differences", "[point]") {
  const vm::Constants c = steel_like();
  const vm::VonMisesModel m(c);
  pl::Settings s = settings_for(pl::Scheme::closest_point);
  s.ftol = 1e-12;
  const double ey = c.sigma_y / c.E;
  Vec6 plane, general;
  plane << 1.0, -0.6, 0.0, 0.8, 0.0, 0.0; // plane strain: eps_zz = gamma_yz = gamma_zx = 0
  general << 0.7, -0.2, -0.4, 0.5, -0.6, 0.3;
  Vec6 prestress; // a state on the yield surface with eps_bar_p = 0.004 and a mean stress
  prestress << 30.0, -80.0, -20.0, 35.0, 10.0, -15.0;
  const double q_pre = 0.004;
  prestress =
      -25.0 * pl::identity() + pl::deviator(prestress) * ((c.sigma_y + c.H * q_pre) / pl::q_mises(prestress));

  struct Start {
    const char* name;
    Vec6 sigma;
    double q;
  };
  for (const Start& st : {Start{"virgin", Vec6::Zero(), 0.0}, Start{"on the surface", prestress, q_pre}}) {
    for (const Vec6& dir : {plane, general}) {
      const bool is_plane = dir == plane;
      for (double size : {0.3, 2.0, 30.0}) {
        const Vec6 de = dir / dir.cwiseAbs().maxCoeff() * size * ey * (st.q > 0 ? 0.2 : 1.0);
        // from the surface, unloading along -dir would be elastic: keep the loading sense
        const Vec6 n = m.yield_gradient(0, st.sigma, std::span<const double>(&st.q, 1));
        const Vec6 d = (st.q > 0 && n.dot(vm::isotropic_stiffness(c.E, c.nu) * de) < 0) ? Vec6(-de) : de;
        INFO(st.name << (is_plane ? ", plane strain" : ", 3D") << ", |de| = " << size << " eps_y");
        Vec6 sigma;
        Mat6 T;
        double q[1] = {st.q};
        const pl::Result r = pl::integrate(m, s, st.sigma, d, sigma, q, T);
        REQUIRE(r.outcome.ok());
        const bool elastic = st.q == 0.0 && size < 1.0;
        CHECK(r.plastic == !elastic);
        const Mat6 T_fd = fd_tangent(m, s, st.sigma, st.q, d);
        CHECK(rel_max(T, T_fd) < 1e-5);
        CHECK((T - T.transpose()).cwiseAbs().maxCoeff() < 1e-9 * T.cwiseAbs().maxCoeff()); // associated
        if (!elastic && size > 10.0) {
          // a large step: the algorithmic modulus differs from the continuum one
          const int active[1] = {0};
          const Mat6 Cep = pl::continuum_tangent(m, sigma, q, active);
          CHECK(rel_max(Cep, T_fd) > 1e-3);
        }
      }
    }
  }
}

TEST_CASE("von_mises: closest-point return equals the classical radial return", "[point]") {
  // Simo & Hughes (1998), box 3.1: dgamma = f_trial / (3 G + H) in q_eq units, s = s_trial (1 - 3 G dgamma /
  // q_trial)
  const vm::Constants c = steel_like();
  const vm::VonMisesModel m(c);
  Vec6 de;
  de << 15e-3, -5e-3, 2.5e-3, 10e-3, -5e-3, 2e-3;
  const Vec6 trial = vm::isotropic_stiffness(c.E, c.nu) * de;
  const double f_trial = pl::q_mises(trial) - c.sigma_y;
  REQUIRE(f_trial > c.sigma_y);
  const double dl = f_trial / (3.0 * c.G() + c.H);
  const Vec6 expected =
      pl::mean(trial) * pl::identity() + pl::deviator(trial) * (1.0 - 3.0 * c.G() * dl / pl::q_mises(trial));
  Vec6 sigma;
  Mat6 T;
  double q[1] = {0.0};
  pl::Counters counters;
  REQUIRE(pl::integrate(m, settings_for(pl::Scheme::closest_point), Vec6::Zero(), de, sigma, q, T, &counters)
              .outcome.ok());
  CHECK((sigma - expected).cwiseAbs().maxCoeff() < 1e-10 * c.sigma_y);
  CHECK(q[0] == Approx(dl).epsilon(1e-12));
  CHECK(counters.iterations == 1); // Newton on the full system is exact after one step for linear hardening
  // classical algorithmic modulus: D - 6 G^2/(3G + H) N N^T - 4 G^2 dl / q_trial (I_dev - 3/2 N N^T), N =
  // s/|s| ... (checked against finite differences above); here: bulk response stays elastic
  const Vec6 vol = pl::identity() * 1e-4;
  CHECK((T * vol).head<3>().mean() == Approx(3.0 * c.K() * 1e-4).epsilon(1e-10));
}

TEST_CASE("von_mises: material update, history and schema", "[point]") {
  const stratum::Schema schema = vm::schema();
  REQUIRE(schema.find("E"));
  CHECK(schema.find("E")->required());
  CHECK(schema.find("sigma_y")->required());
  CHECK_FALSE(schema.find("nu")->in_range(0.5));
  CHECK_FALSE(schema.find("nu")->in_range(-1.0));
  CHECK(schema.find("H")->in_range(0.0));
  CHECK_FALSE(schema.find("H")->in_range(-1.0));
  CHECK(std::get<std::string>(*schema.find("integrator")->fallback) == "closest_point");

  stratum::Params p;
  for (const auto& spec : schema.specs())
    if (spec.fallback) p.set(spec.name, *spec.fallback);
  p.set("E", 2.0e4);
  p.set("sigma_y", 100.0);
  p.set("H", 2.0e3);
  p.set("integrator", std::string("modified_euler"));
  const auto mat = vm::create(p);
  REQUIRE(mat);
  CHECK(mat->history_size() == 1);
  CHECK_FALSE(mat->is_linear());
  const auto& vmat = dynamic_cast<const vm::VonMisesMaterial&>(*mat);
  CHECK(vmat.settings().scheme == pl::Scheme::modified_euler);
  CHECK(vmat.model().constants().nu == 0.3);

  const Vec6 stress_n = Vec6::Zero(), strain_n = Vec6::Zero();
  Vec6 dstrain;
  dstrain << 2e-2, -1e-2, -1e-2, 0, 0, 0;
  const double history_n[1] = {0.0};
  double history[1] = {-1.0};
  Vec6 stress;
  Mat6 tangent;
  stratum::MaterialOutput out{stress, history, tangent};
  const stratum::Outcome o = mat->update({stress_n, strain_n, history_n, dstrain, {3, 1}}, out);
  REQUIRE(o.ok());
  CHECK(history[0] > 0.0);
  CHECK(pl::q_mises(stress) == Approx(100.0 + 2.0e3 * history[0]).epsilon(1e-8));

  // failures name the point and the integrator
  Vec6 bad = dstrain;
  bad[0] = std::numeric_limits<double>::infinity();
  const stratum::Outcome f = mat->update({stress_n, strain_n, history_n, bad, {3, 1}}, out);
  CHECK(f.status == stratum::Status::non_finite);
  CHECK_THAT(f.message, Catch::Contains("von_mises (element 3, point 1)"));
  CHECK_THAT(f.message, Catch::Contains("modified_euler"));
}

} // namespace test_von_mises
