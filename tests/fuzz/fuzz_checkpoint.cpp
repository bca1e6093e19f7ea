// libFuzzer target: the checkpoint reader (framework/src/run/checkpoint.cpp, read_checkpoint) from bytes.
//
// The first byte chooses how the rest is used:
//  * even: the rest is a whole checkpoint file (header line and payload) as read from disk;
//  * odd: the rest is a payload; a header with its true CRC-32 and size is put in front, so the
//    mutations reach the Boost archive behind the checksum (a damaged or hostile file whose CRC
//    happens to match).
// The contract checked: a damaged checkpoint ends in stratum::Error naming the file; any other
// exception aborts here, as do the sanitizers' findings.
#include "run/checkpoint.hpp"

#include "stratum/error.hpp"

#include <boost/crc.hpp>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return -1;
  std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] % 2 == 1) {
    boost::crc_32_type crc;
    crc.process_bytes(bytes.data(), bytes.size());
    char header[96];
    std::snprintf(header, sizeof header, "STRATUM-CHECKPOINT %d %08x %zu\n", stratum::Checkpoint::format,
                  static_cast<unsigned>(crc.checksum()), bytes.size());
    bytes.insert(0, header);
  }
  try {
    std::istringstream in(bytes, std::ios::binary);
    const stratum::Checkpoint c = stratum::read_checkpoint(in, "fuzz.ckpt");
    (void)c;
  } catch (const stratum::Error&) {
    // a damaged checkpoint, reported as it should be
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_checkpoint: internal error (not a stratum::Error): %s\n", e.what());
    std::abort();
  }
  return 0;
}
