// `stratum plugins` and `stratum describe` (framework/cli/info.hpp).
#include "info.hpp"

#include "scene/reference.hpp"
#include "stratum/analysis.hpp"
#include "stratum/plugin.hpp"
#include "stratum/plugin_loader.hpp"
#include "suggest.hpp"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace stratum::cli {

namespace {

constexpr const char* plugins_help_text =
    "usage: stratum plugins                   one line per plugin: kind, name, summary\n"
    "       stratum plugins --describe NAME   one plugin in full: library, every parameter with\n"
    "                                         its type, unit, range, default and meaning (every\n"
    "                                         kind of that name, e.g. a material and its calibration)\n"
    "       stratum plugins --describe        (or --all) every plugin in full\n"
    "       stratum plugins --paths           the folders searched for plugins, one a line, in order\n"
    "\n"
    "Plugins are found on STRATUM_PLUGIN_PATH, then in the program's own plugin folder: an\n"
    "installed stratum searches <prefix>/lib/stratum/plugins, never the build tree it came from.\n"
    "A scene's [plugins] path comes before both.\n"
    "The framework's own stage actions and mesh generators are listed with them (library \"(built in)\").\n"
    "\n"
    "options:\n"
    "  --scene FILE  with --describe: units, defaults and bounds in that scene's [units]\n"
    "                (p_a = 100 kPa reads 0.1 MPa in an N, mm scene; stratum describe units)\n"
    "  -h, --help    this text\n"
    "\n"
    "exit status: 0 listed, 1 unknown plugin name or a plugin library that cannot be opened,\n"
    "  3 internal error\n";

constexpr const char* describe_help_text =
    "usage: stratum describe              the sections of a scene file, one line each\n"
    "       stratum describe SECTION      one section in full: every key with its type, unit,\n"
    "                                     allowed values, default (or required) and meaning; for\n"
    "                                     [solver], [mesh.<generator>] and [[stages.actions]] the keys\n"
    "                                     of each solver, generator and action type\n"
    "       stratum describe --markdown   the whole reference as Markdown (docs/scene-reference.md)\n"
    "\n"
    "SECTION is a name from the list, e.g. analysis, mesh.blocks, stages.actions, output.history,\n"
    "with or without its brackets. The keys are those the scene reader checks the tables against.\n"
    "Materials, elements and contact laws are plugins: stratum plugins --describe NAME.\n"
    "\n"
    "options:\n"
    "  -h, --help   this text\n"
    "\n"
    "exit status: 0 described, 1 unknown section (with the known ones), 3 internal error\n";

constexpr PluginKind kinds[] = {PluginKind::element,    PluginKind::material,     PluginKind::contact_law,
                                PluginKind::solver,     PluginKind::stage_action, PluginKind::mesh_generator,
                                PluginKind::calibration};

/// The unknowns an element's nodes carry, per cell type it accepts (Element::node_fields), for
/// an element that its parameters' defaults create.
void describe_fields(const Registry& reg, const std::string& name, const Units& units) {
  const Schema& s = reg.schema(PluginKind::element, name);
  Params p;
  for (const auto& spec : s.specs())
    if (spec.fallback) p.set(spec.name, *spec.fallback);
  std::unique_ptr<Element> element;
  try {
    element = reg.element(name).create(p);
  } catch (const Error&) {
  }
  if (!element) return;
  std::cout << "  unknowns of its nodes (constraints, recorders and VTK arrays name them):\n";
  for (int t = 0; t <= static_cast<int>(CellType::wedge); ++t) {
    const auto type = static_cast<CellType>(t);
    if (!element->accepts(type)) continue;
    const NodeFields nf = element->node_fields(type, corner_slots(type));
    std::cout << "    " << to_string(type) << ":";
    for (std::size_t f = 0; f < nf.fields.size(); ++f) {
      const Field& field = nf.fields[f];
      bool everywhere = true;
      for (std::size_t i = 0; i < nf.carried.size(); ++i)
        everywhere = everywhere && (nf.carried[i] >> f & 1u);
      std::cout << (f ? ", " : " ") << field.name << " [" << units.label(field.unit) << "; reaction "
                << units.label(field.reaction_unit) << "]" << (everywhere ? "" : " (on some nodes)");
    }
    std::cout << "\n";
  }
}

void describe(const Registry& reg, PluginKind kind, const std::string& name, bool full,
              const Units& units = {}) {
  std::string summary, library;
  const Schema& s = reg.schema(kind, name, &summary, &library);
  std::cout << to_string(kind) << " " << name << ": " << summary << "\n";
  if (full) std::cout << "  library: " << library << "\n";
  if (!units.is_default())
    std::cout << "  (in [units] " << units.describe()
              << ": units, defaults and bounds as the scene reads them)\n";
  write_schema(std::cout, s, units);
  if (full && kind == PluginKind::element) describe_fields(reg, name, units);
}

} // namespace

