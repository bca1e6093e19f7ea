// Every parameter a factory declares is read when a scene sets it. A declared key that nothing
// reads is accepted by the schema check and then silently ignored (what `[output] pile_head` was);
// MOOSE calls such parameters unused and refuses them. Here each factory of every plugin library
// of the build tree and of the framework is created from a full set of valid values, and the
// parameters it read (Params::read_names) must be all it declares.
#include "stratum/analysis.hpp"
#include "stratum/calibration.hpp"
#include "stratum/contact_law.hpp"
#include "stratum/element.hpp"
#include "stratum/material.hpp"
#include "stratum/mesh_generator.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/registry.hpp"
#include "stratum/solver.hpp"
#include "stratum/stage_action.hpp"

#include <catch2/catch.hpp>

#include <map>
#include <set>
#include <string>

using namespace stratum;

namespace {

/// A number inside the declared range: the middle of a closed interval, one above an open lower
/// bound (or the bound itself when closed), one below an upper bound alone, 1 when unbounded.
double inside(const ParamSpec& s) {
  if (s.lower && s.upper) return 0.5 * (*s.lower + *s.upper);
  if (s.lower) return *s.lower + (s.lower_open || *s.lower == 0.0 ? 1.0 : 0.0);
  if (s.upper) return *s.upper - 1.0;
  return 1.0;
}

/// Every declared parameter set: its default where it has one, otherwise a valid value.
Params full(const Schema& schema, const std::string& context) {
  Params p;
  p.context = context;
  for (const auto& s : schema.specs()) {
    if (s.fallback) {
      p.set(s.name, *s.fallback);
      continue;
    }
    switch (s.type) {
    case ParamType::real:
      p.set(s.name, inside(s));
      break;
    case ParamType::integer:
      p.set(s.name, static_cast<long long>(inside(s)));
      break;
    case ParamType::boolean:
      p.set(s.name, false);
      break;
    case ParamType::text:
      p.set(s.name, s.choices.empty() ? std::string("x") : s.choices.front());
      break;
    case ParamType::real_list:
      p.set(s.name, std::vector<double>{inside(s)});
      break;
    }
  }
  return p;
}

struct Result {
  std::set<std::string> unread;
  std::string failure; ///< why the factory could not be created from the values (empty: created)
};

template <class T> Result try_factory(const Registry& reg, PluginKind kind, const std::string& name) {
  const Schema& schema = reg.schema(kind, name);
  const Params p = full(schema, std::string(to_string(kind)) + " " + name);
  Result r;
  try {
    const auto object = reg.factory<T>(name).create(p);
    if (!object) r.failure = "created nothing";
  } catch (const std::exception& e) {
    r.failure = e.what();
    return r;
  }
  for (const auto& s : schema.specs())
    if (!p.read_names().count(s.name)) r.unread.insert(s.name);
  return r;
}

} // namespace

TEST_CASE("params: every factory reads every parameter it declares", "[params][plugins]") {
  Registry reg;
  register_builtin_factories(reg);
  PluginCatalog catalog({STRATUM_PLUGIN_DIR});
  catalog.require_all(reg);

  // Factories that cannot be created from declared values alone, and why; their parameters are
  // read by the scene tests that create them from real input.
  const std::map<std::string, std::string> needs_more = {
      {"umat", "needs a compiled UMAT library at `library`"},
  };
  // Stage actions keep their parameters and read them when their stage starts, against a model:
  // the stage tests (tests/test_stage_actions.cpp) set each key of each action.

  int created = 0;
  auto check = [&](PluginKind kind, const std::string& name, const Result& r) {
    INFO(to_string(kind) << " \"" << name << "\"");
    if (!r.failure.empty()) {
      INFO("creating it from its declared values failed: " << r.failure);
      CHECK(needs_more.count(name) == 1);
      return;
    }
    ++created;
    std::string unread;
    for (const auto& n : r.unread) unread += (unread.empty() ? "" : ", ") + n;
    INFO("declared but never read: " << unread);
    CHECK(r.unread.empty());
  };
  for (const auto& name : reg.names(PluginKind::material))
    check(PluginKind::material, name, try_factory<Material>(reg, PluginKind::material, name));
  for (const auto& name : reg.names(PluginKind::element))
    check(PluginKind::element, name, try_factory<Element>(reg, PluginKind::element, name));
  for (const auto& name : reg.names(PluginKind::contact_law))
    check(PluginKind::contact_law, name, try_factory<ContactLaw>(reg, PluginKind::contact_law, name));
  for (const auto& name : reg.names(PluginKind::solver))
    check(PluginKind::solver, name, try_factory<Solver>(reg, PluginKind::solver, name));
  for (const auto& name : reg.names(PluginKind::mesh_generator))
    check(PluginKind::mesh_generator, name,
          try_factory<MeshGenerator>(reg, PluginKind::mesh_generator, name));
  for (const auto& name : reg.names(PluginKind::calibration))
    check(PluginKind::calibration, name, try_factory<Calibration>(reg, PluginKind::calibration, name));
  // The libraries of this tree hold some thirty factories besides the stage actions.
  CHECK(created >= 30);
}

TEST_CASE("params: a parameter read is recorded, has() and where() are not reads", "[params]") {
  Params p;
  p.set("a", 1.0);
  p.set("b", std::string("x"));
  CHECK(p.read_names().empty());
  CHECK(p.has("a"));
  (void)p.where("b");
  CHECK(p.read_names().empty());
  CHECK(p.real("a") == 1.0);
  CHECK(p.read_names() == std::set<std::string>{"a"});
  const Params copy = p;
  CHECK(copy.text("b") == "x");
  CHECK(copy.read_names() == std::set<std::string>{"a", "b"});
}
