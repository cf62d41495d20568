#pragma once
// COLMAP's camera models, shared by the text and binary model readers: the id the binary files
// store, the name the text files store, the parameter count, and the mapping onto Intrinsics.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "io/dataset/dataset_loaders.h"

namespace vknerf::io::detail {

struct ColmapCameraModel {
  int id;  // COLMAP's model id (sensor/models.h), as cameras.bin stores it
  const char* name;
  size_t params;
};

// nullptr for a name or id COLMAP does not define.
const ColmapCameraModel* colmapModelByName(std::string_view name);
const ColmapCameraModel* colmapModelById(int64_t id);

// Intrinsics of a width x height camera of `model` from its `params` (model.params of them), its
// distortion as a Lens: SIMPLE_RADIAL, RADIAL, OPENCV and FULL_OPENCV as LensModel::OpenCV,
// OPENCV_FISHEYE, SIMPLE_RADIAL_FISHEYE and RADIAL_FISHEYE as LensModel::Fisheye, and any model whose
// distortion parameters are all zero as a pinhole. Throws vknerf::Error starting with `where` for a
// model vknerf cannot use (FOV, THIN_PRISM_FISHEYE), a size out of range, a non-positive focal
// length, parameters that are not finite as floats or a lens that does not invert over the image
// (checkLens, vknerf/camera.h).
Intrinsics colmapIntrinsics(const ColmapCameraModel& model, uint64_t cameraId, uint64_t width, uint64_t height,
                            std::span<const double> params, const std::string& where);

}  // namespace vknerf::io::detail
