// What the material plugins of this project that provide one material declared with
// stratum/parameters.hpp share: the plugin entry point that registers it, and the create
// functions that build a model from the declared struct alone or from it and the shared
// stress-integrator parameters (stratum/plasticity/integrate.hpp).
#pragma once

#include "stratum/parameters.hpp"
#include "stratum/plasticity/integrate.hpp"
#include "stratum/plugin.hpp"

#include <memory>

namespace stratum::material_plugin {

/// The create function of a model constructed from the declared struct alone: Model(input).
template <class Model>
inline constexpr auto from_input =
    [](const auto& input, const Params&) { return std::make_unique<Model>(input); };

/// The create function of a model constructed from the declared struct and the integrator
/// parameters (plasticity::add_integrator_parameters): Model(input, integrator settings).
template <class Model>
inline constexpr auto with_integrator = [](const auto& input, const Params& p) {
  return std::make_unique<Model>(input, plasticity::read_integrator_parameters(p));
};

} // namespace stratum::material_plugin

/// The entry point of a plugin that provides one material: registers
/// stratum::material_factory(name, summary, declared, create[, start]) (the arguments as given).
#define STRATUM_MATERIAL_PLUGIN(...)                                                                         \
  STRATUM_PLUGIN(registry) { registry.add(stratum::material_factory(__VA_ARGS__)); }
