// Replacing one program's section of docs/benchmarks.md (between its begin and end
// markers), keeping the rest of the file; written to a temporary file and renamed.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace stratum::bench {

/// `block` must start with `begin_marker` and end with `end_marker` (and a newline).
inline void replace_docs_section(const std::filesystem::path& path, const std::string& begin_marker,
                                 const std::string& end_marker, const std::string& block) {
  std::string old;
  {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    old = ss.str();
  }
  std::string text;
  const auto b = old.find(begin_marker);
  const auto e = b == std::string::npos ? std::string::npos : old.find(end_marker, b);
  if (e != std::string::npos) {
    auto after = e + end_marker.size();
    if (after < old.size() && old[after] == '\n') ++after;
    text = old.substr(0, b) + block + old.substr(after);
  } else if (old.empty()) {
    text =
        "# Benchmarks\n\nMeasured figures of Stratum's benchmark programs (`tools/bench`). Each section is "
        "rewritten by the program named in it.\n\n" +
        block;
  } else {
    text = old + (old.back() == '\n' ? "\n" : "\n\n") + block;
  }
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  const auto tmp = path.parent_path() / ("." + path.filename().string() + ".tmp");
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, path);
}

} // namespace stratum::bench
