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

namespace test_params_read {

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

/// Values that a factory's cross-parameter checks need (each value alone is inside its range, a
/// pair is not: Cam-Clay's kappa < lambda, the cap model's C < A, Hardening Soil's E_ur > 2 E_50,
/// a thin layer with some strength, the parameters Duncan-Chang's default form requires). These
/// keys count as set by the scene in every case.
const std::map<std::string, std::map<std::string, double>> consistent = {
    {"cam_clay", {{"kappa", 0.02}, {"lambda", 0.1}}},
    {"modified_cam_clay", {{"kappa", 0.02}, {"lambda", 0.1}}},
    {"cap_sandler", {{"A", 500.0}, {"C", 100.0}}},
    {"hardening_soil", {{"E50_ref", 1e4}, {"Eur_ref", 3e4}}},
    {"thin_layer_hyperbolic", {{"delta", 30.0}}},
    {"duncan_chang", {{"G", 0.3}, {"F", 0.05}, {"d", 2.0}}}, // the E_nu form's own three
};

/// A valid value of a parameter: the consistent one above, its default, or one inside its range.
ParamValue sample(const ParamSpec& s, const std::string& factory) {
  if (const auto f = consistent.find(factory); f != consistent.end() && f->second.count(s.name)) {
    const double v = f->second.at(s.name);
    if (s.type == ParamType::real_list) return std::vector<double>{v};
    return v;
  }
  if (s.fallback) return *s.fallback;
  switch (s.type) {
  case ParamType::integer:
    return static_cast<long long>(inside(s));
  case ParamType::boolean:
    return false;
  case ParamType::text:
    return s.choices.empty() ? std::string("x") : s.choices.front();
  case ParamType::real_list:
    return std::vector<double>{inside(s)};
  case ParamType::real:
    break;
  }
  return inside(s);
}

/// The parameters as a scene that sets `key` (and the required ones) gives them: those it sets
/// carry a location (line = the parameter's number + 1), the others their default, unlocated.
Params scene_setting(const Schema& schema, const std::string& context, const std::string& factory,
                     const std::string& key) {
  Params p;
  p.context = context;
  int line = 0;
  for (const auto& s : schema.specs()) {
    ++line;
    const bool set =
        s.name == key || !s.fallback || (consistent.count(factory) && consistent.at(factory).count(s.name));
    p.set(s.name, sample(s, factory), set ? SourceLocation{"scene.toml", line, 1} : SourceLocation{});
  }
  return p;
}

struct Result {
  std::set<std::string> unread; ///< keys set, the object created, the key not read
  std::string failure;          ///< why the factory could not be created (empty: created)
};

/// For each declared key: a scene that sets it either creates the object and the key was read,
/// or is refused with an error located at the key (the key has no meaning in that configuration
/// and the factory says so). Created without reading it is what this test exists to find.
template <class T> Result try_factory(const Registry& reg, PluginKind kind, const std::string& name) {
  const Schema& schema = reg.schema(kind, name);
  const std::string context = std::string(to_string(kind)) + " " + name;
  Result r;
  int line = 0;
  for (const auto& spec : schema.specs()) {
    ++line;
    const Params p = scene_setting(schema, context, name, spec.name);
    try {
      const auto object = reg.factory<T>(name).create(p);
      if (!p.read_names().count(spec.name)) r.unread.insert(spec.name);
    } catch (const Error& e) {
      if (e.where().line != line) {
        r.failure = e.what();
        return r;
      }
    } catch (const std::exception& e) {
      r.failure = e.what();
      return r;
    }
  }
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

namespace {

/// A material that declares two parameters and reads one: what the test above must catch.
class Leaky final : public Material {
public:
  [[nodiscard]] Outcome update(const MaterialInput&, MaterialOutput&) const override {
    return Outcome::success();
  }
};

} // namespace

TEST_CASE("params: the check finds a declared key that the factory never reads", "[params]") {
  Registry reg;
  Schema schema;
  schema.real("read", "kPa", "a parameter the factory reads").defaults_to(1.0);
  schema.real("ignored", "kPa", "a parameter the factory forgets").defaults_to(2.0);
  schema.real("refused", "-", "a parameter the factory refuses when set, located").defaults_to(0.0);
  reg.add(Factory<Material>{"leaky",
                            "reads one of its parameters",
                            schema,
                            [](const Params& p) -> std::unique_ptr<Material> {
                              (void)p.real("read");
                              if (p.where("refused").known())
                                throw Error(p.where("refused"), "refused has no meaning here");
                              return std::make_unique<Leaky>();
                            },
                            {}});
  const Result r = try_factory<Material>(reg, PluginKind::material, "leaky");
  CHECK(r.failure.empty());
  CHECK(r.unread == std::set<std::string>{"ignored"});
}

} // namespace test_params_read
