#pragma once

#include <string>

#include "longterm_mapper2d/core/common/status.h"

namespace longterm_mapper2d {

// Replaces the file at `path` with `bytes` so that readers see either the old file or the complete
// new one, never a partial write: the bytes go to a temporary file in the same folder (rename is
// only atomic within one file system), are flushed to disk, then renamed over `path`. Any disk
// error (missing folder, full disk, permissions) is returned and leaves `path` untouched.
Status WriteFileAtomically(const std::string& path, const std::string& bytes);

// Creates a folder and its missing parents (like mkdir -p).
Status MakeDirectories(const std::string& directory);

// Reads a whole file as bytes.
StatusOr<std::string> ReadFileBytes(const std::string& path);

}  // namespace longterm_mapper2d
