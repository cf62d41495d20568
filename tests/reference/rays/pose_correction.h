#pragma once
// Camera refinement's pose algebra is production's (src/core/camera/pose_algebra.h: the host writes
// the refined poses with it); the tests take it as the oracle of shaders/rays/so3.glsl and
// camera_correct.comp.
#include "core/camera/pose_algebra.h"

namespace vknerf::ref {

using core::correctedPose;
using core::Mat3;
using core::so3Coefficients;
using core::so3Exp;
using core::so3LeftJacobian;
using core::so3Series;

}  // namespace vknerf::ref
