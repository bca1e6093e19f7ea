// What a stage records of a pile after each converged step: the head's load and settlement
// (curves/load_settlement.csv), the settlement components, the axial force profile and the shaft
// rows, and whether the stage's settlement limit (stop_settlement) is reached. The stepping loop
// (run/run_stage.cpp) asks it; it knows nothing of piles. Internal to the framework.
#pragma once

#include "output/pile_components.hpp"
#include "stages/stage.hpp"
#include "stratum/model.hpp"
#include "stratum/units.hpp"

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

namespace stratum {

/// What one observation gives the tables (all empty when the stage monitors no pile head).
struct PileObservation {
  bool recorded = false;   ///< a head is monitored: load, settlement and the rows below are set
  double load = 0.0;       ///< head load (kN, downward positive)
  double settlement = 0.0; ///< mean head settlement (Units::small_length)
  std::optional<std::array<double, 8>> components; ///< with [output] pile_cells (pile_components.hpp)
  std::vector<std::array<double, 3>> axial;        ///< load, y, N (with [output] pile_cells)
  std::vector<std::array<double, 6>> shaft;        ///< load, y, shear, normal, slip, status
};

class PileMonitor {
public:
  /// head: the stage's load on the pile head (StageState::head_load), or null; head_disp: the
  /// nodes of a displacement-controlled head (StageState::head_nodes); pile: [output] pile_cells
  /// (null: none); interface_domains: the indices into model.domains of the scene's interfaces.
  /// before: the loads acting when the stage started; a head load among them on the same head,
  /// removed by this stage, is where the stage's head load starts (it hands over linearly).
  PileMonitor(const Model& model, const stage::Stage& stage, const LoadSpec* head,
              const std::vector<LoadSpec>& before, const std::vector<int>& head_disp,
              const std::vector<int>* pile, std::vector<std::size_t> interface_domains, const Units& units);
  PileMonitor(const PileMonitor&) = delete; // monitored() may point at head_nodes_
  PileMonitor& operator=(const PileMonitor&) = delete;

  /// A pile head (loaded or displaced) is monitored: observe() records rows.
  [[nodiscard]] bool has_head() const { return has_head_; }
  /// The stage stops at a settlement (stop_settlement > 0 and a node set to watch).
  [[nodiscard]] bool watches_settlement() const { return stop_settlement_ > 0 && monitored_ != nullptr; }
  /// The rows at the model's committed state; `stepped`: a step of the stage has converged (the
  /// reactions of a displaced head are the step's).
  PileObservation observe(Model& model, bool stepped);
  /// The monitored mean settlement exceeds the stage's stop_settlement (watches_settlement()).
  [[nodiscard]] bool settlement_reached(const Model& model) const;

private:
  /// The head load (kN, downward positive): the applied force, or the reaction on a displaced head.
  [[nodiscard]] double head_load(const Model& model, bool stepped) const;
  /// The shaft rows at `load`: the interface points on the pile's vertical wall.
  void shaft_rows(const Model& model, double load, std::vector<std::array<double, 6>>& rows) const;

  std::vector<int> head_nodes_;
  bool displaced_head_ = false, has_head_ = false;
  double force_ = 0.0;                          ///< the head load's total force (a loaded head)
  double start_force_ = 0.0;                    ///< the head loads on the same head before the stage
  const std::vector<int>* monitored_ = nullptr; ///< the stage's monitor set, else the head
  double stop_settlement_ = 0.0;
  const std::vector<int>* pile_ = nullptr;
  std::vector<std::size_t> interface_domains_;
  double small_ = 1e3;    ///< length unit -> unit of the settlements (Units::small_length_factor)
  double per_unit_ = 1e6; ///< axial profile levels: micrometres in the length unit
  std::optional<PileComponents> components_; ///< created at the first observation
};

} // namespace stratum
