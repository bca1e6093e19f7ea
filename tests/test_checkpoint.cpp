// The checkpoint reader against damaged and forged payloads (the findings of
// tests/fuzz/fuzz_checkpoint, docs/testing.md): a payload whose CRC-32 matches but whose content
// is not what write_checkpoint writes must end in a located Error, never in a huge allocation,
// undefined behaviour or a silently accepted value.
#include "run/checkpoint.hpp"

#include <boost/crc.hpp>
#include <unistd.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace test_checkpoint {

using namespace stratum;
using Catch::Matchers::Contains;

namespace {

Checkpoint sample() {
  Checkpoint c;
  c.fingerprint = "FINGERPRINT-0123456789";
  c.part_names = {"mesh"}, c.part_digests = {"d1"}, c.part_stages = {-1};
  c.stages_done = 1, c.stage_name = "geostatic";
  c.u = {1.0, -2.0, 3.5}, c.reactions = {0.0, 0.0, 0.0};
  c.active = {1, 0}, c.constrained = {0, 1, 0};
  stage::LoadSpec l;
  l.name = "head", l.kind = stage::LoadSpec::Kind::pressure, l.set = "pile", l.p = 5.0;
  c.loads = {l};
  c.states = {{1.0, 2.0}, {3.0}};
  c.time = 1.0;
  c.water_level = PhreaticLevel{{0.0, 20.0}, {6.5, 4.5}}, c.gamma_w = 10.0;
  stage::LoadSpec w;
  w.name = "self_weight", w.kind = stage::LoadSpec::Kind::gravity, w.set = "soil", w.gamma = 18.0;
  w.water = PhreaticLevel{{0.0, 20.0}, {6.5, 4.5}}, w.gamma_below = 10.0, w.gamma_w = 10.0;
  c.loads.push_back(w);
  stage::LoadSpec q;
  q.name = "recharge", q.kind = stage::LoadSpec::Kind::inflow, q.set = "top", q.q = 2.5e-8;
  c.loads.push_back(q);
  return c;
}

std::string payload_of(const Checkpoint& c) {
  // One file per process: CTest runs these cases in parallel processes.
  const auto path = (std::filesystem::temp_directory_path() /
                     ("stratum_test_checkpoint_" + std::to_string(::getpid()) + ".ckpt"))
                        .string();
  write_checkpoint(path, c);
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  std::filesystem::remove(path);
  const std::string file = ss.str();
  return file.substr(file.find('\n') + 1);
}

/// A checkpoint file with this payload and its true CRC-32 and size in the header.
std::string with_header(const std::string& payload) {
  boost::crc_32_type crc;
  crc.process_bytes(payload.data(), payload.size());
  char header[96];
  std::snprintf(header, sizeof header, "STRATUM-CHECKPOINT %d %08x %zu\n", Checkpoint::format,
                static_cast<unsigned>(crc.checksum()), payload.size());
  return header + payload;
}

Checkpoint read(const std::string& file) {
  std::istringstream in(file, std::ios::binary);
  return read_checkpoint(in, "forged.ckpt");
}

/// The one byte offset at which two payloads of equal length differ (REQUIREs that there is one).
std::size_t only_difference(const std::string& a, const std::string& b) {
  REQUIRE(a.size() == b.size());
  std::size_t at = a.size(), n = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i] != b[i]) at = i, ++n;
  REQUIRE(n == 1);
  return at;
}

} // namespace

TEST_CASE("checkpoint: what write_checkpoint writes reads back unchanged", "[checkpoint]") {
  const Checkpoint c = sample();
  const Checkpoint r = read(with_header(payload_of(c)));
  CHECK(r.fingerprint == c.fingerprint);
  CHECK(r.u == c.u);
  CHECK(r.active == c.active);
  CHECK(r.constrained == c.constrained);
  CHECK(r.states == c.states);
  REQUIRE(r.loads.size() == 3);
  CHECK(r.loads[0].name == "head");
  CHECK(r.loads[0].p == 5.0);
  CHECK(r.loads[0].top_of_cells == false);
  CHECK(r.time == 1.0);
  // Class version 2: a sloped water table, a buoyant self-weight under it and an inflow.
  CHECK(r.water_level.x == std::vector<double>{0.0, 20.0});
  CHECK(r.water_level.y == std::vector<double>{6.5, 4.5});
  CHECK(r.gamma_w == 10.0);
  CHECK(r.loads[1].water.at(10.0) == 5.5);
  CHECK(r.loads[1].gamma_below == 10.0);
  CHECK(r.loads[1].gamma_w == 10.0);
  CHECK(r.loads[2].kind == stage::LoadSpec::Kind::inflow);
  CHECK(r.loads[2].q == 2.5e-8);
}

