#include "stratum/registry.hpp"
#include "stratum/enum_names.hpp"

#include "suggest.hpp"

namespace stratum {

const char* to_string(PluginKind k) {
  static constexpr std::array<const char*, 7> names{"material",     "element",        "contact_law", "solver",
                                                    "stage_action", "mesh_generator", "calibration"};
  return enum_name(k, names);
}

bool plugin_kind_from_string(const std::string& s, PluginKind& kind) {
  for (PluginKind k : all_plugin_kinds)
    if (s == to_string(k)) {
      kind = k;
      return true;
    }
  return false;
}

template <class T>
void Registry::add_to(std::map<std::string, Factory<T>>& m, PluginKind kind, Factory<T> f) {
  if (f.name.empty())
    throw Error(current_library_ + ": a " + std::string(to_string(kind)) + " factory has no name");
  if (!f.create)
    throw Error(current_library_ + ": " + to_string(kind) + " '" + f.name + "' has no create function");
  auto it = m.find(f.name);
  if (it != m.end())
    throw Error(std::string("duplicate ") + to_string(kind) + " '" + f.name + "': registered by " +
                it->second.library + " and again by " + current_library_);
  f.library = current_library_;
  std::string name = f.name;
  m.emplace(std::move(name), std::move(f));
}

template <class T>
const Factory<T>& Registry::find(const std::map<std::string, Factory<T>>& m, PluginKind kind,
                                 const std::string& name) const {
  auto it = m.find(name);
  if (it != m.end()) return it->second;
  std::string known;
  for (const auto& [n, f] : m) known += (known.empty() ? "" : ", ") + n;
  throw Error(std::string("unknown ") + to_string(kind) + " '" + name +
              "'; known: " + (known.empty() ? "(none)" : known) + unknown_hint + did_you_mean(name, m));
}

template void Registry::add_to(std::map<std::string, Factory<Material>>&, PluginKind, Factory<Material>);
template void Registry::add_to(std::map<std::string, Factory<Element>>&, PluginKind, Factory<Element>);
template void Registry::add_to(std::map<std::string, Factory<ContactLaw>>&, PluginKind, Factory<ContactLaw>);
template void Registry::add_to(std::map<std::string, Factory<Solver>>&, PluginKind, Factory<Solver>);
template void Registry::add_to(std::map<std::string, Factory<StageAction>>&, PluginKind,
                               Factory<StageAction>);
template const Factory<StageAction>& Registry::find(const std::map<std::string, Factory<StageAction>>&,
                                                    PluginKind, const std::string&) const;
template void Registry::add_to(std::map<std::string, Factory<MeshGenerator>>&, PluginKind,
                               Factory<MeshGenerator>);
template const Factory<MeshGenerator>& Registry::find(const std::map<std::string, Factory<MeshGenerator>>&,
                                                      PluginKind, const std::string&) const;
template void Registry::add_to(std::map<std::string, Factory<Calibration>>&, PluginKind,
                               Factory<Calibration>);
template const Factory<Calibration>& Registry::find(const std::map<std::string, Factory<Calibration>>&,
                                                    PluginKind, const std::string&) const;
template const Factory<Material>& Registry::find(const std::map<std::string, Factory<Material>>&, PluginKind,
                                                 const std::string&) const;
template const Factory<Element>& Registry::find(const std::map<std::string, Factory<Element>>&, PluginKind,
                                                const std::string&) const;
template const Factory<ContactLaw>& Registry::find(const std::map<std::string, Factory<ContactLaw>>&,
                                                   PluginKind, const std::string&) const;
template const Factory<Solver>& Registry::find(const std::map<std::string, Factory<Solver>>&, PluginKind,
                                               const std::string&) const;

namespace {
template <class T> std::vector<std::string> keys(const std::map<std::string, Factory<T>>& m) {
  std::vector<std::string> v;
  for (const auto& [n, f] : m) v.push_back(n);
  return v;
}
} // namespace

bool Registry::has(PluginKind kind, const std::string& name) const {
  switch (kind) {
  case PluginKind::material:
    return materials_.count(name) != 0;
  case PluginKind::element:
    return elements_.count(name) != 0;
  case PluginKind::contact_law:
    return contact_laws_.count(name) != 0;
  case PluginKind::solver:
    return solvers_.count(name) != 0;
  case PluginKind::stage_action:
    return stage_actions_.count(name) != 0;
  case PluginKind::mesh_generator:
    return mesh_generators_.count(name) != 0;
  case PluginKind::calibration:
    return calibrations_.count(name) != 0;
  }
  return false;
}

std::vector<std::string> Registry::names(PluginKind kind) const {
  switch (kind) {
  case PluginKind::material:
    return keys(materials_);
  case PluginKind::element:
    return keys(elements_);
  case PluginKind::contact_law:
    return keys(contact_laws_);
  case PluginKind::solver:
    return keys(solvers_);
  case PluginKind::stage_action:
    return keys(stage_actions_);
  case PluginKind::mesh_generator:
    return keys(mesh_generators_);
  case PluginKind::calibration:
    return keys(calibrations_);
  }
  return {};
}

const Schema& Registry::schema(PluginKind kind, const std::string& name, std::string* summary,
                               std::string* library) const {
  auto fill = [&](const auto& f) -> const Schema& {
    if (summary) *summary = f.summary;
    if (library) *library = f.library;
    return f.schema;
  };
  switch (kind) {
  case PluginKind::material:
    return fill(material(name));
  case PluginKind::element:
    return fill(element(name));
  case PluginKind::contact_law:
    return fill(contact_law(name));
  case PluginKind::solver:
    return fill(solver(name));
  case PluginKind::stage_action:
    return fill(stage_action(name));
  case PluginKind::mesh_generator:
    return fill(mesh_generator(name));
  case PluginKind::calibration:
    return fill(calibration(name));
  }
  throw Error("unknown plugin kind");
}

} // namespace stratum
