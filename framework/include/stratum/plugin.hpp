// What a plugin library includes. A plugin exports exactly two C symbols:
//
//   int  stratum_plugin_abi_version(void);     -> STRATUM_PLUGIN_ABI_VERSION at build time
//   void stratum_register(stratum::Registry&);  -> adds its factories
//
// Write them with the STRATUM_PLUGIN macro:
//
//   STRATUM_PLUGIN(registry) {
//     registry.add(stratum::Factory<stratum::Material>{ ... });
//   }
#pragma once

#include "stratum/registry.hpp"

/// Bumped whenever an interface in stratum/*.hpp changes in a binary-incompatible way; every
/// version, what changed and how to port a plugin: docs/plugin-abi.md.
#define STRATUM_PLUGIN_ABI_VERSION 15

#define STRATUM_PLUGIN(registry_name)                                                                        \
  extern "C" __attribute__((visibility("default"))) int stratum_plugin_abi_version() {                       \
    return STRATUM_PLUGIN_ABI_VERSION;                                                                       \
  }                                                                                                          \
  extern "C" __attribute__((visibility("default"))) void stratum_register(stratum::Registry& registry_name)
