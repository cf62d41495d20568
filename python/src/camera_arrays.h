#pragma once
// Cameras to and from NumPy: a pose is a (4, 4) camera-to-world matrix in vknerf's (OpenGL)
// convention; intrinsics are (fx, fy, cx, cy) or a 3x3 matrix K; distortion is OpenCV's
// coefficient vector (k1, k2, p1, p2[, k3[, k4, k5, k6]]) or, for lens="fisheye", (k1, k2, k3, k4).
#include <pybind11/numpy.h>

#include <string>

#include "vknerf/camera.h"

namespace vknerf::python {

void setPose(Camera& c, const float* rowMajor16);
void setIntrinsics(Camera& c, const pybind11::handle& intrinsics, const std::string& name);
void setLens(Camera& c, const pybind11::handle& distortion, const std::string& lens, const std::string& name);

pybind11::array_t<float> poseArray(const Camera& c);
pybind11::array_t<float> distortionArray(const Lens& lens);
const char* lensName(LensModel m);

}  // namespace vknerf::python
