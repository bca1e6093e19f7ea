// Files, the command line and sweeps as they go wrong in the wild (issue 40): input files that are
// not regular files or are too large, deep include chains, an address-space or file-size limit,
// output paths below a file or over an input, two sweeps into one folder, a sweep whose samples
// all fail. Each case runs the program as a child process and asserts what the user sees: the
// exit status and the one line on stderr.
#include "run/checkpoint.hpp"
#include "stratum/analysis.hpp"
#include "stratum/error.hpp"
#include "stratum/mesh_io.hpp"

#include <catch2/catch.hpp>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace test_input_files {

namespace fs = std::filesystem;

namespace {

/// One scratch folder per process and test case (CTest runs the cases in parallel).
fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("stratum_files_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

struct Result {
  int code = -1;  ///< the exit status; -1 when a signal ended the process
  int signal = 0; ///< the signal that ended it, if one did
  std::string out, err;
};

/// A resource limit for the child: RLIMIT_AS or RLIMIT_FSIZE and its value in bytes.
struct Limit {
  int resource;
  rlim_t bytes;
};

/// Starts stratum with `args` in `dir` (stdout and stderr to files there), under `limit`; the
/// build tree's plugins only.
pid_t start(const std::vector<std::string>& args, const fs::path& dir, std::optional<Limit> limit = {},
            const std::string& tag = "") {
  std::vector<std::string> all{STRATUM_EXE};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string out = (dir / ("stdout" + tag + ".txt")).string(),
                    err = (dir / ("stderr" + tag + ".txt")).string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (::chdir(dir.c_str()) != 0) ::_exit(126);
    const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (o < 0 || e < 0) ::_exit(126);
    ::dup2(o, 1);
    ::dup2(e, 2);
    // Only the build tree's plugins, unless a case names a folder (STRATUM_TEST_PLUGIN_PATH).
    const char* plugin_path = ::getenv("STRATUM_TEST_PLUGIN_PATH");
    ::setenv("STRATUM_PLUGIN_PATH", plugin_path ? plugin_path : "", 1);
    if (limit) {
      const rlimit r{limit->bytes, limit->bytes};
      if (::setrlimit(limit->resource, &r) != 0) ::_exit(126);
    }
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

Result finish(pid_t pid, const fs::path& dir, const std::string& tag = "") {
  int status = 0;
  ::waitpid(pid, &status, 0);
  Result r;
  if (WIFEXITED(status)) r.code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.out = slurp(dir / ("stdout" + tag + ".txt"));
  r.err = slurp(dir / ("stderr" + tag + ".txt"));
  return r;
}

Result cli(const std::vector<std::string>& args, const fs::path& dir, std::optional<Limit> limit = {}) {
  return finish(start(args, dir, limit), dir);
}

int lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

/// Exit status `code`, and one line on stderr that starts "stratum: " and holds `text`.
void expect_one_line(const Result& r, int code, const std::string& text) {
  INFO("stdout: " << r.out << "\nstderr: " << r.err);
  CHECK(r.signal == 0);
  CHECK(r.code == code);
  CHECK(lines(r.err) == 1);
  CHECK(r.err.rfind("stratum: ", 0) == 0);
  CHECK(r.err.find(text) != std::string::npos);
  CHECK(r.err.find("internal error") == std::string::npos);
}

const std::string ring = slurp(fs::path(STRATUM_SOURCE_DIR) / "tests" / "scenes" / "cli" / "ring.toml");
const std::string elastic_point = std::string(STRATUM_SOURCE_DIR) + "/inputs/point/elastic_paths.toml";

/// A study of the elastic point file over the Young's moduli `values` (a TOML array).
std::string point_study(const std::string& values, const std::string& study_extra = "") {
  return "[study]\npoint = \"" + elastic_point + "\"\ndesign = \"grid\"\n" + study_extra +
         "[[parameters]]\nname = \"E\"\npath = \"material.E\"\nvalues = " + values +
         "\n[[quantities]]\nname = \"n\"\ntype = \"steps\"\n";
}

} // namespace

TEST_CASE("input files: a device, a FIFO or a file over its size limit is refused in one line, never read",
          "[cli][files]") {
  const fs::path d = scratch("inputs");
  write(d / "ring.toml", ring);
  REQUIRE(::mkfifo((d / "fifo.toml").c_str(), 0644) == 0);

  SECTION("the scene file") {
    expect_one_line(cli({"run", "/dev/zero"}, d), 1,
                    "stratum: /dev/zero: not a regular file but a character device; a scene file must be a "
                    "regular file");
    expect_one_line(
        cli({"check", "fifo.toml"}, d), 1,
        "fifo.toml: not a regular file but a FIFO (named pipe); a scene file must be a regular file");
    // 17 MB (a sparse file: nothing is written): over the 16 MB of a scene file.
    fs::resize_file((write(d / "big.toml", ""), d / "big.toml"), 17u << 20);
    expect_one_line(
        cli({"check", "big.toml"}, d), 1,
        "stratum: big.toml: the file (17.0 MB) is larger than the limit of 16 MB for a scene file");
    fs::remove(d / "big.toml");
  }
  SECTION("an included file, located at its include line") {
    write(d / "inc_zero.toml", "include = \"/dev/zero\"\n" + ring);
    expect_one_line(
        cli({"check", "inc_zero.toml"}, d), 1,
        "inc_zero.toml:1:11 included file '/dev/zero' is not a regular file but a character device; "
        "a scene file must be a regular file");
    write(d / "inc_fifo.toml", "include = \"fifo.toml\"\n" + ring);
    expect_one_line(
        cli({"check", "inc_fifo.toml"}, d), 1,
        "inc_fifo.toml:1:11 included file 'fifo.toml' is not a regular file but a FIFO (named pipe)");
  }
  SECTION("a mesh file named by the scene") {
    // The fuzz corpus's scene: its [mesh] file is /dev/zero.
    const std::string scene =
        std::string(STRATUM_SOURCE_DIR) + "/tests/fuzz/corpus/fuzz_scene/finding_mesh_dev_zero.toml";
    expect_one_line(
        cli({"check", scene}, d), 1,
        "finding_mesh_dev_zero.toml:6:8 [mesh] file = \"/dev/zero\": is not a regular file (a folder, a "
        "FIFO or a device)");
  }
  SECTION("a checkpoint to restart from") {
    expect_one_line(cli({"run", "ring.toml", "--out", "o", "--restart-from", "/dev/zero"}, d), 1,
                    "stratum: /dev/zero: not a regular file but a character device; a checkpoint must be a "
                    "regular file");
    fs::resize_file((write(d / "big.ckpt", ""), d / "big.ckpt"), (4096ull << 20) + 1);
    expect_one_line(cli({"run", "ring.toml", "--out", "o", "--restart-from", "big.ckpt"}, d), 1,
                    "stratum: big.ckpt: the file (4294967297 bytes) is larger than the limit of 4096 MB for "
                    "a checkpoint");
    fs::remove(d / "big.ckpt"); // sparse, but 4 GB to whoever lists the folder
  }
  SECTION("a study, point or CSV file") {
    expect_one_line(
        cli({"sweep", "/dev/zero", "--out", "s"}, d), 1,
        "/dev/zero: not a regular file but a character device; a study file must be a regular file");
    expect_one_line(
        cli({"point", "/dev/zero", "--out", "p.csv"}, d), 1,
        "/dev/zero: not a regular file but a character device; a point file must be a regular file");
    expect_one_line(
        cli({"fit", "duncan_chang", "/dev/zero"}, d), 1,
        "/dev/zero: not a regular file but a character device; a CSV file must be a regular file");
    CHECK(!fs::exists(d / "s"));
    CHECK(!fs::exists(d / "p.csv"));
  }
  SECTION("a plugin manifest in a folder of STRATUM_PLUGIN_PATH") {
    // A FIFO named *.plugin would block the reader; it is refused in one line instead.
    fs::create_directories(d / "plugins");
    REQUIRE(::mkfifo((d / "plugins" / "blocked.plugin").c_str(), 0644) == 0);
    REQUIRE(::setenv("STRATUM_TEST_PLUGIN_PATH", (d / "plugins").c_str(), 1) == 0);
    const Result r = cli({"plugins"}, d);
    ::unsetenv("STRATUM_TEST_PLUGIN_PATH");
    expect_one_line(r, 1,
                    "blocked.plugin: not a regular file but a FIFO (named pipe); a plugin manifest must be a "
                    "regular file");
  }
  SECTION("a mesh and a checkpoint through their readers") {
    auto message = [](auto&& f) {
      try {
        f();
      } catch (const stratum::Error& e) {
        return std::string(e.what());
      }
      return std::string("no error");
    };
    const std::string fifo = (d / "fifo.toml").string();
    CHECK(message([&] { (void)stratum::read_gmsh(fifo); }) ==
          fifo + ": not a regular file but a FIFO (named pipe); a mesh file must be a regular file");
    CHECK(message([&] { (void)stratum::read_checkpoint(fifo); }) ==
          fifo + ": not a regular file but a FIFO (named pipe); a checkpoint must be a regular file");
    // A checkpoint whose first line never ends: only its first 128 bytes are taken as the header.
    std::istringstream zeros(std::string(1 << 20, '\0'));
    CHECK(message([&] {
            (void)stratum::read_checkpoint(zeros, "zeros.ckpt");
          }).rfind("zeros.ckpt: not a Stratum checkpoint", 0) == 0);
  }
}

TEST_CASE("include: a chain of 5000 nested includes stops at the depth limit with a located line",
          "[cli][files][include]") {
  const fs::path d = scratch("deep");
  // inc_0 includes inc_1, which includes inc_2, ...: each file sets one key of its own.
  constexpr int n = 5000;
  for (int i = 0; i < n; ++i)
    write(d / ("inc_" + std::to_string(i) + ".toml"),
          "include = \"inc_" + std::to_string(i + 1) + ".toml\"\n[units]\n");
  write(d / ("inc_" + std::to_string(n) + ".toml"), "title = \"the end\"\n");
  write(d / "deep.toml", "include = \"inc_0.toml\"\n" + ring);
  // deep.toml is depth 0, inc_0 depth 1, ...: inc_32 (depth 33) is refused at its include line
  // in inc_31.
  expect_one_line(cli({"check", "deep.toml"}, d), 1,
                  "inc_31.toml:1:11 include 'inc_32.toml' would be at depth 33 of a chain of includes (the "
                  "scene is depth 0); includes nest at most 32 deep");
  // 32 deep is fine.
  write(d / ("inc_" + std::to_string(31) + ".toml"), "title = \"the end\"\n");
  const Result ok = cli({"check", "deep.toml", "--quiet"}, d);
  INFO(ok.err);
  CHECK(ok.code == 0);
  // A cycle is still a cycle, however deep.
  write(d / ("inc_" + std::to_string(31) + ".toml"), "include = \"inc_0.toml\"\n");
  expect_one_line(cli({"check", "deep.toml"}, d), 1, "inc_31.toml:1:11 include 'inc_0.toml' includes itself");
}

TEST_CASE(
    "an address-space limit (ulimit -v) that the mesh exceeds is one line and exit 2, not an internal error",
    "[cli][files][memory]") {
  const fs::path d = scratch("memory");
  // The ring with 2000 x 2000 quad8 cells: some 12 million nodes, far more than 512 MB hold.
  std::string big = ring;
  big.replace(big.find("nx = 4"), 6, "nx = 2000");
  big.replace(big.find("ny = 1"), 6, "ny = 2000");
  write(d / "big.toml", big);
  write(d / "ring.toml", ring);
  const Limit as{RLIMIT_AS, rlim_t{512} << 20};
  // The small ring runs under the same limit: the program itself fits in it.
  const Result small = cli({"check", "ring.toml"}, d, as);
  INFO(small.err);
  REQUIRE(small.code == 0);
  for (const char* cmd : {"check", "run"}) {
    std::vector<std::string> args{cmd, "big.toml"};
    if (std::string(cmd) == "run") args.insert(args.end(), {"--out", "o"});
    const Result r = cli(args, d, as);
    expect_one_line(r, 2,
                    "stratum: out of memory while reading big.toml and building its model: the process could "
                    "allocate no more (limit: ulimit -v 524288 kB)");
    CHECK(!fs::exists(d / "o")); // nothing written
  }
}

TEST_CASE("output paths: --out below a regular file, or over an input file, is refused before anything runs",
          "[cli][files]") {
  const fs::path d = scratch("out");
  write(d / "ring.toml", ring);
  write(d / "study.toml", point_study("[10000.0, 20000.0]"));
  write(d / "p.toml", slurp(elastic_point));
  write(d / "file", "not a folder\n");
  const std::string below = "'file' is a file, not a folder, so nothing can be written below it";
  expect_one_line(cli({"sweep", "study.toml", "--out", "file/x"}, d), 1, "--out 'file/x': " + below);
  expect_one_line(cli({"run", "ring.toml", "--out", "file/x"}, d), 1, "--out 'file/x': " + below);
  expect_one_line(cli({"point", "p.toml", "--out", "file/x.csv"}, d), 1, "--out 'file/x.csv': " + below);
  expect_one_line(cli({"fit", "duncan_chang", "ring.toml", "-o", "file/x.toml"}, d), 1,
                  "-o 'file/x.toml': " + below);
  CHECK(slurp(d / "file") == "not a folder\n");

  // The output is one of the command's inputs: refused, the input untouched.
  const std::string p = slurp(d / "p.toml");
  expect_one_line(
      cli({"point", "p.toml", "--out", "p.toml"}, d), 1,
      "--out 'p.toml' is the input file 'p.toml' of this command, which the output would overwrite");
  fs::create_hard_link(d / "p.toml", d / "link.csv");
  expect_one_line(cli({"point", "p.toml", "--out", "link.csv"}, d), 1,
                  "--out 'link.csv' is the input file 'p.toml'");
  CHECK(slurp(d / "p.toml") == p);
  expect_one_line(cli({"run", "ring.toml", "--out", "ring.toml"}, d), 1,
                  "--out 'ring.toml' is the input file 'ring.toml'");
  fs::create_directories(d / "folder");
  fs::copy_file(d / "study.toml", d / "folder" / "samples.csv");
  expect_one_line(cli({"sweep", "folder/samples.csv", "--out", "folder"}, d), 1,
                  "--out 'folder' (its samples.csv) is the input file 'folder/samples.csv'");
  write(d / "curves.csv", "sigma_3_kPa,eps_axial,q_kPa\n");
  expect_one_line(cli({"fit", "duncan_chang", "curves.csv", "-o", "curves.csv"}, d), 1,
                  "-o 'curves.csv' is the input file 'curves.csv'");
  CHECK(slurp(d / "curves.csv") == "sigma_3_kPa,eps_axial,q_kPa\n");
}

TEST_CASE("sweep: the output folder is locked for the sweep's life, and a second sweep into it is refused",
          "[cli][files][sweep]") {
  const fs::path d = scratch("lock");
  write(d / "study.toml", point_study("[10000.0, 20000.0]"));

  SECTION("the folder held by another process") {
    fs::create_directories(d / "s");
    const int fd = ::open((d / "s" / ".stratum.lock").c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
    REQUIRE(fd >= 0);
    REQUIRE(::flock(fd, LOCK_EX | LOCK_NB) == 0);
    const std::string pid = std::to_string(::getpid()) + "\n";
    REQUIRE(::write(fd, pid.data(), pid.size()) == static_cast<ssize_t>(pid.size()));
    expect_one_line(cli({"sweep", "study.toml", "--out", "s"}, d), 1,
                    "output folder 's' is being written by another stratum run or sweep (process " +
                        std::to_string(::getpid()) + "); wait for it to end or give this one another --out");
    CHECK(!fs::exists(d / "s" / "journal.csv"));
    ::close(fd);
    const Result r = cli({"sweep", "study.toml", "--out", "s"}, d);
    INFO(r.err);
    CHECK(r.code == 0);
  }
  SECTION("two sweeps at once") {
    // Enough samples that the first is still running when the second starts.
    std::string values = "[";
    for (int i = 0; i < 2000; ++i) values += (i ? ", " : "") + std::to_string(10000 + i) + ".0";
    write(d / "long.toml", point_study(values + "]"));
    const pid_t first = start({"sweep", "long.toml", "--out", "s"}, d, {}, "_first");
    // The first holds the lock once its journal exists.
    for (int i = 0; i < 600 && !fs::exists(d / "s" / "journal.csv"); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const Result second = cli({"sweep", "long.toml", "--out", "s"}, d);
    const Result one = finish(first, d, "_first");
    INFO(one.err);
    REQUIRE(one.code == 0);
    expect_one_line(second, 1,
                    "output folder 's' is being written by another stratum run or sweep (process " +
                        std::to_string(first) + ")");
    // Every sample ran once: the journal has a head line and 2000 rows.
    CHECK(lines(slurp(d / "s" / "journal.csv")) == 2001);
  }
}

TEST_CASE("sweep: [study] threads is range-checked, and a sweep whose every sample failed exits 2",
          "[cli][files][sweep]") {
  const fs::path d = scratch("threads");
  write(d / "threads.toml", point_study("[10000.0]", "threads = 100000\n"));
  expect_one_line(cli({"sweep", "threads.toml", "--out", "t"}, d), 1,
                  "threads.toml:4:11 [study] threads = 100000 must be at most 256");
  CHECK(!fs::exists(d / "t"));

  // Every Young's modulus negative: every sample fails.
  write(d / "failing.toml", point_study("[-5.0, -6.0]"));
  const Result r = cli({"sweep", "failing.toml", "--out", "f"}, d);
  INFO(r.out << r.err);
  CHECK(r.code == 2);
  CHECK(r.out.rfind("failed: every sample failed: 2 samples (0 converged, 0 stopped, 2 failed)", 0) == 0);
  CHECK(lines(r.err) >= 1);
  CHECK(r.err.find("sweep: failed: every one of the 2 samples failed (sample 0: ") != std::string::npos);
  CHECK(r.err.find("E = -5") != std::string::npos);
  CHECK(fs::exists(d / "f" / "samples.csv"));
  // One that fails among others: exit 0, as before.
  write(d / "some.toml", point_study("[10000.0, -6.0]"));
  const Result some = cli({"sweep", "some.toml", "--out", "g"}, d);
  CHECK(some.code == 0);
  CHECK(some.out.rfind("done: 2 samples (1 converged, 0 stopped, 1 failed)", 0) == 0);
}

TEST_CASE("a file-size limit (ulimit -f) ends a run with one line naming the file and exit 2, not SIGXFSZ",
          "[cli][files]") {
  const fs::path d = scratch("fsize");
  write(d / "ring.toml", ring);
  const Result r = cli({"run", "ring.toml", "--out", "o"}, d, Limit{RLIMIT_FSIZE, 2048});
  INFO("stdout: " << r.out << "\nstderr: " << r.err);
  CHECK(r.signal == 0); // not killed by SIGXFSZ
  CHECK(r.code == 2);
  CHECK(lines(r.err) == 1);
  CHECK(r.err.rfind("stratum: ring.toml: cannot write 'o/", 0) == 0);
  CHECK((r.err.find("file size limit of 2 kB reached (ulimit -f") != std::string::npos));
  CHECK(r.err.find("the files written before are whole and kept") != std::string::npos);
  // The summary says how the run ended; no temporary file is left.
  const std::string summary = slurp(d / "o" / "summary.toml");
  CHECK(summary.find("ended = 'failed'") != std::string::npos);
  CHECK(summary.find("status = 'error'") != std::string::npos);
  CHECK(summary.find("file size limit") != std::string::npos);
  for (const auto& e : fs::recursive_directory_iterator(d / "o")) CHECK(e.path().extension() != ".tmp");

  // stratum point: its table is larger than 2 kB; no table and no temporary file are left.
  write(d / "p.toml", slurp(elastic_point));
  expect_one_line(
      cli({"point", "p.toml", "--out", "p.csv"}, d, Limit{RLIMIT_FSIZE, 2048}), 2,
      "stratum: cannot write 'p.csv': file size limit of 2 kB reached (ulimit -f; File too large)");
  CHECK(!fs::exists(d / "p.csv"));
  CHECK(!fs::exists(d / ".p.csv.tmp"));
}

} // namespace test_input_files

namespace test_input_files {

TEST_CASE("every shipped scene builds and every shipped study reads its base file", "[input][cli]") {
  // The scenes of inputs/ (not the studies, points or materials) are built as `stratum check`
  // builds them; every study file of inputs/studies prints its base scene for its first sample
  // (`stratum sweep|calibrate --print-scene`), which reads and checks the study and the scene.
  const fs::path inputs = fs::path(STRATUM_SOURCE_DIR) / "inputs";
  int scenes = 0, studies = 0;
  for (const char* folder : {"loess_pile", "examples", "verification", "clay_pile"})
    for (const auto& e : fs::directory_iterator(inputs / folder)) {
      if (e.path().extension() != ".toml") continue;
      INFO(e.path().string());
      stratum::RunOptions o;
      o.plugin_dirs = {STRATUM_PLUGIN_DIR};
      CHECK_NOTHROW(stratum::Analysis::from_file(e.path().string(), o));
      ++scenes;
    }
  for (const auto& e : fs::recursive_directory_iterator(inputs / "studies")) {
    if (e.path().extension() != ".toml") continue;
    std::ifstream in(e.path());
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const bool calibration = text.find("[calibration]") != std::string::npos;
    const std::string cmd = std::string(STRATUM_EXE) + (calibration ? " calibrate " : " sweep ") +
                            e.path().string() + (calibration ? " --print-scene" : " --print-scene 0") +
                            " > /dev/null 2>&1";
    INFO(cmd);
    CHECK(std::system(cmd.c_str()) == 0);
    ++studies;
  }
  CHECK(scenes >= 15); // 19 on 2026-11-29: a guard that the folders were found
  CHECK(studies >= 8);
}

} // namespace test_input_files
