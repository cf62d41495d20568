#pragma once
// The training cameras as the frames of a transforms.json written to another folder (vknerf export
// cameras): each frame must name its image from the file's folder and state the image's own size,
// or the file does not load.
#include <string>
#include <vector>

#include "vknerf/camera.h"

namespace vknerf::nerf {

// `cameras` as frames of a file written to `output`:
//   - a relative name that names a file from the current folder (the folder training ran in, as a
//     rule) is made relative to the output's folder, from which the loader reads file_path; an
//     absolute name, or one that names no file here, is kept as it is;
//   - a camera whose image is k times its size (training's --downscale k: the image's width and
//     height divided by k, rounded down, as Dataset::load does) is scaled back up to the image: its
//     focal lengths and principal point times k, the image's size. The file then loads with
//     --downscale k as it was trained (exactly when k is a power of two). Without its image a camera
//     is kept as it is.
// Throws vknerf::Error naming the camera and its image when the image is neither its size nor a
// multiple of it: the image is not the one it was trained on.
std::vector<TrainedCamera> framesForFile(const std::vector<TrainedCamera>& cameras, const std::string& output);

}  // namespace vknerf::nerf
