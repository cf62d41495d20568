#pragma once
// Occupancy grid for empty-space skipping (shaders/occupancy/occupancy_*.comp, shaders/occupancy/occupancy.glsl).
// C nested cascades of R^3 cells: cascade C - 1 covers the scene box, each one inside it half the
// side around the same centre (instant-ngp's cascades; C = 1 is one grid over the box). Layouts:
//   density  float[C R^3]: running maximum of the field density sigma per cell (instant-ngp's EMA)
//   bits     uint[ceil(C R^3 / 32)]: cell i = c R^3 + x + R (y + R z) of cascade c is occupied when
//            bit (i & 31) of word i >> 5 is set; bits past the last cell are meaningless and never read
// An update is three steps around the caller's field evaluation:
//   1. recordAllCellPoints / recordRandomCellPoints: vec4 positions (normalised box [-1, 1]^3,
//      w = 0; cascade c's cells span [-2^(c-C+1), 2^(c-C+1)]^3 of it) and uint cell indices of the
//      points to evaluate;
//   2. the caller writes float density[] (sigma, activated) for those points;
//   3. recordUpdate: d = max(d * decay, max of the new densities in the cell) for every cell, then
//      bits = d > threshold.
// The threshold is a density; densityThreshold(tau, dt) gives the density at which one march step
// dt has optical thickness sigma * dt = tau (instant-ngp: tau = 0.01, alpha ~ 1%).
#include <cstdint>
#include <span>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "vknerf/camera.h"

namespace vknerf::nerf {

// The occupancy bits on the host, in the grid's layout (above): what an exporter reads to sample
// the field only where a render would.
struct OccupancyBits {
  uint32_t resolution = 0, cascades = 0;
  std::vector<uint32_t> words;
  bool occupied(uint32_t cell) const { return (words[cell >> 5] >> (cell & 31u)) & 1u; }
};

class OccupancyGrid {
 public:
  static constexpr uint32_t kMaxCascades = 8;

  // resolution R in [1, 256], cascades C in [1, kMaxCascades], C R^3 at most 2^24; density starts
  // at 0 and every cell empty: call recordMarkAllOccupied before the first march so that nothing is
  // skipped until the field has been measured.
  OccupancyGrid(Context& ctx, uint32_t resolution = 128, uint32_t cascades = 1);

  uint32_t resolution() const { return resolution_; }
  uint32_t cascades() const { return cascades_; }
  uint32_t numCells() const { return numCells_; }
  uint32_t numWords() const { return (numCells_ + 31u) / 32u; }
  const gpu::Buffer& density() const { return density_; }
  const gpu::Buffer& bits() const { return bits_; }
  // The densities to write (a checkpoint's load, a test): the next mean reads every cell again,
  // not the word sums of the last update (recordMeanDensity).
  gpu::Buffer& density() {
    wordSumsCurrent_ = false;
    return density_;
  }
  gpu::Buffer& bits() { return bits_; }

  static float densityThreshold(float opticalThickness, float dt) { return opticalThickness / dt; }
  // The decay an update applies to every cell when it measures `measured` random points of a grid
  // of `cells`: `decayPerQuarter` (instant-ngp's 0.95) where it measures a quarter of the cells or
  // more, and the root of it that keeps a cell's decay between two of its measurements the same
  // where it measures fewer. A 128^3 grid measured 2^16 points at a time would otherwise lose 0.95^32
  // of a cell's density before that cell is looked at again: thin parts fall under the threshold.
  static float decayFor(float decayPerQuarter, uint32_t measured, uint32_t cells);

  // Every cell occupied (the initial state of training); densities are left as they are.
  void recordMarkAllOccupied(gpu::Recorder& rec);

  // Before training (instant-ngp's mark_untrained_density_grid): every cell none of whose corners
  // any of `cameras` sees (in front of it, inside its image through a pinhole bound that holds the
  // lens: core::viewBoundOf) gets density -1, which no update changes, so it starts and stays empty;
  // then bits = occupied wherever a camera sees. `box` is the scene box the grid covers. Records,
  // submits and waits.
  void markUnseenEmpty(std::span<const Camera> cameras, const Aabb& box);

  // numCells() points, point j in cell j: positions vec4[numCells()], cells uint[numCells()].
  void recordAllCellPoints(gpu::Recorder& rec, uint32_t seed, const gpu::BufferRange& positions,
                           const gpu::BufferRange& cells);
  // `count` points in cells drawn uniformly at random (with repetition), cell rngUint(seed, j, 3) % numCells().
  void recordRandomCellPoints(gpu::Recorder& rec, uint32_t seed, uint32_t count, const gpu::BufferRange& positions,
                              const gpu::BufferRange& cells);
  // Densities measured at `count` points of `cells`: point j's density is
  // density[j * densityStride + densityComponent] (stride 4, component 3: sigma of a field vec4).
  struct Measured {
    gpu::BufferRange cells, density;
    uint32_t count = 0;
    uint32_t densityStride = 1, densityComponent = 0;
  };
  // How an update takes them in: decay in [0, 1], threshold >= 0; capAtMeanDensity: the threshold
  // is min(threshold, the grid's mean density before this update), computed on the device
  // (recordMeanDensity), so the update needs no read-back.
  struct Update {
    float decay = 0, threshold = 0;
    bool capAtMeanDensity = false;
  };
  // EMA and bits from `measured`. NaN and negative densities count as 0, +inf as FLT_MAX.
  void recordUpdate(gpu::Recorder& rec, const Measured& measured, const Update& update);
  // The mean over all cells of the density (non-finite values as 0), one float into meanDensity():
  // from the sums of 32 cells the last update's EMA wrote, when no one has taken the densities to
  // write since, else from every cell.
  void recordMeanDensity(gpu::Recorder& rec);
  const gpu::Buffer& meanDensity() const { return mean_; }

  // Number of occupied cells into counter (one uint, overwritten).
  void recordCountOccupied(gpu::Recorder& rec, gpu::Buffer& counter);
  // Occupied cells / all cells, after everything submitted so far (records, submits, waits).
  float occupiedFraction();
  // The same per cascade, innermost first (reads the bits on the host).
  std::vector<double> occupiedFractionPerCascade();
  // The bits after everything submitted so far.
  OccupancyBits hostBits() const;

 private:
  Context& ctx_;
  uint32_t resolution_, cascades_, numCells_;
  gpu::Buffer density_, bits_, fresh_, counter_, mean_, meanPartials_, wordSums_;
  gpu::Kernel points_, splat_, ema_, meanKernel_, count_, unseen_;
  bool wordSumsCurrent_ = false;  // wordSums_ holds the sums of the densities as they are
  void recordEma(gpu::Recorder& rec, float decay, float threshold, bool capAtMean);
};

}  // namespace vknerf::nerf
