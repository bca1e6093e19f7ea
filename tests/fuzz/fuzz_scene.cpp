// libFuzzer target: the scene reader, i.e. what `stratum check` does (Analysis::from_string: TOML
// parse, schema checks, plugins, mesh, domains, constraints, loads, stages) without running a
// step or writing anything.
//
// The contract checked: bad input ends in stratum::Error (a located one-line message); any other
// exception is what the CLI reports as "internal error" and is a defect, so it aborts here, as
// do the sanitizers' findings. Relative paths in a scene resolve against tests/data, so a
// mutated scene can reach the Gmsh files there.
#include "stratum/analysis.hpp"
#include "stratum/error.hpp"

#include <toml++/toml.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

// Scenes that are valid but merely big (a mesh of a million cells) are slow, not wrong; they would
// end the fuzzing run as a timeout or out-of-memory. Skipped: integers in [mesh] whose product per
// table (block counts, pile cell counts) exceeds this. Negative and zero counts still go through.
constexpr double max_cells = 2e4;

bool too_big(const toml::table& t) {
  double product = 1.0;
  for (auto&& [key, value] : t) {
    if (const auto* i = value.as_integer(); i && i->get() > 1) product *= static_cast<double>(i->get());
    if (const auto* sub = value.as_table(); sub && too_big(*sub)) return true;
    if (const auto* a = value.as_array())
      for (const auto& e : *a)
        if (const auto* st = e.as_table(); st && too_big(*st)) return true;
  }
  return product > max_cells;
}

bool skip(const std::string& text) {
  // A user's UMAT library is opened at check time; a mutated absolute path must not dlopen
  // whatever shared library it happens to name on this machine.
  if (text.find(".so") != std::string::npos) return true;
  try {
    const toml::table root = toml::parse(text, std::string_view("fuzz"));
    const auto* mesh = root.get_as<toml::table>("mesh");
    return mesh && too_big(*mesh);
  } catch (const toml::parse_error&) {
    return false; // the reader must report it
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (skip(text)) return -1; // -1: not added to the corpus
  stratum::RunOptions options;
  options.write_output = false;
  options.plugin_dirs = {STRATUM_PLUGIN_DIR};
  try {
    const auto analysis = stratum::Analysis::from_string(text, STRATUM_FUZZ_SCENE_DIR "/fuzz.toml", options);
    (void)analysis->model();
  } catch (const stratum::Error&) {
    // bad input, reported as it should be
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_scene: internal error (not a stratum::Error): %s\n", e.what());
    std::abort();
  }
  return 0;
}
