#pragma once
// The fast model's capacity from the training data, where its configuration leaves it open
// (FastModel::hashLog2Size or hashGrowth 0; a value set explicitly is kept):
//   - finest hash-grid resolution: two cells (Nyquist) per pixel footprint at the typical camera
//     distance over the box's largest side, N = 2 * extent / (distance / focal), the medians over the
//     cameras of their distance to the box centre and of distance / focal; rounded up to a power of
//     two (the estimate is rough: never under-resolve), within [64, 4096]. The hash grid spans the
//     whole box, so with cascades (aabb_scale) N grows with the box, as instant-ngp's 2048 x aabb_scale.
//     A CPU device keeps N <= 512: in the minutes it trains, finer levels did not pay (measured).
//   - table entries per level: a parameter per training pixel at most, 2^T <= pixels / (levels x
//     features), since more than the photos constrain only adds optimizer work (the sample scene:
//     2^15 matched 2^17 at a third of the Adam cost); and no more than the finest level's cells in
//     the part of the box some camera sees, N^3 x seen; within 2^15..2^19.
#include <string>

#include "vknerf/config.h"
#include "vknerf/dataset.h"

namespace vknerf::nerf {

// Fills what `model` leaves open from `train`; returns one line saying what was chosen and why.
std::string resolveFastCapacity(FastModel& model, const Dataset& train, bool cpuDevice);

}  // namespace vknerf::nerf
