#include "run/checkpoint.hpp"

#include "files.hpp"

#include <boost/archive/binary_iarchive_impl.hpp>
#include <boost/archive/binary_oarchive.hpp>
#include <boost/archive/impl/archive_serializer_map.ipp>
#include <boost/archive/impl/basic_binary_iarchive.ipp>
#include <boost/archive/impl/basic_binary_iprimitive.ipp>
#include <boost/crc.hpp>
#include <boost/serialization/string.hpp>
#include <boost/serialization/vector.hpp>
#include <boost/serialization/version.hpp>

// Class versions of what a checkpoint holds (the header's format stays 2: Boost writes each class's
// version into the archive, and a reader of version 1 reads version 0 archives as they were).
// Version 1 (2026-11-29): the model's water table, and a gravity load's level and buoyant weight.
BOOST_CLASS_VERSION(stratum::Checkpoint, 2)
BOOST_CLASS_VERSION(stratum::LoadSpec, 2)

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace fs = std::filesystem;

namespace stratum {
namespace {

/// Boost's binary input archive with every count and length it reads (collections, strings, the
/// archive's own signature) bounded by the payload's size: each element takes at least one byte,
/// so a larger count is damage, and it is refused before anything is allocated for it (a payload
/// whose CRC matches but whose counts are forged made the reader request petabytes; found by
/// tests/fuzz/fuzz_checkpoint). The wire format is binary_iarchive's.
class BoundedArchive
    : public boost::archive::binary_iarchive_impl<BoundedArchive, char, std::char_traits<char>> {
  using Base = boost::archive::binary_iarchive_impl<BoundedArchive, char, std::char_traits<char>>;
  friend class boost::archive::detail::interface_iarchive<BoundedArchive>;
  friend class boost::archive::basic_binary_iarchive<BoundedArchive>;
  friend class boost::archive::basic_binary_iprimitive<BoundedArchive, char, std::char_traits<char>>;
  friend class boost::archive::load_access;

public:
  BoundedArchive(std::istream& in, std::size_t limit) : Base(in, 0), limit_(limit) { init(0); }

protected:
  using Base::load;
  using Base::load_override;
  void load_override(boost::serialization::collection_size_type& t) {
    Base::load_override(t);
    check(t);
  }
  void load(std::string& s) {
    std::size_t n = 0;
    load(n);
    check(n);
    s.resize(n);
    if (n > 0) load_binary(s.data(), n);
  }
  // binary_iarchive copies the byte into the bool: any value but 0 and 1 is undefined behaviour
  // (UBSan under tests/fuzz/fuzz_checkpoint).
  void load(bool& b) {
    unsigned char byte = 0;
    load_binary(&byte, 1);
    if (byte > 1) throw Error("a flag stored as " + std::to_string(byte) + ", not 0 or 1");
    b = byte == 1;
  }

private:
  void check(std::size_t n) const {
    if (n > limit_)
      throw Error("a count of " + std::to_string(n) + " exceeds the " + std::to_string(limit_) +
                  " payload bytes");
  }
  std::size_t limit_;
};

} // namespace
} // namespace stratum

BOOST_SERIALIZATION_REGISTER_ARCHIVE(stratum::BoundedArchive)
BOOST_SERIALIZATION_USE_ARRAY_OPTIMIZATION(stratum::BoundedArchive)
template class boost::archive::basic_binary_iprimitive<stratum::BoundedArchive, char, std::char_traits<char>>;
template class boost::archive::basic_binary_iarchive<stratum::BoundedArchive>;
template class boost::archive::binary_iarchive_impl<stratum::BoundedArchive, char, std::char_traits<char>>;
template class boost::archive::detail::archive_serializer_map<stratum::BoundedArchive>;

namespace stratum {

namespace {
constexpr const char* magic = "STRATUM-CHECKPOINT";

/// The bytes every payload starts with: Boost's archive header as this build writes it (signature,
/// library version, sizes). Boost reads it with assertions only, so a payload cut or forged inside
/// it was not reported but asserted or read on (found by tests/fuzz/fuzz_checkpoint).
std::string archive_header() {
  std::ostringstream s(std::ios::binary);
  { boost::archive::binary_oarchive ar(s); }
  return s.str();
}

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
  std::ostringstream header;
  header << magic << ' ' << Checkpoint::format << ' ' << std::hex << std::setw(8) << std::setfill('0')
         << crc32(bytes) << std::dec << ' ' << bytes.size() << '\n';
  // A temporary file renamed over the target; a failed write (disk full, file size limit) is a
  // WriteError naming the checkpoint.
  write_file_atomically(path, header.str() + bytes);
}

Checkpoint read_checkpoint(const std::string& path) {
  // A regular file within the limit only: /dev/zero has no end and no header line.
  (void)check_input_file(path, SourceLocation{}, "checkpoint", file_limits::checkpoint);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open the checkpoint");
  return read_checkpoint(in, path);
}

Checkpoint read_checkpoint(std::istream& in, const std::string& path) {
  // The header line is short ("STRATUM-CHECKPOINT 3 1a2b3c4d 12345"): at most 128 bytes are
  // looked at, so that a file without a newline is not read whole as its header.
  std::string header;
  for (char ch = 0; header.size() < 128 && in.get(ch) && ch != '\n';) header += ch;
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
  if (const std::string h = archive_header(); bytes.compare(0, h.size(), h) != 0)
    throw Error(
        path + ": damaged checkpoint: the payload does not start with the " + std::to_string(h.size()) +
        "-byte archive header this build writes (Boost.Serialization binary archive, library version " +
        std::to_string(static_cast<unsigned>(boost::archive::BOOST_ARCHIVE_VERSION())) + ")");
  Checkpoint c;
  try {
    std::istringstream payload(bytes, std::ios::binary);
    BoundedArchive ar(payload, size);
    ar >> c;
  } catch (const std::exception& e) {
    throw Error(path + ": damaged checkpoint: " + e.what());
  }
  for (const auto& l : c.loads)
    if (l.kind != stage::LoadSpec::Kind::pressure && l.kind != stage::LoadSpec::Kind::force &&
        l.kind != stage::LoadSpec::Kind::gravity && l.kind != stage::LoadSpec::Kind::inflow)
      throw Error(path + ": damaged checkpoint: load '" + l.name + "' has kind " +
                  std::to_string(static_cast<int>(l.kind)) +
                  ", not one of 0 (pressure), 1 (force), 2 (gravity), 3 (inflow)");
  return c;
}

} // namespace stratum
