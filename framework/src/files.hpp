// Writing a result file so that a reader never sees it half-written: the text goes to a hidden
// temporary file beside the target (".<name>.tmp"), is flushed to disk, and is then renamed over
// the target (a rename within one folder is atomic on POSIX file systems).
#pragma once

#include <string>

namespace stratum {

/// Writes `text` to `path` atomically; creates the parent folders. Throws stratum::Error naming
/// the file when it cannot be written (the temporary file is removed).
void write_file_atomically(const std::string& path, const std::string& text);

} // namespace stratum
