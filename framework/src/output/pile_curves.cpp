#include "output/pile_curves.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

namespace stratum {

double mean_settlement(const Model& m, const std::vector<int>& nodes) {
  if (nodes.empty()) return 0.0;
  double s = 0.0;
  for (int n : nodes) s -= m.u[m.dofs.dof(n, field_uy)];
  return s / static_cast<double>(nodes.size());
}

std::vector<std::array<double, 2>> axial_profile(const Model& m, const std::vector<int>& cells,
                                                 double per_unit) {
  std::map<long long, std::array<double, 2>> rows; // key: y in micrometres (1 / per_unit)
  std::vector<int> set(cells);
  std::sort(set.begin(), set.end());
  std::vector<int> nodes;
  Eigen::MatrixXd x, xp;
  Eigen::VectorXd w;
  for (const auto& dm : m.domains) {
    if (!dm.law.material) continue;
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
      const int c = dm.cells[ci];
      if (!m.is_active(c) || !std::binary_search(set.begin(), set.end(), c)) continue;
      m.cell_nodes(c, nodes, x);
      const ElementData data = m.element_data(c, x);
      dm.element->point_coordinates(data, xp);
      dm.element->point_weights(data, w);
      const double r0 = x.col(0).minCoeff(), r1 = x.col(0).maxCoeff();
      const double area =
          m.formulation == Formulation::axisymmetric ? std::numbers::pi * (r1 * r1 - r0 * r0) : r1 - r0;
      std::map<long long, std::array<double, 2>> local; // sum w sigma, sum w
      for (Eigen::Index p = 0; p < xp.rows(); ++p) {
        const auto key = std::llround(xp(p, 1) * per_unit);
        const double sy =
            dm.states.committed(dm.first_point[ci] + static_cast<std::size_t>(p)).stress()[voigt::yy];
        local[key][0] += w[p] * sy;
        local[key][1] += w[p];
      }
      for (const auto& [key, v] : local) {
        rows[key][0] = static_cast<double>(key) * (1.0 / per_unit);
        rows[key][1] += -area * v[0] / v[1];
      }
    }
  }
  std::vector<std::array<double, 2>> out;
  for (auto it = rows.rbegin(); it != rows.rend(); ++it) out.push_back(it->second);
  return out;
}

} // namespace stratum
