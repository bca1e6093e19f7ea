// Where a pile's head settlement comes from, and how its head load is shared between shaft and
// base (curves/settlement_components.csv). Internal to the framework.
//
// Every quantity is a change since the start of the loaded stage (the first recorded level), so
// that the pile's weight and the stresses left by boring and concreting do not enter:
//
//   head_mm     = area mean of the settlement over the pile head  (1/A) int -u_y dA
//   base_mm     = the same over the pile toe
//   shortening  = -(1/A) int_pile eps_yy dV        (integration points of the pile cells)
//   slip        = settlement of the pile minus settlement of the soil at each node pair of the
//                 shaft interface (positive: the pile moves down past the soil); its mean over the
//                 shaft's node pairs and its value at the top pair
//   shaft, base = the vertical force the interface cells of the shaft (vertical edges) and of the
//                 base (the others) put on the pile's nodes, from the interface element's own
//                 integration of its tractions (kN, compression positive)
//
// For a prismatic pile with full (not B-bar) integration head = shortening + base to round-off:
// the identity checks the strain bookkeeping of the element against its displacements. In
// equilibrium shaft + base equals the head load to the solver's tolerance.
#pragma once

#include "stratum/model.hpp"
#include "stratum/units.hpp"

#include <array>
#include <utility>
#include <vector>

namespace stratum {

class PileComponents {
public:
  /// pile_cells: the pile's cell set; interface_domains: indices into model.domains of the
  /// interfaces whose one side is the pile. Call at the start of the loaded stage.
  PileComponents(const Model& model, std::vector<int> pile_cells, std::vector<std::size_t> interface_domains);

  /// One row at the model's committed state: load_kN (given), head_mm, pile_shortening_mm,
  /// base_mm, shaft_slip_mean_mm, shaft_slip_top_mm, shaft_load_kN, base_load_kN.
  /// The first call sets the reference state (all components zero).
  /// `small`: the factor from the length unit to the unit of the settlements (Units::small_length).
  std::array<double, 8> row(Model& model, double load_kN, double small = 1e3);

  /// The CSV header in the scene's units (the names above in kN, m).
  [[nodiscard]] static std::string header(const Units& units);

private:
  struct Raw {
    double head = 0, base = 0, shortening = 0, slip_mean = 0, slip_top = 0, shaft = 0, base_load = 0;
  };
  Raw measure(Model& model) const;

  std::vector<int> pile_cells_;
  std::vector<std::size_t> interface_domains_;
  std::vector<char> pile_node_; ///< per mesh node: 1 when a pile cell uses it
  double top_ = 0, bottom_ = 0; ///< the pile's head and toe levels (y)
  /// Per node of the head (toe) edges: its share of the area mean (sums to 1).
  std::vector<std::pair<int, double>> head_weights_, toe_weights_;
  double area_ = 0; ///< int w dA of the head, w = r (axisymmetric) or 1: the shortening's divisor
  bool have_reference_ = false;
  Raw reference_;
};

} // namespace stratum
