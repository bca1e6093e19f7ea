// `stratum describe`: the scene format's reference, printed from the schemas the reader checks
// the tables against (scene/schemas.cpp) and from the registry's factories.
#include "scene/reference.hpp"

#include "meshers/builtin_generators.hpp"
#include "scene/recorder_spec.hpp"
#include "scene/schemas.hpp"
#include "stratum/mesh_generator.hpp"
#include "suggest.hpp"

#include <iomanip>
#include <ostream>
#include <sstream>

namespace stratum {

std::string default_text(const ParamSpec& p) {
  if (!p.fallback) return "";
  if (!p.default_note.empty()) return p.default_note;
  std::ostringstream d;
  std::visit(
      [&](const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::vector<double>>) {
          d << "[";
          for (std::size_t i = 0; i < v.size(); ++i) d << (i ? ", " : "") << v[i];
          d << "]";
        } else if constexpr (std::is_same_v<T, bool>) {
          d << (v ? "true" : "false");
        } else if constexpr (std::is_same_v<T, std::string>) {
          d << '"' << v << '"';
        } else {
          d << v;
        }
      },
      *p.fallback);
  return d.str();
}

void write_schema(std::ostream& out, const Schema& s) { write_schema(out, s, Units{}); }

void write_schema(std::ostream& out, const Schema& s, const Units& units) {
  for (const auto& declared : s.specs()) {
    const ParamSpec p = spec_in_units(declared, units);
    out << "  " << std::left << std::setw(18) << p.name << " " << std::setw(8) << to_string(p.type) << " "
        << std::setw(7) << (p.unit.empty() ? "-" : p.unit) << " " << p.allowed();
    if (p.fallback)
      out << ", default " << default_text(p);
    else
      out << ", required";
    out << "\n      " << p.meaning << "\n";
  }
}

