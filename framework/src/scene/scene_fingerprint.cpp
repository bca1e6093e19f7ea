#include "scene_fingerprint.hpp"

#include "files.hpp"
#include "scene/toml_check.hpp"

#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

namespace stratum {

std::string digest_of(const std::string& text) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

namespace {

std::string canonical(const toml::node& n) {
  std::ostringstream o;
  // toml++ keeps a table's keys sorted, so equal data prints equally whatever the file's order.
  if (const auto* t = n.as_table())
    o << toml::toml_formatter(*t, toml::format_flags::none);
  else if (const auto* a = n.as_array())
    o << toml::toml_formatter(*a, toml::format_flags::none);
  else
    o << toml::toml_formatter(n, toml::format_flags::none);
  return o.str();
}

/// A cell's kind as the digest wrote it before cell types existed (0 a continuum cell, 1 a node
/// pair, 2 an interface line), so that checkpoints of earlier runs still match their mesh; the
/// types that did not exist then get codes of their own.
int kind_code(CellType t) {
  switch (t) {
  case CellType::quadrilateral:
  case CellType::triangle:
    return 0;
  case CellType::node_pair:
    return 1;
  case CellType::line_interface:
    return 2;
  default:
    return 10 + static_cast<int>(t);
  }
}

std::string mesh_text(const Mesh& m) {
  std::ostringstream o;
  char buf[64];
  for (const auto& x : m.nodes) {
    std::snprintf(buf, sizeof buf, "%a %a\n", x.x(), x.y());
    o << buf;
  }
  for (const auto& c : m.cells) {
    o << kind_code(c.type);
    for (int n : c.nodes) o << ' ' << n;
    o << '\n';
  }
  for (const auto& [name, v] : m.cell_sets) {
    o << "cells " << name;
    for (int c : v) o << ' ' << c;
    o << '\n';
  }
  for (const auto& [name, v] : m.edge_sets) {
    o << "edges " << name;
    for (const auto& e : v) o << ' ' << e.a << '/' << e.b << '/' << e.mid;
    o << '\n';
  }
  return o.str();
}

/// The stage (0-based) of the first `change_material` action naming each material that no
/// [[domains]] entry names.
std::map<std::string, int> material_stages(const toml::table& root) {
  std::set<std::string> in_domains;
  if (const auto* ds = root["domains"].as_array())
    for (const auto& d : *ds)
      if (const auto* t = d.as_table())
        if (const auto* m = t->get("material"); m && m->is_string()) in_domains.insert(m->as_string()->get());
  std::map<std::string, int> first;
  if (const auto* st = root["stages"].as_array())
    for (std::size_t k = 0; k < st->size(); ++k)
      if (const auto* t = (*st)[k].as_table())
        if (const auto* actions = t->get("actions"); actions && actions->is_array())
          for (const auto& a : *actions->as_array())
            if (const auto* at = a.as_table()) {
              const auto* type = at->get("type");
              const auto* m = at->get("material");
              if (type && type->is_string() && type->as_string()->get() == "change_material" && m &&
                  m->is_string() && !in_domains.count(m->as_string()->get()))
                first.emplace(m->as_string()->get(), static_cast<int>(k));
            }
  return first;
}

} // namespace

std::string mesh_digest(const Mesh& mesh) { return digest_of(mesh_text(mesh)); }

std::vector<FingerprintPart> scene_parts(const toml::table& root, const std::string& program_version) {
  std::vector<FingerprintPart> parts;
  auto add = [&](std::string name, const std::string& text, int stage, SourceLocation where) {
    parts.push_back({std::move(name), digest_of(text), stage, std::move(where)});
  };
  add("the program version", program_version, -1, {});
  std::string formulation = "plane_strain";
  if (const auto* a = root["analysis"].as_table())
    if (const auto* f = a->get("formulation"); f && f->is_string()) formulation = f->as_string()->get();
  add("[analysis] formulation", formulation, -1, io::location(root));
  // [units] only when a scene has them: checkpoints of kN, m scenes stay as they were.
  if (const auto* u = root.get("units")) add("[units]", canonical(*u), -1, io::location(*u));
  parts.push_back(
      {mesh_part_name, "", -1, root.get("mesh") ? io::location(*root.get("mesh")) : io::location(root)});
  // A material that no [[domains]] entry names but a stage's change_material does belongs to the
  // first such stage: a restart before it may add or edit it (the stage is still to run).
  const std::map<std::string, int> first_stage = material_stages(root);
  for (const char* group : {"materials", "contact_laws"})
    if (const auto* t = root[group].as_table())
      for (auto&& [key, value] : *t) {
        const auto at = first_stage.find(std::string(key.str()));
        add("[" + std::string(group) + "." + std::string(key.str()) + "]", canonical(value),
            std::string(group) == "materials" && at != first_stage.end() ? at->second : -1,
            io::location(value));
      }
  for (const char* list : {"domains", "interfaces", "constraints"})
    if (const auto* n = root.get(list))
      add("[[" + std::string(list) + "]]", canonical(*n), -1, io::location(*n));
  if (const auto* st = root["stages"].as_array()) {
    int k = 0;
    for (const auto& e : *st) {
      std::string name;
      if (const auto* t = e.as_table())
        if (const auto* nm = t->get("name"); nm && nm->is_string())
          name = " \"" + nm->as_string()->get() + "\"";
      add("[[stages]] #" + std::to_string(k + 1) + name, canonical(e), k, io::location(e));
      ++k;
    }
  } else {
    std::string text;
    if (const auto* l = root.get("loads")) text = canonical(*l);
    add("[[loads]]", text, 0, root.get("loads") ? io::location(*root.get("loads")) : io::location(root));
  }
  return parts;
}

std::vector<FingerprintPart> library_parts(const std::vector<std::string>& paths) {
  std::vector<FingerprintPart> parts;
  for (const auto& path : paths) {
    // Through the guarded reader (a regular file, at most file_limits::library), as every input.
    const std::string bytes = read_text_file(path, SourceLocation{}, "plugin library", file_limits::library);
    parts.push_back({"plugin library " + std::filesystem::path(path).filename().string(),
                     digest_of(bytes),
                     FingerprintPart::if_both,
                     {}});
  }
  return parts;
}

std::string fingerprint_mismatch(const std::vector<FingerprintPart>& saved,
                                 const std::vector<FingerprintPart>& current, int stages_done,
                                 SourceLocation* where) {
  auto relevant = [&](const FingerprintPart& p) { return p.stage < stages_done; };
  for (const auto& s : saved) {
    if (!relevant(s)) continue;
    const FingerprintPart* c = nullptr;
    for (const auto& p : current)
      if (p.name == s.name) c = &p;
    if (!c) {
      if (s.stage == FingerprintPart::if_both) continue; // a library this run does not open
      return s.name + " of the scene that wrote the checkpoint is missing from this scene";
    }
    if (c->digest != s.digest) {
      if (where) *where = c->where;
      if (s.stage == FingerprintPart::if_both)
        return c->name + " is not the file that wrote the checkpoint (rebuilt or changed): its model's "
                         "saved states would be continued by another model; restart with the library "
                         "that wrote them, or run the scene from its start";
      return c->name + " differs from the scene that wrote the checkpoint (it must stay as it was up to the "
                       "restart; only later stages may change)";
    }
  }
  for (const auto& c : current) {
    if (!relevant(c) || c.stage == FingerprintPart::if_both) continue; // a library it did not use: fine
    bool found = false;
    for (const auto& s : saved) found = found || s.name == c.name;
    if (!found) {
      if (where) *where = c.where;
      return c.name + " is not in the scene that wrote the checkpoint";
    }
  }
  return {};
}

} // namespace stratum
