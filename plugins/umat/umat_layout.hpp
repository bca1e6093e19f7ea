// The one place where Stratum's Voigt vectors meet the Abaqus UMAT component layout.
//
// Stratum (stratum/voigt.hpp), 6 components, engineering shear strains, tension positive:
//   0: xx   1: yy   2: zz   3: xy   4: yz   5: zx
// Abaqus, NDI direct components followed by NSHR shear components, engineering shear strains,
// tension positive:
//   NTENS = 6 (3D):                             11, 22, 33, 12, 13, 23
//   NTENS = 4 (plane strain and axisymmetry):   11, 22, 33, 12
// In axisymmetry Stratum's x is r, y is z and z is theta, so the NTENS = 4 vector is
// (rr, zz, theta-theta, rz), the order Abaqus' axisymmetric elements pass: 1 = r, 2 = z, 3 = theta.
//
// The two layouts differ only in the order of the last two shears: Stratum's yz (index 4) is
// Abaqus' 23 (index 6 in Fortran numbering) and Stratum's zx (index 5) is Abaqus' 13 (index 5).
// Both use engineering shear strains and tensor shear stresses, so no factor of 2 appears.
//
// DDSDDE is a Fortran array DDSDDE(NTENS, NTENS), column-major:
//   DDSDDE(i, j) = d STRESS(i) / d STRAN(j)  at  ddsdde[(i - 1) + (j - 1) * NTENS].
#pragma once

#include "stratum/voigt.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace stratum::umat {

/// Abaqus position (0-based) of each Stratum component for NTENS = 6.
inline constexpr std::array<int, 6> abaqus_index_3d = {0, 1, 2, 3, 5, 4};
/// Abaqus position (0-based) of each Stratum component for NTENS = 4; -1: not carried.
inline constexpr std::array<int, 6> abaqus_index_plane = {0, 1, 2, 3, -1, -1};

/// NDI, NSHR and NTENS of a layout.
struct Layout {
  int ndi = 3;
  int nshr = 3;
  int ntens = 6;

  [[nodiscard]] static Layout three_d() { return {3, 3, 6}; }
  [[nodiscard]] static Layout plane() { return {3, 1, 4}; }
  [[nodiscard]] const std::array<int, 6>& index() const {
    return ntens == 6 ? abaqus_index_3d : abaqus_index_plane;
  }
};

/// True when the out-of-plane shears yz, zx of every vector are exactly zero, i.e. the state
/// fits the NTENS = 4 layout without loss.
[[nodiscard]] inline bool in_plane(const Vec6& a, const Vec6& b, const Vec6& c) {
  return a[voigt::yz] == 0.0 && a[voigt::zx] == 0.0 && b[voigt::yz] == 0.0 && b[voigt::zx] == 0.0 &&
         c[voigt::yz] == 0.0 && c[voigt::zx] == 0.0;
}

/// Stratum vector -> Abaqus array of NTENS entries (stress or engineering strain alike).
inline void to_abaqus(const Layout& l, const Vec6& v, double* a) {
  const auto& idx = l.index();
  for (int i = 0; i < 6; ++i)
    if (idx[static_cast<std::size_t>(i)] >= 0) a[idx[static_cast<std::size_t>(i)]] = v[i];
}

/// Abaqus array of NTENS entries -> Stratum vector; components NTENS = 4 does not carry are 0.
[[nodiscard]] inline Vec6 from_abaqus(const Layout& l, const double* a) {
  const auto& idx = l.index();
  Vec6 v = Vec6::Zero();
  for (int i = 0; i < 6; ++i)
    if (idx[static_cast<std::size_t>(i)] >= 0) v[i] = a[idx[static_cast<std::size_t>(i)]];
  return v;
}

/// Stratum tangent -> column-major DDSDDE(NTENS, NTENS) (used by the tests and for the initial
/// contents of DDSDDE, which a UMAT overwrites).
inline void tangent_to_abaqus(const Layout& l, const Mat6& D, double* ddsdde) {
  const auto& idx = l.index();
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const int a = idx[static_cast<std::size_t>(i)], b = idx[static_cast<std::size_t>(j)];
      if (a >= 0 && b >= 0) ddsdde[a + b * l.ntens] = D(i, j);
    }
}

/// Column-major DDSDDE(NTENS, NTENS) -> Stratum's 6 x 6 tangent.
///
/// For NTENS = 4 the rows and columns of yz and zx are not computed by the UMAT. They are
/// filled with an uncoupled elastic-like shear stiffness on the diagonal: DDSDDE(4, 4) (the
/// in-plane shear stiffness) when it is positive and finite, else the largest direct diagonal
/// entry, else 1. The plane-strain and axisymmetric elements read only the top-left 4 x 4
/// block, so a scene never uses these entries; the material-point driver uses them only to keep
/// the out-of-plane shear stresses at zero under stress control.
[[nodiscard]] inline Mat6 tangent_from_abaqus(const Layout& l, const double* ddsdde) {
  const auto& idx = l.index();
  Mat6 D = Mat6::Zero();
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const int a = idx[static_cast<std::size_t>(i)], b = idx[static_cast<std::size_t>(j)];
      if (a >= 0 && b >= 0) D(i, j) = ddsdde[a + b * l.ntens];
    }
  if (l.ntens == 4) {
    double g = D(voigt::xy, voigt::xy);
    if (!(std::isfinite(g) && g > 0.0)) {
      g = std::max({D(0, 0), D(1, 1), D(2, 2)});
      if (!(std::isfinite(g) && g > 0.0)) g = 1.0;
    }
    D(voigt::yz, voigt::yz) = D(voigt::zx, voigt::zx) = g;
  }
  return D;
}

} // namespace stratum::umat
