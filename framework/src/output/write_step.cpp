// One VTK output step: displacements, reactions, cell stresses, the integration-point cloud
// with the materials' named history variables, and the interface fields.
#include "output/interface_output.hpp"
#include "output/recorders.hpp"
#include "output/run_view.hpp"
#include "output/vtk_output.hpp"
#include "status_output.hpp"

#include <algorithm>
#include <filesystem>
#include <limits>

namespace fs = std::filesystem;

namespace stratum {

namespace {

/// The name of a VTK array with its unit spelt in the scene's units, as ParaView lists it:
/// "stress [kPa]" ("stress [MPa]" in N, mm); "-" for a dimensionless quantity ("strain [-]").
/// Integer codes (domain, set_id, plastic, interface_status) keep their bare names.
std::string with_unit(const std::string& name, const Units& units, std::string_view unit) {
  return name + " [" + units.label(unit) + "]";
}

/// A material's history name "name [unit]" (stratum::history_names, units of kN, m) with its unit
/// spelt in the scene's units; a name without a unit (a UMAT's STATEV names) as it is.
std::string history_name(const std::string& name, const Units& units) {
  const auto open = name.rfind(" [");
  if (open == std::string::npos || name.back() != ']') return name;
  return with_unit(name.substr(0, open), units,
                   std::string_view(name).substr(open + 2, name.size() - open - 3));
}

/// The unit of a nodal force: the whole ring in axisymmetry and a force in 3D, per unit of
/// thickness in plane strain.
std::string_view force_unit(const Model& m) {
  return m.formulation == Formulation::plane_strain ? "kN/m" : "kN";
}

/// The nodal fields: displacement and reaction (3 components), then every other field of the model.
void add_node_fields(const Model& m, const Units& units, OutputStep& out) {
  const std::vector<std::string> xyz{"x", "y", "z"};
  OutputArray disp{with_unit("displacement", units, "m"), 3,
                   std::vector<double>(m.mesh.nodes.size() * 3, 0.0), xyz};
  OutputArray reac{with_unit("reaction", units, force_unit(m)), 3,
                   std::vector<double>(m.mesh.nodes.size() * 3, 0.0), xyz};
  for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n)
    for (int c = 0; c < m.dim(); ++c) {
      const int d = m.dofs.dof(static_cast<int>(n), field_ux + c);
      if (d < 0) continue;
      disp.values[3 * n + static_cast<std::size_t>(c)] = m.u[d];
      if (m.dofs.eq[static_cast<std::size_t>(d)] < 0)
        reac.values[3 * n + static_cast<std::size_t>(c)] =
            m.reactions[d] - m.load_base[d] - m.lambda * m.load_ref[d];
    }
  out.point_fields = {std::move(disp), std::move(reac)};
  // Every other field of the model (e.g. a pore pressure) as a scalar array of its name; NaN at
  // the nodes that do not carry it (the midside nodes of a Taylor-Hood cell).
  for (std::size_t f = static_cast<std::size_t>(m.dim()); f < m.dofs.fields.size(); ++f) {
    OutputArray a{with_unit(m.dofs.fields[f].name, units, m.dofs.fields[f].unit), 1,
                  std::vector<double>(m.mesh.nodes.size(), std::numeric_limits<double>::quiet_NaN())};
    for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n)
      if (const int d = m.dofs.dof(static_cast<int>(n), static_cast<int>(f)); d >= 0) a.values[n] = m.u[d];
    out.point_fields.push_back(std::move(a));
  }
  // The steady (hydrostatic) pore pressure below a phreatic level, at every node.
  if (m.water.present()) {
    OutputArray a{with_unit("p_steady", units, "kPa"), 1, std::vector<double>(m.mesh.nodes.size(), 0.0)};
    for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n)
      a.values[n] = m.water.pressure(m.mesh.nodes[n].x(), m.mesh.nodes[n].y());
    out.point_fields.push_back(std::move(a));
  }
}

