// The state of interface points for output: the CSV of an interface per output step and the
// interface fields of the VTK integration points. Internal to the framework.
#pragma once

#include "output/vtk_output.hpp"
#include "stratum/contact_law.hpp"
#include "stratum/model.hpp"

#include <string>
#include <vector>

namespace stratum {

/// The state of one interface integration point.
struct InterfacePoint {
  Vec2 x;         ///< coordinates
  double s = 0.0; ///< distance along the interface from its first point (m)
  Vec2 traction;  ///< shear, normal (kPa; normal tension positive)
  Vec2 jump;      ///< slip, opening (m)
  ContactState state = ContactState::stick;
  int cell = -1; ///< the interface cell (mesh cell index) the point belongs to
};

/// The committed states of the points of a domain with a ContactLaw, in cell order.
[[nodiscard]] std::vector<InterfacePoint> interface_points(const Model& model, const Domain& domain);

/// Writes the points as CSV (header: s,x,y,shear_traction,normal_traction,slip,opening,status).
/// Throws Error when the file cannot be written.
void write_interface_csv(const std::vector<InterfacePoint>& points, const std::string& path);

/// Integration-point fields over every domain of the model in output order (domains, cells,
/// points): the traction (shear, normal) and the jump (slip, opening) named as given ("interface_
/// traction [kPa]", "interface_jump [m]") and "interface_status" (0 stick, 1 slip, 2 open; -1 at
/// continuum points).
void append_interface_fields(const Model& model, const std::string& traction_name,
                             const std::string& jump_name, std::vector<OutputArray>& ip_fields);

} // namespace stratum
