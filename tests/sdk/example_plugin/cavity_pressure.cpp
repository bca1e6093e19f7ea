// example_cavity_pressure: a stage action (SDK example). It puts a uniform pressure on the
// wall of a cavity (an edge set of the mesh) when its stage starts; the pressure stays applied
// until a later stage's `remove` action names it.
//
//   [[stages.actions]]
//   type = "example_cavity_pressure"
//   edges = "ring.left"   # the cavity wall
//   p = 1.0               # kPa, pushing into the body
#include <stratum/load.hpp>
#include <stratum/plugin.hpp>
#include <stratum/stage_action.hpp>

#include <memory>
#include <string>

namespace example_cavity {

class CavityPressure final : public stratum::StageAction {
public:
  explicit CavityPressure(const stratum::Params& p) : params_(p) {
    load_.kind = stratum::LoadSpec::Kind::pressure;
    load_.name = p.text("name");
    load_.set = p.text("edges");
    load_.p = p.real("p");
  }

  /// When the scene is read: the edge set must exist and the load's name must be free.
  void check(stratum::StageCheck& scene) override {
    scene.require_edge_set(params_, "edges");
    scene.add_load_name(load_.name);
  }

  /// When the stage starts: the load joins the applied ones (and the checkpoints).
  void apply(stratum::StageState& state) const override { state.loads.push_back(load_); }

private:
  stratum::Params params_;
  stratum::LoadSpec load_;
};

/// The keys of the action's table besides `type`; any other key is a located error.
stratum::Schema schema() {
  stratum::Schema s;
  s.text("edges", {}, "edge set of the cavity wall");
  s.real("p", "kPa", "pressure on the wall, positive pushing into the body").greater_than(0.0);
  s.text("name", {}, "name by which a later stage removes the pressure").defaults_to(std::string("cavity"));
  return s;
}

} // namespace example_cavity

STRATUM_PLUGIN(registry) {
  registry.add(stratum::Factory<stratum::StageAction>{
      "example_cavity_pressure", // what scenes write as  type = "example_cavity_pressure"
      "a uniform pressure on the wall of a cavity (SDK example)",
      example_cavity::schema(),
      [](const stratum::Params& p) -> std::unique_ptr<stratum::StageAction> {
        return std::make_unique<example_cavity::CavityPressure>(p);
      },
      {}});
}
