#include "checkpoint.hpp"

#include <boost/archive/binary_iarchive.hpp>
#include <boost/archive/binary_oarchive.hpp>
#include <boost/crc.hpp>
#include <boost/serialization/string.hpp>
#include <boost/serialization/vector.hpp>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace fs = std::filesystem;

namespace stratum {

namespace {
constexpr const char* magic = "STRATUM-CHECKPOINT";

std::uint32_t crc32(const std::string& s) {
  boost::crc_32_type crc;
  crc.process_bytes(s.data(), s.size());
  return crc.checksum();
}
} // namespace

void write_checkpoint(const std::string& path, const Checkpoint& c) {
  std::ostringstream payload(std::ios::binary);
  {
    boost::archive::binary_oarchive ar(payload);
    ar << c;
  }
  const std::string bytes = payload.str();
  const fs::path target(path);
  if (target.has_parent_path()) fs::create_directories(target.parent_path());
  const fs::path tmp = target.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error("cannot write checkpoint " + tmp.string());
    out << magic << ' ' << Checkpoint::format << ' ' << std::hex << std::setw(8) << std::setfill('0')
        << crc32(bytes) << std::dec << ' ' << bytes.size() << '\n';
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) throw Error("cannot write checkpoint " + tmp.string());
  }
  fs::rename(tmp, target);
}

Checkpoint read_checkpoint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open the checkpoint");
  std::string header;
  std::getline(in, header);
  std::istringstream hs(header);
  std::string m, crc_hex;
  int format = 0;
  std::size_t size = 0;
  hs >> m >> format >> crc_hex >> size;
  if (m != magic || !hs)
    throw Error(path + ": not a Stratum checkpoint (the first line must start with " + magic + ")");
  if (format != Checkpoint::format)
    throw Error(path + ": checkpoint format " + std::to_string(format) +
                " is not supported; this build reads " + std::to_string(Checkpoint::format));
  // The size field is checked against what the file holds before anything is allocated for it.
  const auto here = in.tellg();
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  in.seekg(here);
  if (here < 0 || end < here || size != static_cast<std::size_t>(end - here))
    throw Error(path + ": damaged checkpoint: the header announces " + std::to_string(size) +
                " payload bytes, the file holds " + std::to_string(end >= here ? end - here : 0));
  std::string bytes(size, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::size_t>(in.gcount()) != size || in.peek() != std::char_traits<char>::eof())
    throw Error(path + ": damaged checkpoint: the payload is not the " + std::to_string(size) +
                " bytes the header announces");
  std::ostringstream want;
  want << std::hex << std::setw(8) << std::setfill('0') << crc32(bytes);
  if (want.str() != crc_hex)
    throw Error(path + ": damaged checkpoint: CRC-32 is " + want.str() + ", the header says " + crc_hex);
  Checkpoint c;
  try {
    std::istringstream payload(bytes, std::ios::binary);
    boost::archive::binary_iarchive ar(payload);
    ar >> c;
  } catch (const std::exception& e) {
    throw Error(path + ": damaged checkpoint: " + e.what());
  }
  return c;
}

} // namespace stratum
