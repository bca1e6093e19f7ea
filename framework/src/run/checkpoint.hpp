// Checkpoints written at the end of every stage and read by `stratum run --restart-from`.
//
// File layout: a text header line "STRATUM-CHECKPOINT <format> <crc32 hex> <payload bytes>\n"
// followed by a Boost.Serialization binary archive (the payload). The CRC-32 covers the
// payload; the scene fingerprint inside it must match the scene being restarted.
#pragma once

#include "stages/stage.hpp"

#include <istream>
#include <limits>
#include <string>
#include <vector>

namespace stratum {

struct Checkpoint {
  static constexpr int format = 2;
  std::string fingerprint; ///< mesh, domains and stage list of the scene that wrote it
  /// The resolved scene's parts that shaped the saved state (scene_fingerprint.hpp): name,
  /// digest and stage (-1 global) of each.
  std::vector<std::string> part_names, part_digests;
  std::vector<int> part_stages;
  int stages_done = 0;    ///< stages completed (the restart runs stage stages_done + 1 on)
  std::string stage_name; ///< name of the last completed stage
  std::vector<double> u, reactions;
  std::vector<char> active, constrained;
  std::vector<stage::LoadSpec> loads;
  std::vector<std::vector<double>> states; ///< committed state store of every domain
  double time = 0.0;                       ///< output time reached
  /// Model::water (no level: dry); class version 1 on (docs/design.md: a checkpoint of version 0,
  /// written before the water, reads as dry; version 1 holds a horizontal level as one number,
  /// version 2 a PhreaticLevel).
  PhreaticLevel water_level;
  double gamma_w = 9.81;

  template <class Ar> void serialize(Ar& ar, unsigned version) {
    ar& fingerprint& part_names& part_digests& part_stages& stages_done& stage_name& u& reactions& active&
        constrained& loads& states& time;
    if (version == 1) {
      double level = -std::numeric_limits<double>::infinity();
      ar& level& gamma_w;
      if (level > -std::numeric_limits<double>::infinity()) water_level = PhreaticLevel::horizontal(level);
    }
    if (version >= 2) ar& water_level& gamma_w;
  }
};

/// Writes atomically (temporary file, then rename). Throws Error when the file cannot be written.
void write_checkpoint(const std::string& path, const Checkpoint& c);
/// Reads and verifies header, size and checksum. Throws Error naming the file and the defect.
Checkpoint read_checkpoint(const std::string& path);
/// The same from a seekable binary stream; `path` names it in messages (tests/fuzz/fuzz_checkpoint.cpp).
Checkpoint read_checkpoint(std::istream& in, const std::string& path);

} // namespace stratum
