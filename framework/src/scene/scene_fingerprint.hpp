// What a checkpoint must agree on with the scene that restarts from it (internal).
//
// The resolved scene is cut into parts, each with a digest of its canonical text: the program
// version, the formulation, the built mesh (coordinates, cells, sets, after interface splits),
// every [materials.*] and [contact_laws.*] table, [[domains]], [[interfaces]], [[constraints]]
// and, per stage, its [[stages]] table (or [[loads]] in a scene without stages). A checkpoint
// written after stage k keeps the global parts and those of stages 1..k; a restart compares
// exactly those, so the later stages may change (that is what a restart is for) and nothing
// that shaped the saved state may. A [materials.*] table that only a stage's change_material names
// belongs to that stage, not to the global parts. Comments and key order in the file do not matter.
#pragma once

#include "stratum/error.hpp"
#include "stratum/mesh.hpp"

#include <toml++/toml.h>

#include <cstdint>
#include <string>
#include <vector>

namespace stratum {

struct FingerprintPart {
  std::string name;   ///< e.g. "[materials.concrete]", "[[stages]] #2 \"boring\"", "mesh"
  std::string digest; ///< 16 hex digits (FNV-1a 64 of the canonical text)
  /// -1: global; >= 0: the 0-based stage the part belongs to; if_both: global, compared only
  /// when both scenes have it (a plugin library: a restart may open libraries that only its
  /// later stages use, and a checkpoint written before libraries were recorded has none).
  int stage = -1;
  SourceLocation where;
  static constexpr int if_both = -2;
};

/// 16 hex digits of the 64-bit FNV-1a hash of `text`.
[[nodiscard]] std::string digest_of(const std::string& text);

/// The parts of a scene: `root` its TOML (the [[stages]] tables, or the [[loads]] of a scene
/// without stages as stage 0). The mesh's part (its name is mesh_part_name) has an empty digest
/// until the mesh is built: set it to mesh_digest() of the built mesh.
[[nodiscard]] std::vector<FingerprintPart> scene_parts(const toml::table& root,
                                                       const std::string& program_version);

inline constexpr const char* mesh_part_name = "the mesh (nodes, cells and sets as built)";

/// The digest of a built mesh: coordinates, cells and sets, after interface splits.
[[nodiscard]] std::string mesh_digest(const Mesh& mesh);

/// One part per plugin library the scene opened (`paths`): "plugin library <file name>" with the
/// digest of the file's bytes, so that a restart with a rebuilt or changed model library is
/// refused (the saved states were computed by the other one). Throws Error when a file cannot
/// be read.
[[nodiscard]] std::vector<FingerprintPart> library_parts(const std::vector<std::string>& paths);

/// The first part of `saved` (a checkpoint's, written after `stages_done` stages) that the scene's
/// `current` parts do not reproduce, as a message; "" when they agree.
[[nodiscard]] std::string fingerprint_mismatch(const std::vector<FingerprintPart>& saved,
                                               const std::vector<FingerprintPart>& current, int stages_done,
                                               SourceLocation* where);

} // namespace stratum
