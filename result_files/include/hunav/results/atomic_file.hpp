#pragma once
// Result files are written whole or not at all: into a temporary file beside them, then renamed, so
// that a reader (or a crash) never sees half a file.
#include <filesystem>
#include <string_view>

namespace hunav::results {

// Writes `text` to `file` through `file`.tmp and a rename. Throws std::runtime_error naming the file
// on an I/O error.
void writeFileAtomically(const std::filesystem::path& file, std::string_view text);

}  // namespace hunav::results
