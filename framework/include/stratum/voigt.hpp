// Voigt notation shared by all materials and elements.
//
// Materials work in full 3D Voigt form, tension positive, engineering shear strains:
//   index 0: xx   1: yy   2: zz   3: xy   4: yz   5: zx
// Axisymmetric elements map  r -> x (0), z -> y (1), theta -> z (2), rz -> xy (3).
// Plane-strain elements use components 0, 1, 3 and keep eps_zz = 0 (sigma_zz is computed).
#pragma once

#include <Eigen/Core>

namespace stratum {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;

namespace voigt {
inline constexpr int xx = 0, yy = 1, zz = 2, xy = 3, yz = 4, zx = 5;
inline constexpr int size = 6;
} // namespace voigt

} // namespace stratum