/// The arrays of the materials' named history components (empty) and, per domain, the history
/// slot of each array's name (-1: none).
void history_fields(const Model& m, const Units& units, std::vector<OutputArray>& ip_history,
                    std::vector<std::vector<int>>& history_index) {
  for (std::size_t d = 0; d < m.domains.size(); ++d) {
    if (!m.domains[d].law.material) continue;
    const auto names = m.domains[d].law.material->history_names();
    const auto n =
        std::min<std::size_t>(names.size(), static_cast<std::size_t>(m.domains[d].states.history_size()));
    for (std::size_t k = 0; k < n; ++k) {
      const std::string name = history_name(names[k], units);
      std::size_t f = 0;
      while (f < ip_history.size() && ip_history[f].name != name) ++f;
      if (f == ip_history.size()) ip_history.push_back(OutputArray{name, 1, {}});
      for (auto& idx : history_index) idx.resize(ip_history.size(), -1);
      history_index[d][f] = static_cast<int>(k);
    }
  }
}

/// A model with pore water anywhere: a phreatic level, a pore-pressure field or an undrained domain.
bool has_pore_water(const Model& m) {
  return m.water.present() || m.dofs.field("p") >= 0 ||
         std::any_of(m.domains.begin(), m.domains.end(),
                     [](const Domain& d) { return d.drainage == "undrained"; });
}

} // namespace