namespace {

/// One table of keys: a section's own, or one variant (a solver, a generator, an action type).
struct Block {
  std::string title;   ///< empty: the section's own keys; else e.g. `type = "geostatic"`
  std::string summary; ///< for a variant: the factory's summary
  Schema schema;
  std::vector<scene::OtherKey> other;
  std::vector<std::string> notes;
};

struct Section {
  SceneSectionInfo info;
  std::vector<std::string> notes; ///< paragraphs after the summary
  std::vector<Block> blocks;
};

Block own(Schema s, std::vector<scene::OtherKey> other = {}) {
  return Block{"", "", std::move(s), std::move(other), {}};
}
Block own(scene::TableKeys k) { return own(std::move(k.schema), std::move(k.other)); }

template <class T> T fallback_of(const Schema& s, const std::string& name) {
  return std::get<T>(*s.find(name)->fallback);
}

/// The blocks of every registered factory of `kind`; `title` makes the block's title from the name.
template <class F> std::vector<Block> variants(const Registry& reg, PluginKind kind, F title) {
  std::vector<Block> v;
  for (const auto& n : reg.names(kind)) {
    std::string summary;
    const Schema& s = reg.schema(kind, n, &summary);
    v.push_back(Block{title(n), summary.substr(0, summary.find('\n')), s, {}, {}});
  }
  return v;
}

/// The sets a mesh generator defines with its default parameters (when all have defaults): generated
/// here, so that the list is the generator's own. Empty when it cannot be generated so.
std::vector<std::string> generator_sets(const Registry& reg, const std::string& name) {
  const auto& f = reg.factory<MeshGenerator>(name);
  Params p;
  for (const auto& s : f.schema.specs()) {
    if (!s.fallback) return {};
    p.set(s.name, *s.fallback);
  }
  Mesh mesh;
  try {
    mesh = f.create(p)->generate(MeshRequest{});
  } catch (const Error&) {
    return {};
  }
  const auto names = [](const auto& sets, const std::map<std::string, std::vector<Edge>>* skip = nullptr) {
    std::string s;
    for (const auto& [n, v] : sets)
      if (!skip || !skip->count(n)) s += (s.empty() ? "" : ", ") + n;
    return s.empty() ? std::string("(none)") : s;
  };
  return {"cell sets: " + names(mesh.cell_sets), "edge sets (each also a node set): " + names(mesh.edge_sets),
          "other node sets: " + names(mesh.node_sets, &mesh.edge_sets)};
}

/// Appends a section (no blocks, no notes yet) and returns it.
Section& add_section(std::vector<Section>& out, std::string name, std::string header, std::string summary) {
  out.push_back(Section{{std::move(name), std::move(header), std::move(summary)}, {}, {}});
  return out.back();
}

/// The sections of the scene file itself: its top-level keys, include, [units].
void add_top_sections(std::vector<Section>& out) {
  const auto add = [&](std::string n, std::string h, std::string sm) -> Section& {
    return add_section(out, std::move(n), std::move(h), std::move(sm));
  };
  {
    auto& s =
        add("scene", "(top level)", "the keys at the top of a scene file: title, include and the sections");
    s.blocks.push_back(own(scene::top_keys()));
  }
  {
    auto& s = add("include", "include = ...",
                  "other scene files merged into this one (shared materials, a base scene)");
    s.notes = {
        "`include = \"file.toml\"` or `include = [\"a.toml\", \"b.toml\"]` at the top level, paths relative "
        "to the including file. The included files' tables are merged first, then this file's on top: "
        "tables merge key by key at any depth; a value this file sets replaces the included one; the same "
        "value in two included files, or an array of tables (such as [[stages]]) written both in an include "
        "and in the including file, is an error naming both places; includes nest, a cycle is an error. "
        "Includes nest at most 32 deep (the scene is depth 0), and one scene reads at most 1024 included "
        "files in all (a file counted as often as it is included). An included file must be a regular file "
        "(not a FIFO or a device such as /dev/zero) of at most 16 MB, as the scene file itself. "
        "File names written as values (a Gmsh mesh) stay relative to the file that is run."};
  }
  {
    auto& s = add("units", "[units]", "the scene's force and length units (default kN, m; stress kPa)");
    s.notes = {
        "The scene's numbers are read in its units and the results are written in them: nothing the scene "
        "writes is converted. What converts are the defaults of parameters, which plugins and the framework "
        "declare in kN, m, kPa (the units the reference shows): a default of a dimensional parameter "
        "(p_a = 100 kPa, gamma_w = 9.81 kN/m3, force_atol = 1e-10 kN) becomes its value in the scene's "
        "units (p_a = 0.1 in N, mm), and so do range bounds. `stratum plugins --describe NAME --scene "
        "FILE` shows a plugin's units and defaults in a scene's units. A plugin whose model holds "
        "numbers it cannot rescale refuses other units with a located error.",
        "Labels follow: CSV headers (load_N, depth_mm, shear_traction_MPa), the VTK field data "
        "(head_load_N, and a `units` string), the run's table and the check lines. Settlements and "
        "slips are tabulated in mm when length = \"m\" (x 1000), otherwise in the length unit itself."};
    s.blocks.push_back(own(scene::units_schema()));
  }
}

/// [analysis], [convergence] and [solver] (the solver plugins' variants with `reg`).
void add_analysis_sections(std::vector<Section>& out, const Registry* reg, const Schema& analysis) {
  const auto add = [&](std::string n, std::string h, std::string sm) -> Section& {
    return add_section(out, std::move(n), std::move(h), std::move(sm));
  };
  add("analysis", "[analysis]", "formulation, solver plugin, linear solver, threads, load stepping")
      .blocks.push_back(own(analysis));
  add("convergence", "[convergence]", "when a load step's iterations count as converged")
      .blocks.push_back(own(scene::convergence_schema()));
  {
    auto& s = add("solver", "[solver]", "parameters of the solver plugin named by [analysis] solver");
    if (reg)
      s.blocks =
          variants(*reg, PluginKind::solver, [](const std::string& n) { return "solver = \"" + n + "\""; });
  }
}

/// [mesh], [[mesh.blocks]] and the mesh generators' tables (their variants and sets with `reg`).
void add_mesh_sections(std::vector<Section>& out, const Registry* reg) {
  const auto add = [&](std::string n, std::string h, std::string sm) -> Section& {
    return add_section(out, std::move(n), std::move(h), std::move(sm));
  };
  {
    auto& s = add("mesh", "[mesh]", "where the mesh comes from: blocks, a Gmsh file or a mesh generator");
    s.notes = {"generator = \"gmsh\": the physical groups of the file become sets by name: 2D groups cell "
               "sets, 1D groups edge sets (and node sets of their nodes), 0D groups node sets.",
               "Every generator defines the cell set \"all\"."};
    s.blocks.push_back(own(scene::mesh_keys()));
  }
  add("mesh.blocks", "[[mesh.blocks]]", "one structured, graded block of generator = \"blocks\"")
      .blocks.push_back(own(scene::block_schema()));
  {
    auto& s =
        add("mesh.generators", "[mesh.<generator>]", "parameters of a mesh generator ([mesh] generator)");
    if (reg) {
      s.blocks = variants(*reg, PluginKind::mesh_generator, [](const std::string& n) {
        return "generator = \"" + n + "\": [mesh." + generator_table(n) + "]";
      });
      const auto names = reg->names(PluginKind::mesh_generator);
      for (std::size_t i = 0; i < names.size(); ++i) {
        const auto sets = generator_sets(*reg, names[i]);
        if (sets.empty()) continue;
        s.blocks[i].notes.push_back(
            "The sets it defines (generated with the defaults, axisymmetric, 8-node cells):");
        for (const auto& line : sets) s.blocks[i].notes.push_back(line);
      }
    }
  }
}

/// The model: materials, domains, constraints, loads, contact laws and interfaces.
void add_model_sections(std::vector<Section>& out) {
  const auto add = [&](std::string n, std::string h, std::string sm) -> Section& {
    return add_section(out, std::move(n), std::move(h), std::move(sm));
  };
  {
    auto& s = add("materials", "[materials.<name>]",
                  "a named material: its model plugin and the model's parameters");
    s.notes = {"The model's own parameters: `stratum plugins` lists the models, `stratum plugins --describe "
               "<model>` gives each parameter."};
    s.blocks.push_back(own(scene::material_schema()));
  }
  {
    auto& s = add("domains", "[[domains]]", "a cell set with its element and material");
    s.notes = {"The element's own parameters (e.g. its formulation, which follows [analysis]): `stratum "
               "plugins --describe <element>`. Every cell of the mesh must belong to exactly one domain."};
    s.blocks.push_back(own(scene::domain_schema()));
  }
  add("constraints", "[[constraints]]", "fixed or prescribed displacements of a node set")
      .blocks.push_back(own(scene::constraint_schema()));
  {
    auto& s = add("loads", "[[loads]]", "a load of a scene without [[stages]]");
    s.notes = {"Each [[loads]] table is read by the stage action of its type (stratum describe "
               "stages.actions); a scene with [[stages]] gives its loads as actions."};
    s.blocks.push_back(own(scene::loads_schema()));
  }
  {
    auto& s = add("contact_laws", "[contact_laws.<name>]", "a named contact law for [[interfaces]]");
    s.notes = {"The law's own parameters: `stratum plugins --describe <model>`."};
    s.blocks.push_back(own(scene::contact_law_schema()));
  }
  {
    auto& s = add("interfaces", "[[interfaces]]",
                  "an interface: the mesh split along an edge set, joined by contact elements");
    s.notes = {"The element's own parameters: `stratum plugins --describe <element>`."};
    s.blocks.push_back(own(scene::interface_schema()));
  }
}

/// [[stages]] and their actions (the action plugins' variants with `reg`).
void add_stage_sections(std::vector<Section>& out, const Registry* reg, const Schema& analysis) {
  const auto add = [&](std::string n, std::string h, std::string sm) -> Section& {
    return add_section(out, std::move(n), std::move(h), std::move(sm));
  };
  {
    auto& s =
        add("stages", "[[stages]]", "a stage of a staged run: its stepping and output, then its actions");
    const scene::TableKeys output = scene::output_keys();
    s.blocks.push_back(own(scene::stage_keys(
        fallback_of<long long>(analysis, "max_cutbacks"), fallback_of<double>(analysis, "error_tolerance"),
        fallback_of<bool>(output.schema, "vtk"), fallback_of<long long>(output.schema, "every"))));
  }
  {
    auto& s = add("stages.actions", "[[stages.actions]]", "what a stage does when it starts, by type");
    s.blocks.push_back(own(scene::action_schema()));
    if (reg)
      for (auto& b : variants(*reg, PluginKind::stage_action,
                              [](const std::string& n) { return "type = \"" + n + "\""; }))
        s.blocks.push_back(std::move(b));
  }
}

/// [output], [[output.history]], [[checks]] and [plugins].
void add_output_sections(std::vector<Section>& out) {
  const auto add = [&](std::string n, std::string h, std::string sm) -> Section& {
    return add_section(out, std::move(n), std::move(h), std::move(sm));
  };
  add("output", "[output]", "VTK output, the pile's curves and how often tables are written")
      .blocks.push_back(own(scene::output_keys()));
  {
    auto& s = add("output.history", "[[output.history]]",
                  "a recorder: chosen quantities after every step, history/<name>.csv");
    Block b = own(scene::recorder_keys());
    for (const char* kind : {"node", "nodes", "point", "global", "interface"}) {
      std::string q;
      for (const auto& n : recorder_quantities(kind)) q += (q.empty() ? "" : ", ") + n;
      b.notes.push_back(std::string("kind = \"") + kind + "\" records: " + q);
    }
    b.notes.push_back(
        "Units: displacements m, reactions kN (sums over the set; the whole ring in axisymmetry, kN/m in "
        "plane strain), stresses kPa (tension positive), strains -, s, x, y m; status: the model's own "
        "regime number (-1: none). In a scene with [units]: its length, force and stress units. The CSV "
        "header names each column with its unit (uy_m, ry_kN, ry_kN_per_m, sxx_kPa); a study or a check "
        "names the quantity without it (footing.ry).");
    b.notes.push_back(
        "Sign of a reaction: the force the supports put on the body, in the axes' directions: a footing "
        "pushed down by a prescribed settlement records a negative ry, and a [[checks]] entry expects that "
        "sign.");
    s.blocks.push_back(std::move(b));
  }
  {
    auto& s =
        add("checks", "[[checks]]", "an expected value of a recorded quantity; a failed check exits with 5");
    s.notes = {"Passes when |value - expected| <= atol + rtol |expected|, with the value at the last "
               "recorded step (for an interface recorder, at every point)."};
    s.blocks.push_back(own(scene::check_schema()));
  }
  add("plugins", "[plugins]", "extra folders searched for plugin libraries")
      .blocks.push_back(own(scene::plugins_keys()));
}

/// All sections; with `reg` null only their names, headers and summaries (no plugins opened).
std::vector<Section> sections(const Registry* reg) {
  std::vector<Section> out;
  add_top_sections(out);
  const Schema analysis = scene::analysis_schema();
  add_analysis_sections(out, reg, analysis);
  add_mesh_sections(out, reg);
  add_model_sections(out);
  add_stage_sections(out, reg, analysis);
  add_output_sections(out);
  return out;
}

std::string bare(std::string s) {
  while (!s.empty() && (s.front() == '[' || s.front() == ' ')) s.erase(s.begin());
  while (!s.empty() && (s.back() == ']' || s.back() == ' ')) s.pop_back();
  return s;
}

void write_other(std::ostream& out, const std::vector<scene::OtherKey>& other) {
  for (const auto& k : other)
    out << "  " << std::left << std::setw(18) << k.name << " " << k.type << "\n      " << k.meaning << "\n";
}

/// Text for Markdown outside code spans: <name> would be taken for an HTML tag.
std::string md_text(const std::string& s) {
  std::string o;
  for (char c : s) o += c == '<' ? std::string("&lt;") : c == '>' ? std::string("&gt;") : std::string(1, c);
  return o;
}

/// A Markdown table cell.
std::string md(const std::string& s) {
  std::string o;
  for (char c : md_text(s)) o += c == '|' ? std::string("\\|") : std::string(1, c);
  return o;
}

} // namespace

