// Parameter studies: random numbers, normal quantiles, the distributions' quantiles and the
// curve reading of a sample's quantities (framework/src/sweep/sweep.hpp).
#include "sweep/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

namespace stratum::sweep {

namespace {
constexpr double nan = std::numeric_limits<double>::quiet_NaN();
}

// ---------------------------------------------------------------- numbers

double Rng::uniform() { return (static_cast<double>(engine_() >> 11) + 0.5) * 0x1.0p-53; }

std::uint64_t Rng::below(std::uint64_t n) {
  return static_cast<std::uint64_t>((static_cast<unsigned __int128>(engine_()) * n) >> 64);
}

double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

double normal_quantile(double p) {
  if (!(p > 0.0 && p < 1.0)) return p == 0.0 ? -INFINITY : p == 1.0 ? INFINITY : nan;
  // P. J. Acklam's rational approximations (central region and tails), about 1e-9 relative.
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                                 1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                                 6.680131188771972e+01, -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                                 -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                                 3.754408661907416e+00};
  const double p_low = 0.02425;
  double x;
  if (p < p_low || p > 1.0 - p_low) {
    const double q = std::sqrt(-2.0 * std::log(p < p_low ? p : 1.0 - p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    if (p > 1.0 - p_low) x = -x;
  } else {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
  }
  // One Halley step on Phi(x) - p (third-order convergence) brings it to rounding level.
  const double e = normal_cdf(x) - p;
  const double u = e * std::sqrt(2.0 * std::numbers::pi) * std::exp(0.5 * x * x);
  return x - u / (1.0 + 0.5 * x * u);
}

double Parameter::quantile(double p) const {
  switch (distribution) {
  case Distribution::uniform:
    return lower + p * (upper - lower);
  case Distribution::normal:
    return mean + sd * normal_quantile(p);
  case Distribution::lognormal: {
    const double s2 = std::log1p((sd / mean) * (sd / mean));
    return std::exp(std::log(mean) - 0.5 * s2 + std::sqrt(s2) * normal_quantile(p));
  }
  case Distribution::truncated_normal: {
    const double fa = std::isfinite(lower) ? normal_cdf((lower - mean) / sd) : 0.0;
    const double fb = std::isfinite(upper) ? normal_cdf((upper - mean) / sd) : 1.0;
    return std::clamp(mean + sd * normal_quantile(fa + p * (fb - fa)), lower, upper);
  }
  }
  return nan;
}

double curve_at(const std::vector<std::array<double, 2>>& xy, double x0) {
  for (std::size_t i = 0; i + 1 < xy.size(); ++i) {
    const double xa = xy[i][0], xb = xy[i + 1][0];
    if ((x0 - xa) * (x0 - xb) > 0.0) continue;
    if (xa == xb) return xy[i][1];
    const double t = (x0 - xa) / (xb - xa);
    return xy[i][1] + t * (xy[i + 1][1] - xy[i][1]);
  }
  if (xy.size() == 1 && xy[0][0] == x0) return xy[0][1];
  return nan;
}

std::string format_number(double v) {
  if (std::isnan(v)) return "";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.10g", v + 0.0);
  return buf;
}

std::vector<std::string> Quantity::columns() const {
  if (kind != Kind::curve || !list) return {name};
  std::vector<std::string> c;
  for (double a : at) c.push_back(name + "@" + format_number(a));
  return c;
}

} // namespace stratum::sweep
