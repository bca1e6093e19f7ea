// The plugin search list of the build tree's program (`stratum plugins --paths`): the folders of
// STRATUM_PLUGIN_PATH in order, then the build tree's plugins folder, nothing else. The installed
// program's list (its prefix only, never a build tree) is checked by tests/sdk/run.sh.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace test_plugin_paths {

namespace fs = std::filesystem;

namespace {

std::string run(const std::string& env, const std::string& args, int& code) {
  const fs::path out = fs::temp_directory_path() / ("stratum_paths_" + std::to_string(::getpid()) + ".txt");
  const std::string cmd = env + " " + STRATUM_EXE + " " + args + " >" + out.string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(out);
  std::stringstream s;
  s << in.rdbuf();
  fs::remove(out);
  return s.str();
}

} // namespace

TEST_CASE("stratum plugins --paths: STRATUM_PLUGIN_PATH first, then the build tree's plugins",
          "[cli][plugins]") {
  int code = -1;
  const std::string build = fs::weakly_canonical(STRATUM_PLUGIN_DIR).string();
  CHECK(run("STRATUM_PLUGIN_PATH=/nowhere/a::/nowhere/b", "plugins --paths", code) ==
        "/nowhere/a\n/nowhere/b\n" + build + "\n");
  CHECK(code == 0);
  CHECK(run("STRATUM_PLUGIN_PATH=", "plugins --paths", code) == build + "\n");
  const std::string bad = run("", "plugins --path", code);
  CHECK(code == 1);
  CHECK(bad.find("allowed: --describe [NAME], --all, --paths") != std::string::npos);
}

} // namespace test_plugin_paths