std::vector<SceneSectionInfo> scene_sections() {
  std::vector<SceneSectionInfo> v;
  for (const auto& s : sections(nullptr)) v.push_back(s.info);
  return v;
}

void list_scene_sections(std::ostream& out) {
  for (const auto& s : scene_sections())
    out << std::left << std::setw(16) << s.name << std::setw(22) << s.header << s.summary << "\n";
}

void describe_scene_section(std::ostream& out, const Registry& reg, const std::string& name) {
  const std::string want = bare(name);
  const auto all = sections(&reg);
  std::vector<std::string> names;
  for (const auto& s : all) {
    names.push_back(s.info.name);
    if (s.info.name != want && bare(s.info.header) != want) continue;
    out << s.info.header << ": " << s.info.summary << "\n";
    for (const auto& n : s.notes) out << "  " << n << "\n";
    for (const auto& b : s.blocks) {
      if (!b.title.empty()) out << "\n" << s.info.header << " " << b.title << ": " << b.summary << "\n";
      write_schema(out, b.schema);
      write_other(out, b.other);
      if (b.schema.specs().empty() && b.other.empty() && b.notes.empty()) out << "  (no keys)\n";
      for (const auto& n : b.notes) out << "  " << n << "\n";
    }
    return;
  }
  std::string known;
  for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
  throw Error("describe: unknown section '" + name + "'; known: " + known + did_you_mean(want, names));
}

