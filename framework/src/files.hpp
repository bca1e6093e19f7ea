// Reading an input file whole, and writing a result file so that a reader never sees it
// half-written: the text goes to a hidden temporary file beside the target (".<name>.tmp"), is
// flushed to disk, and is then renamed over the target (a rename within one folder is atomic on
// POSIX file systems).
//
// Every input file goes through read_text_file (or check_input_file): only a regular file is
// read (a FIFO would block, /dev/zero never ends), and only up to the size limit of its kind.
#pragma once

#include "stratum/error.hpp"

#include <cstdint>
#include <string>

namespace stratum {

/// A result file could not be written (disk full, file size limit, I/O error): the run ends
/// there, as a failure of its environment rather than of its input (`stratum run`: exit 2).
class WriteError : public Error {
public:
  using Error::Error;
  ~WriteError() override;
};

/// The most an input file of a kind may hold, and the kind's name in the message that refuses
/// a larger one (README.md, "Input files").
struct FileLimit {
  std::uintmax_t megabytes;
  const char* kind;
};
namespace file_limits {
inline constexpr FileLimit scene{16, "scene file"}; ///< a scene and each file it includes
inline constexpr FileLimit point{16, "point file"};
inline constexpr FileLimit study{16, "study file"};
inline constexpr FileLimit mesh{2048, "mesh file"};
inline constexpr FileLimit checkpoint{4096, "checkpoint"};
inline constexpr FileLimit csv{256, "CSV file"};
inline constexpr FileLimit journal{1024, "sweep journal"};
inline constexpr FileLimit manifest{1, "plugin manifest"};
inline constexpr FileLimit library{4096, "plugin library"}; ///< read whole only for its checksum
} // namespace file_limits

/// Writes `text` to `path` atomically; creates the parent folders. Throws WriteError naming
/// the file when it cannot be written (the temporary file is removed).
void write_file_atomically(const std::string& path, const std::string& text);

/// Why a write failed, from its errno: EFBIG says which file size limit (ulimit -f) was reached,
/// ENOSPC that the disk is full; otherwise strerror.
[[nodiscard]] std::string write_failure(int err);

/// The bytes of the file at `path`. Throws Error at `where` (a located line when `where` has a
/// line, else "<path>: ...") when it cannot be opened, is a folder, is not a regular file (a
/// FIFO, a device) or is larger than `limit`; `what` names it ("scene file", "included file").
[[nodiscard]] std::string read_text_file(const std::string& path, const SourceLocation& where,
                                         const std::string& what, const FileLimit& limit);

/// The same checks without reading: the size of the regular file at `path`, for a reader that
/// streams it (a checkpoint).
std::uintmax_t check_input_file(const std::string& path, const SourceLocation& where, const std::string& what,
                                const FileLimit& limit);

} // namespace stratum