std::string plugins_help() { return plugins_help_text; }
std::string describe_help() { return describe_help_text; }

int plugins(std::vector<std::string> args) {
  // --scene FILE: units, defaults and bounds in that scene's [units] (stratum/units.hpp).
  Units units;
  if (const auto at = std::find(args.begin(), args.end(), "--scene"); at != args.end()) {
    if (at + 1 == args.end()) throw Error("plugins: --scene needs a scene file (see stratum plugins --help)");
    units = scene_units(*(at + 1));
    args.erase(at, at + 2);
  }
  const bool all = args.size() == 1 && (args[0] == "--describe" || args[0] == "--all");
  const bool one = args.size() == 2 && args[0] == "--describe";
  if (args.size() == 1 && args[0] == "--paths") {
    for (const auto& d : PluginCatalog::default_directories()) std::cout << d << "\n";
    return 0;
  }
  if (!args.empty() && !all && !one)
    throw Error("plugins: unexpected argument" + std::string(args.size() > 2 ? "s" : "") + " '" + args[0] +
                (args.size() > 1 ? " " + args[1] + (args.size() > 2 ? " ..." : "") : "") +
                "'; allowed: --describe [NAME], --all, --paths (see stratum plugins --help)");
  PluginCatalog catalog(PluginCatalog::default_directories());
  Registry reg;
  register_builtin_factories(reg); // the framework's own stage actions and mesh generators
  catalog.require_all(reg);
  if (one) {
    // One name may be several plugins, e.g. the duncan_chang material and its calibration
    // target: each in full, separated by a blank line.
    bool found = false;
    for (PluginKind k : kinds)
      if (reg.has(k, args[1])) {
        if (found) std::cout << "\n";
        describe(reg, k, args[1], true, units);
        found = true;
      }
    if (found) return 0;
    std::string known;
    std::vector<std::string> names;
    for (PluginKind k : kinds)
      for (const auto& n : reg.names(k)) {
        known += (known.empty() ? "" : ", ") + n;
        names.push_back(n);
      }
    throw Error("unknown plugin '" + args[1] + "'; known: " + known + did_you_mean(args[1], names));
  }
  if (all) {
    for (PluginKind k : kinds)
      for (const auto& n : reg.names(k)) describe(reg, k, n, false, units);
    return 0;
  }
  // The short list: one line per plugin; the summary is the first line of the plugin's own.
  std::size_t width = 0;
  std::size_t kind_width = 0; // "stage_action" is 12 characters: one more for the space
  for (PluginKind k : kinds) {
    kind_width = std::max(kind_width, std::string(to_string(k)).size() + 1);
    for (const auto& n : reg.names(k)) width = std::max(width, n.size());
  }
  for (PluginKind k : kinds)
    for (const auto& n : reg.names(k)) {
      std::string summary;
      static_cast<void>(reg.schema(k, n, &summary));
      summary = summary.substr(0, summary.find('\n'));
      std::cout << std::left << std::setw(static_cast<int>(kind_width)) << to_string(k)
                << std::setw(static_cast<int>(width) + 2) << n << summary << "\n";
    }
  return 0;
}

/// `stratum describe [SECTION | --markdown]`: the scene format's reference (scene_reference.hpp).
int describe_scene(const std::vector<std::string>& args) {
  if (args.size() > 1)
    throw Error("describe: give one section at most (got '" + args[0] + "', '" + args[1] +
                "', ...); see stratum describe --help");
  if (args.empty()) {
    list_scene_sections(std::cout);
    std::cout << "(stratum describe SECTION: the keys of one section)\n";
    return 0;
  }
  if (args[0].size() > 1 && args[0][0] == '-' && args[0] != "--markdown")
    throw Error("describe: unknown option '" + args[0] + "'; allowed: --markdown, --help" +
                did_you_mean(args[0], std::vector<std::string_view>{"--markdown", "--help"}));
  // The registry as a scene sees it: the framework's stage actions and mesh generators, and
  // every plugin found (the solvers, the plugins' actions and generators).
  PluginCatalog catalog(PluginCatalog::default_directories());
  Registry reg;
  register_builtin_factories(reg);
  catalog.require_all(reg);
  std::ostringstream out; // nothing printed before the whole text is made
  if (args[0] == "--markdown")
    write_scene_reference_markdown(out, reg);
  else
    describe_scene_section(out, reg, args[0]);
  std::cout << out.str();
  return 0;
}

} // namespace stratum::cli
