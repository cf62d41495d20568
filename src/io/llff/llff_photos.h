#pragma once
// Which folder beside LLFF's poses_bounds.npy a load takes its photos from. LLFF ships the photos at
// the size hwf states in images/ and copies N times smaller in images_N/; scenes are often shared
// with images_N/ alone (the full-size photos are large), and those load too.
#include <cstdint>
#include <filesystem>
#include <vector>

namespace vknerf::io::detail {

struct LlffPhotos {
  std::vector<std::filesystem::path> files;  // one per row of the .npy, in sorted name order
  uint32_t factor = 1;     // how many times smaller than hwf states they are: images_N/'s N, 1 for images/
  uint32_t downscale = 1;  // what Dataset::load still shrinks them by
};

// The photos for a load asking for `downscale` (relative to hwf's size) of the scene in `file`'s
// folder, of `rows` rows whose first states hwf's `width` x `height` (for the note):
// - images_<downscale>/ when it exists, read as it is;
// - else images/, shrunk by `downscale`;
// - with no images/, the images_N/ that serves the request: that of the largest N dividing
//   `downscale`, shrunk by the rest; else, when some N exceeds it, the smallest such, as it is (the
//   nearest to what was asked, the finest of all for the default downscale 1). It says which on
//   stderr, once.
// Throws, naming the folders, when none fits or a folder does not hold one photo per row.
LlffPhotos findLlffPhotos(const std::filesystem::path& file, size_t rows, uint32_t downscale, uint32_t width,
                          uint32_t height);

}  // namespace vknerf::io::detail
