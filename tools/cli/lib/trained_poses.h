#pragma once
// Training views evaluated where the model learned they were: with camera refinement a checkpoint
// records each training photo's refined pose (Model::trainingCameras), and scoring a training view
// at the dataset's pose would misalign the render with its photo by the correction.
#include <cstddef>
#include <string>
#include <vector>

#include "vknerf/camera.h"

namespace vknerf::nerf {

// Gives each camera whose image name (names[i], as Dataset::names holds it) is a trained camera's
// name that camera's pose (c2w); intrinsics, size and lens stay the dataset's (the evaluation's
// --downscale may differ from training's). Returns how many took a trained pose. Names that match
// no trained camera (another folder, another scene) keep theirs.
size_t useTrainedPoses(std::vector<Camera>& cameras, const std::vector<std::string>& names,
                       const std::vector<TrainedCamera>& trained);

}  // namespace vknerf::nerf
