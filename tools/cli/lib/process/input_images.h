#pragma once
// The photos a scene is made from: the image files of a folder, and their copies in the scene.
#include <filesystem>
#include <string>
#include <vector>

namespace vknerf::process {

// The JPEG and PNG files (by extension, any case: the formats both COLMAP and vknerf read) directly
// in `folder`, sorted by name. Throws vknerf::Error when the folder cannot be listed.
std::vector<std::filesystem::path> listImages(const std::filesystem::path& folder);

// Decodes each of `images` as vknerf reads photos (vknerf/image_io.h: PNG through stb_image, JPEG
// through libjpeg-turbo, which refuses a truncated file). Throws vknerf::Error naming the ones it
// refuses and why (the first few, and how many in all) and `folder`: COLMAP would skip them with a
// line in its log, or stop with a stack trace, minutes later.
void checkImagesDecode(const std::vector<std::filesystem::path>& images, const std::string& folder);

// Puts each of `images` into `into` (created) under its own file name, as a hard link where the
// file system allows it, else a copy. Throws vknerf::Error naming the file that failed.
void placeImages(const std::vector<std::filesystem::path>& images, const std::filesystem::path& into);

}  // namespace vknerf::process