void write_scene_reference_markdown(std::ostream& out, const Registry& reg) {
  out << "# Scene reference\n\n"
         "<!-- Generated by `stratum describe --markdown > docs/scene-reference.md`; do not edit: the\n"
         "     test scene_reference.up_to_date fails when this file differs from the program's. -->\n\n"
         "Every table and key a scene file (TOML) may hold, as the scene reader checks them: type, unit,\n"
         "allowed values, default (or *required*) and meaning. `stratum describe SECTION` prints the\n"
         "same on the terminal. Materials, elements and contact laws are plugins with their own\n"
         "parameters: `stratum plugins --describe NAME`. Units: kN, m, kPa unless the scene's [units]\n"
         "declare others (the units and defaults below are in kN, m, kPa); tension positive. Besides\n"
         "its range, every number may be at most 1e20 in magnitude (products of larger ones overflow).\n"
         "Names that the output uses in file names (stages, recorders, interfaces) may use letters,\n"
         "digits, `_`, `-`, `.` and `+` (at most 64, not starting with `.`).\n\n";
  const auto all = sections(&reg);
  for (const auto& s : all)
    out << "- [`" << s.info.header << "`](#" << s.info.name << "): " << md_text(s.info.summary) << "\n";
  for (const auto& s : all) {
    out << "\n<a id=\"" << s.info.name << "\"></a>\n## `" << s.info.header << "`\n\n"
        << md_text(s.info.summary) << ".\n\n";
    for (const auto& n : s.notes) out << n << "\n\n";
    for (const auto& b : s.blocks) {
      if (!b.title.empty()) out << "### `" << b.title << "`\n\n" << md_text(b.summary) << ".\n\n";
      if (!b.schema.specs().empty() || !b.other.empty()) {
        out << "| key | type | unit | allowed | default | meaning |\n|---|---|---|---|---|---|\n";
        for (const auto& p : b.schema.specs())
          out << "| `" << p.name << "` | " << to_string(p.type) << " | "
              << (p.unit.empty() ? "-" : md(p.unit)) << " | " << md(p.allowed()) << " | "
              << (p.fallback ? "`" + md(default_text(p)) + "`" : "*required*") << " | " << md(p.meaning)
              << " |\n";
        for (const auto& k : b.other)
          out << "| `" << k.name << "` | " << md(k.type) << " | - | | | " << md(k.meaning) << " |\n";
        out << "\n";
      } else if (b.notes.empty()) {
        out << "(no keys)\n\n";
      }
      for (const auto& n : b.notes) out << "- " << md(n) << "\n";
      if (!b.notes.empty()) out << "\n";
    }
  }
}

} // namespace stratum
