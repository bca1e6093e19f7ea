// Numbering a domain's integration points and giving them their first state (internal to the
// framework): shared by the [[domains]] of area cells and the [[interfaces]].
#pragma once

#include "stratum/error.hpp"
#include "stratum/model.hpp"

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace stratum {

/// Checks every cell of `dm` against its element (shape and geometry), numbers the element's
/// points (`dm.first_point`) and gives every point its first history through `init(history)`,
/// committed and trial alike. A cell the element refuses is reported at `element_at` as
/// "<ctx> cell N: <the element's reason>".
template <class Init>
void place_points(Domain& dm, const Model& model, int history_size, const std::string& ctx,
                  const SourceLocation& element_at, Init&& init) {
  dm.first_point.assign(dm.cells.size() + 1, 0);
  std::vector<int> nodes;
  Eigen::MatrixXd x;
  for (std::size_t c = 0; c < dm.cells.size(); ++c) {
    const int cell = dm.cells[c];
    const Cell& cc = model.mesh.cells[static_cast<std::size_t>(cell)];
    const unsigned shape = cc.shape();
    try {
      if (!dm.element->accepts(cc.type))
        throw Error(std::string("the element does not take cells of type ") + to_string(cc.type));
      dm.element->check_shape(shape);
      model.cell_nodes(cell, nodes, x);
      dm.element->check_geometry(model.element_data(cell, x));
    } catch (const Error& e) {
      throw Error(element_at, ctx + " cell " + std::to_string(cell) + ": " + e.message());
    }
    dm.first_point[c + 1] = dm.first_point[c] + static_cast<std::size_t>(dm.element->num_points(shape));
  }
  dm.states = StateStore(dm.first_point.back(), history_size);
  for (std::size_t p = 0; p < dm.states.points(); ++p) init(dm.states.committed_for_init(p).history());
  dm.states.revert();
}

} // namespace stratum