void write_step(VtkSeriesWriter& w, const RunView& run) {
  const Model& m = run.model;
  const RunState& state = run.state;
  const scene::Settings& settings = run.settings;
  const Units& units = run.units;
  OutputStep out;
  out.time = state.time;
  out.mesh = &m.mesh;
  out.texts = {{"stage", state.stage_name}};
  // Other units than kN, m: named in the field data (kN, m writes what it always wrote).
  if (!units.is_default()) out.texts.push_back({"units", units.describe()});
  out.values = {{"stage_number", state.stage_number}, {"step", state.stage_step}, {"load_factor", m.lambda}};
  // The pile head's load and settlement, in a scene that loads one (NaN before its stage).
  if (settings.pile_head) {
    out.values.push_back({units.column("head_load", force_unit(m)), state.head_load});
    out.values.push_back({"head_settlement_" + units.small_length(), state.head_settlement});
  }
  // Every load of the stage: the fraction of its full value applied now and its vertical
  // resultant (y up; 0 for a pressure on a vertical wall), named after the load.
  for (const auto& l : state.stage_loads) {
    const double fraction = l.ramp == 0 ? 1.0 : (l.ramp > 0 ? m.lambda : 1.0 - m.lambda);
    out.values.push_back({"load." + l.name + ".fraction", fraction});
    out.values.push_back({"load." + l.name + "." + units.column("Fy", force_unit(m)), fraction * l.fy});
  }
  add_node_fields(m, units, out);
  const std::vector<std::string> voigt{"xx", "yy", "zz", "xy", "yz", "zx"};
  const std::string stress_name = with_unit("stress", units, "kPa");
  OutputArray stress{stress_name, 6, {}, voigt}, set_id{"set_id", 1, {}};
  OutputArray ip_stress{stress_name, 6, {}, voigt}, ip_strain{with_unit("strain", units, "-"), 6, {}, voigt},
      ip_plastic{"plastic", 1, {}};
  // Named history components (Material::history_names()): one scalar field per name over all
  // integration points; NaN where a domain's material has no component of that name.
  std::vector<OutputArray> ip_history;
  std::vector<std::vector<int>> history_index(m.domains.size()); // field -> history slot, per domain
  if (settings.ip_output) history_fields(m, units, ip_history, history_index);
  // The pore water at the points, in a model that has any (output/recorders.hpp, PointWater).
  const bool water = settings.ip_output && has_pore_water(m);
  OutputArray ip_p{with_unit("pore_pressure", units, "kPa"), 1, {}},
      ip_excess{with_unit("excess_pore_pressure", units, "kPa"), 1, {}},
      ip_effective{with_unit("effective_stress", units, "kPa"), 6, {}, voigt},
      ip_total{with_unit("total_stress", units, "kPa"), 6, {}, voigt};
  std::vector<PointWater> point_w;
  std::size_t total_points = 0;
  for (const auto& dm : m.domains)
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci)
      if (m.is_active(dm.cells[ci])) total_points += dm.first_point[ci + 1] - dm.first_point[ci];
  out.ip_coords.resize(static_cast<Eigen::Index>(settings.ip_output ? total_points : 0), 2);
  Eigen::Index row = 0;
  std::vector<int> nodes;
  Eigen::MatrixXd x, xp;
  Eigen::VectorXd wts;
  for (std::size_t d = 0; d < m.domains.size(); ++d)
    for (std::size_t ci = 0; ci < m.domains[d].cells.size(); ++ci) {
      const auto& dm = m.domains[d];
      const int c = dm.cells[ci];
      if (!m.is_active(c)) continue; // removed (bored) or not yet placed
      out.cells.push_back(c);
      m.cell_nodes(c, nodes, x);
      ElementData data = m.element_data(c, x);
      dm.element->point_weights(data, wts);
      Vec6 avg = Vec6::Zero();
      for (std::size_t p = dm.first_point[ci]; p < dm.first_point[ci + 1]; ++p) {
        const auto slot = dm.states.committed(p);
        avg += wts[static_cast<Eigen::Index>(p - dm.first_point[ci])] * slot.stress();
        if (settings.ip_output) {
          for (int k = 0; k < 6; ++k) {
            ip_stress.values.push_back(slot.stress()[k]);
            ip_strain.values.push_back(slot.strain()[k]);
          }
          ip_plastic.values.push_back(
              dm.law.material ? dm.law.material->point_status(slot.stress(), slot.history()) : -1.0);
          for (std::size_t f = 0; f < ip_history.size(); ++f) {
            const int k = history_index[d].empty() ? -1 : history_index[d][f];
            ip_history[f].values.push_back(k >= 0 ? slot.history()[static_cast<std::size_t>(k)]
                                                  : std::numeric_limits<double>::quiet_NaN());
          }
        }
      }
      if (water) {
        point_water(m, dm, ci, point_w);
        for (const PointWater& pw : point_w) {
          ip_p.values.push_back(pw.p_steady + pw.p_excess);
          ip_excess.values.push_back(pw.p_excess);
          for (int k = 0; k < 6; ++k) {
            ip_effective.values.push_back(pw.effective[k]);
            ip_total.values.push_back(pw.total[k]);
          }
        }
      }
      for (int k = 0; k < 6; ++k) stress.values.push_back(avg[k]);
      set_id.values.push_back(dm.set_id);
      if (settings.ip_output) {
        dm.element->point_coordinates(data, xp);
        out.ip_coords.middleRows(row, xp.rows()) = xp;
        row += xp.rows();
      }
    }
  out.cell_fields = {std::move(stress), std::move(set_id)};
  if (settings.ip_output) out.ip_fields = {std::move(ip_stress), std::move(ip_strain), std::move(ip_plastic)};
  for (auto& f : ip_history) out.ip_fields.push_back(std::move(f));
  if (water)
    for (auto* f : {&ip_p, &ip_excess, &ip_effective, &ip_total}) out.ip_fields.push_back(std::move(*f));
  add_status_names(m, out, settings.ip_output); // "domain", "domains", "plastic_regimes_<domain>"
  if (settings.ip_output && !run.interfaces.interfaces.empty())
    append_interface_fields(m, with_unit("interface_traction", units, "kPa"),
                            with_unit("interface_jump", units, "m"), out.ip_fields);
  w.write(out);
  for (const auto& itf : run.interfaces.interfaces)
    if (itf.csv)
      write_interface_csv(
          interface_points(m, m.domains[itf.domain]),
          (fs::path(run.out_dir) / (fs::path(run.scene_path).stem().string() + "_" + itf.name + "_" +
                                    std::to_string(w.steps_written() - 1) + ".csv"))
              .string());
}

} // namespace stratum
