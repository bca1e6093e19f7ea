// The plugin registry: factories by kind and name, each with its schema.
//
// A Registry is an object handed to every plugin's entry point; there is no
// global registry. Factories remember which library registered them, so a
// duplicate name can name both libraries.
#pragma once

#include "stratum/calibration.hpp"
#include "stratum/contact_law.hpp"
#include "stratum/element.hpp"
#include "stratum/material.hpp"
#include "stratum/mesh_generator.hpp"
#include "stratum/params.hpp"
#include "stratum/solver.hpp"
#include "stratum/stage_action.hpp"

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

namespace stratum {

enum class PluginKind { material, element, contact_law, solver, stage_action, mesh_generator, calibration };
[[nodiscard]] const char* to_string(PluginKind k);
/// Every kind, in the order of the enum (manifest lines and `stratum plugins` use these names).
inline constexpr PluginKind all_plugin_kinds[] = {
    PluginKind::material,     PluginKind::element,        PluginKind::contact_law, PluginKind::solver,
    PluginKind::stage_action, PluginKind::mesh_generator, PluginKind::calibration};
/// The kind whose name is `s` ("material", "stage_action", ...); false when there is none.
bool plugin_kind_from_string(const std::string& s, PluginKind& kind);

template <class T> struct Factory {
  std::string name;
  std::string summary; ///< one line: what it is
  Schema schema;
  std::function<std::unique_ptr<T>(const Params&)> create;
  std::string library; ///< filled in by the registry
};

class Registry {
public:
  void add(Factory<Material> f) { add_to(materials_, PluginKind::material, std::move(f)); }
  void add(Factory<Element> f) { add_to(elements_, PluginKind::element, std::move(f)); }
  void add(Factory<ContactLaw> f) { add_to(contact_laws_, PluginKind::contact_law, std::move(f)); }
  void add(Factory<Solver> f) { add_to(solvers_, PluginKind::solver, std::move(f)); }
  void add(Factory<StageAction> f) { add_to(stage_actions_, PluginKind::stage_action, std::move(f)); }
  void add(Factory<MeshGenerator> f) { add_to(mesh_generators_, PluginKind::mesh_generator, std::move(f)); }
  void add(Factory<Calibration> f) { add_to(calibrations_, PluginKind::calibration, std::move(f)); }

  /// Lookups throw Error listing the known names of that kind.
  [[nodiscard]] const Factory<Material>& material(const std::string& name) const {
    return find(materials_, PluginKind::material, name);
  }
  [[nodiscard]] const Factory<Element>& element(const std::string& name) const {
    return find(elements_, PluginKind::element, name);
  }
  [[nodiscard]] const Factory<ContactLaw>& contact_law(const std::string& name) const {
    return find(contact_laws_, PluginKind::contact_law, name);
  }
  [[nodiscard]] const Factory<Solver>& solver(const std::string& name) const {
    return find(solvers_, PluginKind::solver, name);
  }

  [[nodiscard]] const Factory<StageAction>& stage_action(const std::string& name) const {
    return find(stage_actions_, PluginKind::stage_action, name);
  }
  [[nodiscard]] const Factory<MeshGenerator>& mesh_generator(const std::string& name) const {
    return find(mesh_generators_, PluginKind::mesh_generator, name);
  }
  /// A calibration target (`stratum fit NAME`).
  [[nodiscard]] const Factory<Calibration>& calibration(const std::string& name) const {
    return find(calibrations_, PluginKind::calibration, name);
  }
  /// The same lookups by the plugin's interface type: factory<Material>(name), ...
  template <class T> [[nodiscard]] const Factory<T>& factory(const std::string& name) const;

  [[nodiscard]] bool has(PluginKind kind, const std::string& name) const;
  [[nodiscard]] std::vector<std::string> names(PluginKind kind) const;
  /// Schema and summary of any factory (for `stratum plugins --describe`).
  [[nodiscard]] const Schema& schema(PluginKind kind, const std::string& name, std::string* summary = nullptr,
                                     std::string* library = nullptr) const;

  /// The library whose entry point is running (set by the loader around stratum_register).
  void set_current_library(std::string path) { current_library_ = std::move(path); }

  /// Extra text appended to "unknown name" messages (e.g. the plugin search path).
  std::string unknown_hint;

private:
  template <class T> void add_to(std::map<std::string, Factory<T>>& m, PluginKind kind, Factory<T> f);
  template <class T>
  const Factory<T>& find(const std::map<std::string, Factory<T>>& m, PluginKind kind,
                         const std::string& name) const;

  std::map<std::string, Factory<Material>> materials_;
  std::map<std::string, Factory<Element>> elements_;
  std::map<std::string, Factory<ContactLaw>> contact_laws_;
  std::map<std::string, Factory<Solver>> solvers_;
  std::map<std::string, Factory<StageAction>> stage_actions_;
  std::map<std::string, Factory<MeshGenerator>> mesh_generators_;
  std::map<std::string, Factory<Calibration>> calibrations_;
  std::string current_library_ = "(built in)";
};

/// The kind of a plugin interface type: plugin_kind_of<Material>() == PluginKind::material.
template <class T> constexpr PluginKind plugin_kind_of() {
  if constexpr (std::is_same_v<T, Material>)
    return PluginKind::material;
  else if constexpr (std::is_same_v<T, Element>)
    return PluginKind::element;
  else if constexpr (std::is_same_v<T, ContactLaw>)
    return PluginKind::contact_law;
  else if constexpr (std::is_same_v<T, Solver>)
    return PluginKind::solver;
  else if constexpr (std::is_same_v<T, StageAction>)
    return PluginKind::stage_action;
  else if constexpr (std::is_same_v<T, Calibration>)
    return PluginKind::calibration;
  else {
    static_assert(std::is_same_v<T, MeshGenerator>, "not a plugin interface");
    return PluginKind::mesh_generator;
  }
}

template <class T> const Factory<T>& Registry::factory(const std::string& name) const {
  if constexpr (std::is_same_v<T, Material>)
    return material(name);
  else if constexpr (std::is_same_v<T, Element>)
    return element(name);
  else if constexpr (std::is_same_v<T, ContactLaw>)
    return contact_law(name);
  else if constexpr (std::is_same_v<T, Solver>)
    return solver(name);
  else if constexpr (std::is_same_v<T, StageAction>)
    return stage_action(name);
  else if constexpr (std::is_same_v<T, Calibration>)
    return calibration(name);
  else
    return mesh_generator(name);
}

} // namespace stratum
