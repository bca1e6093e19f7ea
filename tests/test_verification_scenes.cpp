// Every scene in inputs/verification/ states its closed form as [[checks]] (issue 22): a run of
// it prints pass/fail against the closed form and exits non-zero when the answer is wrong.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

TEST_CASE("every verification scene has [[checks]] and [[output.history]]", "[verification][recorders]") {
  const fs::path dir = fs::path(STRATUM_SOURCE_DIR) / "inputs" / "verification";
  int scenes = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".toml") continue;
    ++scenes;
    std::ifstream in(e.path());
    std::stringstream s;
    s << in.rdbuf();
    const std::string text = s.str();
    INFO(e.path().string());
    CHECK(text.find("\n[[checks]]") != std::string::npos);
    CHECK(text.find("\n[[output.history]]") != std::string::npos);
  }
  CHECK(scenes >= 6);
}
