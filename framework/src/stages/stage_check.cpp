// StageCheck: the checks a stage action makes against the scene when it is read.
#include "stratum/stage_action.hpp"
#include "suggest.hpp"

namespace stratum {

namespace {

template <class Sets>
void require_set(const StageCheck& scene, const Params& p, const std::string& key, const Sets& sets,
                 const char* what) {
  const std::string& name = p.text(key);
  if (sets.count(name)) return;
  throw Error(p.where(key).known() ? p.where(key) : scene.where,
              scene.context + " " + key + " = \"" + name + "\" is not " + what +
                  " of the mesh; known: " + key_list(sets, name));
}

} // namespace

void StageCheck::require_cell_set(const Params& p, const std::string& key) const {
  require_set(*this, p, key, mesh.cell_sets, "a cell set");
}

void StageCheck::require_node_set(const Params& p, const std::string& key) const {
  require_set(*this, p, key, mesh.node_sets, "a node set");
}

void StageCheck::require_edge_set(const Params& p, const std::string& key) const {
  require_set(*this, p, key, mesh.edge_sets, "an edge set");
}

void StageCheck::add_load_name(const std::string& name) const {
  if (!load_names.insert(name).second)
    throw Error(where, context + " adds a load named \"" + name +
                           "\", which is already applied; remove it first or choose another name");
}

} // namespace stratum
