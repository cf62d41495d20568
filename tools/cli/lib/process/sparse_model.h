#pragma once
// The models COLMAP's mapper leaves in sparse/0, sparse/1, ... (one per connected set of images),
// summarised from their binary files, and the largest of them.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

namespace vknerf::process {

struct ModelSummary {
  std::filesystem::path folder;
  uint64_t registeredImages = 0;
  uint64_t points = 0;
  double meanReprojectionError = 0;  // pixels: the mean over points of each point's mean error, as COLMAP reports it
};

// A summary of the binary model in `folder` (images.bin, points3D.bin). Throws vknerf::Error naming
// the file when one is missing or truncated.
ModelSummary summarizeModel(const std::filesystem::path& folder);

// The model with the most registered images (then the most points) among the sub-folders of
// `sparse` holding images.bin; nullopt when there is none.
std::optional<ModelSummary> largestModel(const std::filesystem::path& sparse);

}  // namespace vknerf::process
