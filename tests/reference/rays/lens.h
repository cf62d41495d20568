#pragma once
// The lens models are production's (src/core/camera/lens.h: checkLens() and pixelDirection() use
// them); the oracle's rays and view bounds go through the same functions.
#include "core/camera/lens.h"

namespace vknerf::ref {

using core::distort;
using core::fisheyeAngle;
using core::fisheyeTheta;
using core::kLensLargest;
using core::kLensNewtonSteps;
using core::kLensSingular;
using core::lensDirection;
using core::opencvJacobian;
using core::opencvRadial;
using core::opencvRadialDenominator;
using core::Point2;
using core::undistort;
using core::undistortOpenCV;

}  // namespace vknerf::ref
