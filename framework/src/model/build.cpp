// SceneModel::build: the order of building, and the fingerprint a checkpoint must match.
#include "model/scene_model.hpp"

#include "model/body_interfaces.hpp"

#include <sstream>

namespace stratum {

void SceneModel::build(scene::Scene& sc) {
  title = sc.title;
  units = sc.units;
  settings = sc.settings;
  model.formulation = settings.formulation;
  solver_factory = sc.solver.factory;
  solver_params = sc.solver.params;
  // Creating one checks the parameters now; each stage creates its own (run/run_stage.cpp).
  (void)sc.solver.create();

  build_mesh(sc);
  build_domains(sc);
  build_scene_interfaces(sc, model, interfaces);
  build_constraints(sc);
  build_stages(sc);
  rehearse_stages();

  // What a checkpoint must match: mesh size, domain layout, stage names.
  std::ostringstream fp;
  fp << "nodes " << model.mesh.nodes.size() << " cells " << model.mesh.cells.size();
  for (const auto& dm : model.domains)
    fp << " domain " << dm.name << ':' << dm.states.points() << 'x' << dm.states.stride();
  // The unknowns when the scene has fields besides the displacement (a checkpoint of a
  // displacement-only scene keeps the fingerprint it had before fields existed).
  if (model.dofs.fields.size() > static_cast<std::size_t>(model.dim()))
    fp << " fields " << model.dofs.field_list() << " unknowns " << model.dofs.total();
  fp << " stages";
  for (const auto& st : stages) fp << ' ' << st.name;
  fingerprint = fp.str();
  parts = std::move(sc.parts);
  for (auto& part : parts)
    if (part.name == mesh_part_name) part.digest = mesh_digest(model.mesh);
}

void SceneModel::add_library_parts() {
  if (library_parts_added_) return;
  for (auto& part : library_parts(catalog->opened())) parts.push_back(std::move(part));
  library_parts_added_ = true;
}

} // namespace stratum
