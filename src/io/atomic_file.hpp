#pragma once
// Files appear whole or not at all: written to a temporary beside the target, then renamed.
#include <functional>
#include <iosfwd>
#include <string>

namespace weft {

// Calls `write` on a stream to a temporary file next to `path`, checks the stream, then renames
// it over `path`. On any failure the temporary is removed and IoError names `path` and the cause.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace weft
