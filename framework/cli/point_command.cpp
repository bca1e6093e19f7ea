// `stratum point`: one material point driven along the stress or strain paths of a point file.
#include "point_command.hpp"

#include "guards.hpp"
#include "stratum/point_driver.hpp"

#include <filesystem>
#include <iostream>
#include <system_error>

namespace stratum::cli {

namespace {

constexpr const char* point_help_text =
    "usage: stratum point POINT.toml [--out FILE.csv]\n"
    "\n"
    "Drives one material point along the stress or strain paths of the point file (a triaxial or\n"
    "oedometer test without a mesh) and writes one CSV row per step. Stresses are in kPa unless\n"
    "the point file declares [units] as a scene does (force = \"N\", length = \"mm\": MPa, and the\n"
    "columns read p_MPa, q_MPa).\n"
    "\n"
    "options:\n"
    "  --out FILE.csv   the table (default out/<point file name>.csv); written to a temporary\n"
    "                   file and renamed, so a regular file or a new name only, never the point\n"
    "                   file itself\n"
    "  -h, --help       this text\n"
    "\n"
    "exit status: 0 done, 1 bad input (one located line on stderr), 2 the material failed on the\n"
    "  path (the rows computed before are written), the table could not be written or memory ran\n"
    "  out, 3 internal error\n";

} // namespace

std::string point_help() { return point_help_text; }

int point(const std::vector<std::string>& args) {
  std::string file, out;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--out") {
      if (i + 1 >= args.size()) throw Error("--out needs a file name");
      out = args[++i];
    } else if (!args[i].empty() && args[i][0] == '-') {
      throw Error("unknown option '" + args[i] + "'; allowed: --out FILE.csv");
    } else if (file.empty()) {
      file = args[i];
    } else {
      throw Error("more than one point file given ('" + file + "', '" + args[i] + "')");
    }
  }
  if (file.empty()) throw Error("no point file given (see stratum --help)");
  if (out.empty())
    out = (std::filesystem::path("out") / (std::filesystem::path(file).stem().string() + ".csv")).string();
  cli::refuse_output_over_inputs("--out", out, {file});
  cli::refuse_output_below_file("--out", out);
  // The CSV is written to a temporary file and renamed over the target: a symlink or a device
  // there would be replaced by a regular file (as root, /dev/full was), so only a regular file
  // or a new name is taken.
  if (std::error_code ec; std::filesystem::exists(std::filesystem::symlink_status(out, ec)) &&
                          !std::filesystem::is_regular_file(std::filesystem::symlink_status(out, ec)))
    throw Error("--out '" + out +
                "' exists and is not a regular file (a symlink, folder or device); give a new "
                "or a regular file name");
  const PointRun r = cli::in_phase("running the point file " + file, [&] {
    const auto driver = PointDriver::from_file(file);
    return driver->run();
  });
  PointDriver::write_csv(r, out); // what was computed is kept, also after a failure
  if (!r.outcome.ok()) {
    std::cerr << "stratum: " << file << ": " << to_string(r.outcome.status) << ": " << r.outcome.message
              << "\nstratum: " << out << " holds the " << r.rows.size() - 1
              << " steps before the failure (row 0: the initial state)\n";
    return 2;
  }
  std::cout << "done: " << r.rows.size() - 1 << " steps\nresults: " << out << "\n";
  return 0;
}

} // namespace stratum::cli
