#pragma once
// The fast model's capacity from the training data, where its configuration leaves it open
// (FastModel::hashLog2Size, hashGrowth, marchSteps, maxSamplesPerRay, samplesPerBatch, gridResolution
// or nearDistance 0; a value set explicitly is kept):
//   - finest hash-grid resolution: two cells (Nyquist) per pixel footprint at the typical camera
//     distance over the inner cascade's side, N = 2 * inner / (distance / focal), the medians over
//     the cameras of their distance to the box centre and of distance / focal; rounded up to a power
//     of two (the estimate is rough: never under-resolve), within [64, 4096]; a CPU device keeps
//     N <= 512 (in the minutes it trains, finer levels did not pay: measured). The hash grid spans the
//     whole box at that cell size, N x 2^(cascades - 1) over the box (instant-ngp's 2048 x
//     aabb_scale), with one level more per cascade beyond the first, so that the inner cube keeps its
//     detail whatever aabb_scale (one spread of 512 cells over a box 32 times the fruit's left it 16).
//     With contraction (FastModel::contraction) it spans the contracted box, twice the inner cube:
//     2N, one level more.
//   - the march step (FastModel::marchSteps): about 4 pixel footprints, the inner cascade's diagonal
//     over 4 x distance / focal, the power of two nearest it, within [128, 1024], [128, 512] on a
//     CPU; at most as many samples per ray (maxSamplesPerRay), where that is open too.
//   - a training step's samples (FastModel::samplesPerBatch): 2^14, whatever the march steps (at
//     short budgets more, cheaper steps beat larger ones at 128 and 256 march steps alike); 2^13
//     with the proposal estimator (its rays take its few samples each, so a step holds more rays).
//   - the occupancy grid (FastModel::gridResolution): half the march steps cells per axis, so that
//     a cell spans about one step, within [64, 256], [64, 128] on a CPU.
//   - where rays start (FastModel::nearDistance): 5% of the inner cascade's side, so that it means
//     the same in any units.
//   - table entries per level: a parameter per training pixel at most, 2^T <= pixels / (levels x
//     features), since more than the photos constrain only adds optimizer work (the sample scene:
//     2^15 matched 2^17 at a third of the Adam cost); and no more than the finest level's cells in
//     the part of the box some camera sees, N^3 x seen; within 2^15..2^19, 2^17 on a CPU.
#include <string>

#include "vknerf/config.h"
#include "vknerf/dataset.h"

namespace vknerf::models {

// Fills what `model` leaves open from `train`; returns one line saying what was chosen and why.
std::string resolveFastCapacity(FastModel& model, const Dataset& train, bool cpuDevice);

}  // namespace vknerf::models