TEST_CASE("checkpoint: the committed fuzz seeds, written before the bounded reader, still read",
          "[checkpoint]") {
  // tests/fuzz/corpus/fuzz_checkpoint/file_*: a fuzz mode byte, then a checkpoint file that
  // `stratum run` wrote (a three-stage scene of 6 cells). The wire format did not change.
  for (const char* name : {"file_1_geostatic", "file_3_loading"}) {
    std::ifstream in(std::string(STRATUM_SOURCE_DIR) + "/tests/fuzz/corpus/fuzz_checkpoint/" + name,
                     std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    const Checkpoint c = read(ss.str().substr(1));
    CHECK(c.u.size() == 24); // 12 nodes
    CHECK(c.stages_done == (name[5] == '1' ? 1 : 3));
    CHECK(!c.water_level.present()); // written before the water table (class version 0): dry
    for (const auto& l : c.loads) CHECK(!l.water.present());
  }
}

TEST_CASE("checkpoint: a forged count is refused before anything is allocated for it", "[checkpoint]") {
  // The fingerprint's length (8 bytes, little-endian) precedes its text; 2^40 would have been a
  // 1 TB string (AddressSanitizer: allocation-size-too-big, found by fuzz_checkpoint).
  std::string p = payload_of(sample());
  const auto at = p.find("FINGERPRINT-0123456789");
  REQUIRE(at != std::string::npos);
  const std::uint64_t forged = std::uint64_t{1} << 40;
  for (int k = 0; k < 8; ++k) p[at - 8 + k] = static_cast<char>((forged >> (8 * k)) & 0xff);
  REQUIRE_THROWS_WITH(read(with_header(p)), Contains("forged.ckpt: damaged checkpoint") &&
                                                Contains("a count of 1099511627776 exceeds the"));
}

TEST_CASE("checkpoint: a flag byte other than 0 or 1 is refused", "[checkpoint]") {
  // Loading such a byte into a bool is undefined behaviour (UBSan, found by fuzz_checkpoint).
  Checkpoint c = sample();
  const std::string off = payload_of(c);
  c.loads[0].top_of_cells = true;
  std::string p = payload_of(c);
  const std::size_t at = only_difference(off, p);
  p[at] = 2;
  REQUIRE_THROWS_WITH(read(with_header(p)), Contains("a flag stored as 2, not 0 or 1"));
}

TEST_CASE("checkpoint: a load kind outside the enumeration is refused", "[checkpoint]") {
  Checkpoint c = sample();
  const std::string pressure = payload_of(c);
  c.loads[0].kind = stage::LoadSpec::Kind::gravity; // 0 -> 2: one byte of the int differs
  std::string p = payload_of(c);
  const std::size_t at = only_difference(pressure, p);
  p[at] = 7;
  REQUIRE_THROWS_WITH(read(with_header(p)), Contains("load 'head' has kind 7"));
}

TEST_CASE("checkpoint: a payload cut or forged inside the archive header is refused", "[checkpoint]") {
  // Boost reads its header with assertions only (an assertion failure under the sanitizer build,
  // found by fuzz_checkpoint): the header is compared with the one this build writes.
  const std::string p = payload_of(sample());
  const auto sig = p.find("serialization::archive");
  REQUIRE(sig != std::string::npos);
  const std::string cut = p.substr(0, sig + 22); // the signature, then nothing
  REQUIRE_THROWS_WITH(read(with_header(cut)),
                      Contains("does not start with the") && Contains("archive header"));
  std::string forged = p;
  forged[sig + 22] = static_cast<char>(0xff); // the library version
  REQUIRE_THROWS_WITH(read(with_header(forged)), Contains("archive header"));
}

} // namespace test_checkpoint
