// The plugin objects of a scene's contact laws and interfaces, as built (internal to the framework).
#pragma once

#include "stratum/contact_law.hpp"
#include "stratum/element.hpp"
#include "stratum/model.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/registry.hpp"
#include "stratum/units.hpp"

#include <toml++/toml.h>

#include <memory>
#include <string>
#include <vector>

namespace stratum {

/// The contact laws, interface element kinds and named interfaces of a scene.
struct SceneInterfaces {
  struct Named {
    std::string name;
    std::size_t domain = 0; ///< index into Model::domains
    bool csv = true;        ///< write <stem>_<name>_<step>.csv with every output step
  };
  std::vector<std::unique_ptr<ContactLaw>> laws;
  std::vector<std::unique_ptr<Element>> elements;
  std::vector<Named> interfaces;
};

namespace scene {
struct Scene;
}

/// Creates the contact laws, splits the mesh along every [[interfaces]] entry (see
/// split_interface) and appends one Domain per interface to the model. Call after the
/// [[domains]] are built and before the constraints (the node sets <name>.side1/.side2
/// exist afterwards). Throws Error with file:line:col when a set the scene names is not in the
/// mesh or an element does not fit the interface cells.
void build_scene_interfaces(const scene::Scene& scene, Model& model, SceneInterfaces& out);

} // namespace stratum
