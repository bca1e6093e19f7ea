// Writing a text file atomically (a temporary file, then rename).
#pragma once

#include <filesystem>
#include <string>

namespace stratum {

/// Creates the parent folders; throws Error when the file cannot be written.
void write_text_atomically(const std::filesystem::path& path, const std::string& text);

} // namespace stratum
