#pragma once
// A folder of this fuzzing process's own under the temporary directory, for loaders that read a
// scene folder: created once, removed at exit, its files rewritten for every input.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

namespace vknerf::fuzz {

namespace fs = std::filesystem;

// The process's folder (created on first use).
const fs::path& scratchFolder();

// Replaces `path` with `size` bytes (creating its folders); aborts when it cannot, since a fuzzer
// that silently loads the previous input's file would report nonsense.
void writeBytes(const fs::path& path, const uint8_t* data, size_t size);

// Writes a small RGBA PNG of width x height whose left third is transparent (so that the datasets'
// alpha carving has something to work with).
void writeTinyPng(const fs::path& path, uint32_t width, uint32_t height);

}  // namespace vknerf::fuzz
