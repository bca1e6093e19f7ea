#include "output/interface_output.hpp"

#include "files.hpp"

#include <cerrno>
#include <cstdio>
#include <fstream>

namespace stratum {

std::vector<InterfacePoint> interface_points(const Model& model, const Domain& dm) {
  std::vector<InterfacePoint> pts;
  if (!dm.law.contact) return pts;
  std::vector<int> nodes;
  Eigen::MatrixXd x, xp;
  for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
    const int c = dm.cells[ci];
    if (!model.is_active(c)) continue; // output skips cells removed or not yet placed
    model.cell_nodes(c, nodes, x);
    dm.element->point_coordinates(model.element_data(c, x), xp);
    for (std::size_t p = dm.first_point[ci]; p < dm.first_point[ci + 1]; ++p) {
      const auto slot = dm.states.committed(p);
      InterfacePoint ip;
      ip.x = xp.row(static_cast<Eigen::Index>(p - dm.first_point[ci])).transpose();
      ip.traction = Vec2(slot.stress()[0], slot.stress()[1]);
      ip.jump = Vec2(slot.strain()[0], slot.strain()[1]);
      ip.state = dm.law.contact->state(ip.traction, slot.history());
      ip.cell = c;
      pts.push_back(ip);
    }
  }
  if (!pts.empty())
    for (auto& p : pts) p.s = (p.x - pts.front().x).norm();
  return pts;
}

void write_interface_csv(const std::vector<InterfacePoint>& points, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw WriteError("cannot write interface CSV file '" + path + "': " + write_failure(errno));
  out << "s,x,y,shear_traction,normal_traction,slip,opening,status\n";
  static const char* names[] = {"stick", "slip", "open"};
  char buf[256];
  for (const auto& p : points) {
    std::snprintf(buf, sizeof buf, "%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,", p.s, p.x.x(), p.x.y(),
                  p.traction[0], p.traction[1], p.jump[0], p.jump[1]);
    out << buf << names[static_cast<int>(p.state)] << '\n';
  }
  if (!out) throw WriteError("cannot write interface CSV file '" + path + "': " + write_failure(errno));
}

void append_interface_fields(const Model& model, const std::string& traction_name,
                             const std::string& jump_name, std::vector<OutputArray>& ip_fields) {
  OutputArray tr{traction_name, 2, {}, {"shear", "normal"}}, jump{jump_name, 2, {}, {"slip", "opening"}},
      status{"interface_status", 1, {}};
  for (const auto& dm : model.domains) {
    if (!dm.law.contact) {
      std::size_t n = 0;
      for (std::size_t ci = 0; ci < dm.cells.size(); ++ci)
        if (model.is_active(dm.cells[ci])) n += dm.first_point[ci + 1] - dm.first_point[ci];
      tr.values.insert(tr.values.end(), 2 * n, 0.0);
      jump.values.insert(jump.values.end(), 2 * n, 0.0);
      status.values.insert(status.values.end(), n, -1.0);
      continue;
    }
    for (const auto& p : interface_points(model, dm)) {
      tr.values.insert(tr.values.end(), {p.traction[0], p.traction[1]});
      jump.values.insert(jump.values.end(), {p.jump[0], p.jump[1]});
      status.values.push_back(static_cast<double>(static_cast<int>(p.state)));
    }
  }
  ip_fields.push_back(std::move(tr));
  ip_fields.push_back(std::move(jump));
  ip_fields.push_back(std::move(status));
}

// ---------------------------------------------------------------- scene input

} // namespace stratum
