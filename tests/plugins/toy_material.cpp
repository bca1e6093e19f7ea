// Test-only plugins for the loader: built several times with different macros
// into separate directories (see tests/CMakeLists.txt).
//   TOY_ABI       the ABI number the library claims (default: the real one)
//   TOY_NAME      the material name it registers
#include "stratum/plugin.hpp"

namespace {
class Toy final : public stratum::Material {
public:
  stratum::Outcome update(const stratum::MaterialInput& in, stratum::MaterialOutput& out) const override {
    out.tangent = stratum::Mat6::Identity();
    out.stress = in.stress_n + in.dstrain;
    return {};
  }
};
} // namespace

#ifndef TOY_ABI
#define TOY_ABI STRATUM_PLUGIN_ABI_VERSION
#endif

extern "C" __attribute__((visibility("default"))) int stratum_plugin_abi_version() { return TOY_ABI; }

extern "C" __attribute__((visibility("default"))) void stratum_register(stratum::Registry& r) {
  r.add(stratum::Factory<stratum::Material>{
      .name = TOY_NAME,
      .summary = "test-only material",
      .schema = {},
      .create = [](const stratum::Params&) { return std::make_unique<Toy>(); },
      .library = {}});
}
