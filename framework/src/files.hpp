// Reading an input file whole, and writing a result file so that a reader never sees it
// half-written: the text goes to a hidden temporary file beside the target (".<name>.tmp"), is
// flushed to disk, and is then renamed over the target (a rename within one folder is atomic on
// POSIX file systems).
#pragma once

#include "stratum/error.hpp"

#include <string>

namespace stratum {

/// Writes `text` to `path` atomically; creates the parent folders. Throws stratum::Error naming
/// the file when it cannot be written (the temporary file is removed).
void write_file_atomically(const std::string& path, const std::string& text);

/// The bytes of the file at `path`. Throws Error at `where` ("cannot open <what> '<path>'") when
/// it cannot be opened or is a folder.
[[nodiscard]] std::string read_text_file(const std::string& path, const SourceLocation& where,
                                         const std::string& what);

} // namespace stratum
