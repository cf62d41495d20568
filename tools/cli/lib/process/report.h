#pragma once
// The lines `vknerf process` ends with: how much of the capture COLMAP placed, how well, and the
// box training will use.
#include <cstddef>
#include <string>

#include "lib/process/scene_writer.h"
#include "lib/process/sparse_model.h"

namespace vknerf::process {

// "registered N of M images" and the rest, one fact per line.
std::string processReport(const ModelSummary& model, size_t images, const SceneBox& box, double seconds);

// The images a model must register to be kept: at least 3, and at least `share` of `images`.
size_t registeredNeeded(size_t images, double share);

}  // namespace vknerf::process
