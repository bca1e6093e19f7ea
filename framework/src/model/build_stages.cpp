// [[stages]] built: each stage's actions created and checked against the mesh, in the scene's order.
#include "model/scene_model.hpp"

#include "stratum/stage_action.hpp"
#include "suggest.hpp"

#include <set>

namespace stratum {

void SceneModel::build_stages(scene::Scene& sc) {
  const auto ndof = static_cast<Eigen::Index>(model.dofs.total());
  initial_prescribed = model.prescribed;
  model.prescribed_base = Eigen::VectorXd::Zero(ndof);
  model.load_base = Eigen::VectorXd::Zero(ndof);
  model.load_ref = Eigen::VectorXd::Zero(ndof);
  // The actions are created and checked against the mesh in the scene's order: the loads a
  // stage names must have been applied by an earlier action.
  std::set<std::string> load_names;
  for (auto& spec : sc.stages) {
    stage::Stage st = std::move(spec.settings);
    if (!st.monitor.empty() && !model.mesh.node_sets.count(st.monitor))
      throw Error(spec.monitor_at,
                  "[[stages]] #" + std::to_string(stages.size() + 1) + " monitor = \"" + st.monitor +
                      "\" is not a node or edge set of the mesh; known: " + key_list(model.mesh.node_sets));
    for (const auto& a : spec.actions) {
      auto action = a.plugin.create();
      StageCheck check{model.mesh,          a.context, a.at,           load_names,
                       a.default_load_name, false,     &model.domains, &material_by_name};
      action->check(check);
      st.reset_after = st.reset_after || check.reset_after;
      st.actions.push_back(std::move(action));
    }
    stages.push_back(std::move(st));
  }
}

} // namespace stratum
