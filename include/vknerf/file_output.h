#pragma once
// Every file vknerf writes (checkpoints, images, depth maps, JSON and CSV reports) goes through
// writeFileAtomically: the target then holds either its previous content or all of the new bytes,
// never a truncated file, and every failure (full disk, missing folder, no permission) is an error
// rather than a silent 0-byte file.
#include <cstddef>
#include <string>
#include <string_view>

namespace vknerf {

// Writes to a temporary file beside `path`, checks every write and the close, flushes it to disk
// (fsync) and renames it over `path`. A target that exists and is not a regular file (a terminal,
// a pipe, /dev/null, /dev/full) is written in place with the same checks, since a special file
// cannot be replaced by a rename. On failure the temporary file is removed and vknerf::Error
// names `path` and the reason.
void writeFileAtomically(const std::string& path, const void* data, size_t size);
inline void writeFileAtomically(const std::string& path, std::string_view text) {
  writeFileAtomically(path, text.data(), text.size());
}

// Checks, before any work is spent, that writeFileAtomically(path, ...) can succeed as far as can be
// told up front: `path` is not a folder, its folder exists and is writable. Throws vknerf::Error
// naming `path` and the reason. `what` names the output in the message ("model", "--json").
void checkOutputPath(const std::string& path, const std::string& what);

}  // namespace vknerf
