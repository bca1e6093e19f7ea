// What a reader of the VTK output needs to name the codes of the integration-point field
// "plastic" (Material::point_status): each model numbers its own regimes, so the codes mean
// something only together with the domain of the point and the names its model gives them.
//
//   cell field   "domain"                   index of the cell's domain
//   point field  "domain"                   (integration points) index of the point's domain
//   field data   "domains"                  the domain names, in that order
//   field data   "plastic_regimes_<domain>" Material::status_names() of the domain's model,
//                                           index = code (only for models that name them)
//   field data   "interface_status_names"   the codes of "interface_status" (stick, slip,
//                                           open), when the model has interfaces
//
// Header only: called from write_step (output/write_step.cpp) with the same traversal
// of active cells and points as the other integration-point fields.
#pragma once

#include "output/vtk_output.hpp"
#include "stratum/model.hpp"

#include <string>
#include <utility>
#include <vector>

namespace stratum {

/// Adds the field data and the cell field above to `out` and, when `ip_output`, the point
/// field "domain". Called after out.cells is filled (active cells in domain order).
inline void add_status_names(const Model& m, OutputStep& out, bool ip_output) {
  std::vector<std::string> domains;
  bool contact = false;
  OutputArray cell_domain{"domain", 1, {}};
  for (std::size_t d = 0; d < m.domains.size(); ++d) {
    const auto& dm = m.domains[d];
    domains.push_back(dm.name);
    for (const int c : dm.cells)
      if (m.is_active(c)) cell_domain.values.push_back(static_cast<double>(d));
    contact = contact || dm.law.contact != nullptr;
    if (!dm.law.material) continue;
    auto names = dm.law.material->status_names();
    if (!names.empty()) out.text_lists.emplace_back("plastic_regimes_" + dm.name, std::move(names));
  }
  out.text_lists.emplace_back("domains", std::move(domains));
  if (contact)
    out.text_lists.emplace_back("interface_status_names", std::vector<std::string>{"stick", "slip", "open"});
  if (cell_domain.values.size() == out.cells.size()) out.cell_fields.push_back(std::move(cell_domain));
  if (!ip_output) return;
  OutputArray domain{"domain", 1, {}};
  for (std::size_t d = 0; d < m.domains.size(); ++d) {
    const auto& dm = m.domains[d];
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci)
      if (m.is_active(dm.cells[ci]))
        domain.values.insert(domain.values.end(), dm.first_point[ci + 1] - dm.first_point[ci],
                             static_cast<double>(d));
  }
  out.ip_fields.push_back(std::move(domain));
}

} // namespace stratum
