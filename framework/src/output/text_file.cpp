#include "output/text_file.hpp"

#include "stratum/error.hpp"

#include <fstream>

namespace fs = std::filesystem;

namespace stratum {

void write_text_atomically(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << text;
    if (!out) throw Error("cannot write " + tmp.string());
  }
  fs::rename(tmp, path);
}

} // namespace stratum
