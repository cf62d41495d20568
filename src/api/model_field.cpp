// Model::queryField and Model::extractMesh: the trained field read at points the caller chooses,
// through the pipeline's query batch (FieldPipeline::queryBatch).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>

#include "api/model_impl.h"
#include "api/unit_byte.h"
#include "gpu/dispatch/recorder.h"
#include "models/common/field_batch.h"
#include "nerf/mesh/density_grid.h"
#include "nerf/mesh/marching_cubes.h"
#include "nerf/mesh/sample_blocks.h"
#include "vknerf/error.h"

namespace vknerf {
namespace {

// Points per query batch: the pipeline's capacity, within one dispatch of the grid kernels.
uint32_t batchFor(const models::FieldBatch& f) { return std::min(f.capacity, 65535u * 256u); }

// The grid of `resolution` samples along the box's longest side, cubic cells.
core::GridLayout gridOver(const Aabb& box, uint32_t resolution) {
  float longest = 0;
  for (int k = 0; k < 3; ++k) {
    if (!(box.max[k] > box.min[k]) || !std::isfinite(box.max[k] - box.min[k]))
      throw Error("mesh: the box is empty or not finite along axis " + std::to_string(k));
    longest = std::max(longest, box.max[k] - box.min[k]);
  }
  if (resolution < 2) throw Error("mesh: the resolution must be at least 2 samples");
  const float h = longest / float(resolution - 1);
  core::GridLayout g;
  for (int k = 0; k < 3; ++k) {
    const float side = box.max[k] - box.min[k];
    g.n[k] = std::max(2u, uint32_t(std::lround(side / h)) + 1);
    g.origin[k] = box.min[k];
    g.spacing[k] = side / float(g.n[k] - 1);
  }
  return g;
}

// Per vertex, the area-weighted sum of its triangles' normals, normalised (+z where they cancel).
std::vector<float> vertexNormals(const core::TriangleMesh& m) {
  std::vector<float> n(m.positions.size(), 0.0f);
  for (size_t t = 0; t < m.triangles.size(); t += 3) {
    const float* a = &m.positions[3 * m.triangles[t]];
    const float* b = &m.positions[3 * m.triangles[t + 1]];
    const float* c = &m.positions[3 * m.triangles[t + 2]];
    const float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const float f[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) n[3 * m.triangles[t + j] + k] += f[k];
  }
  for (size_t i = 0; i < n.size(); i += 3) {
    const float len = std::sqrt(n[i] * n[i] + n[i + 1] * n[i + 1] + n[i + 2] * n[i + 2]);
    if (len > 0) n[i] /= len, n[i + 1] /= len, n[i + 2] /= len;
    else n[i] = 0, n[i + 1] = 0, n[i + 2] = 1;
  }
  return n;
}

}  // namespace

FieldSamples Model::queryField(const std::vector<float>& points, const std::vector<float>& directions) const {
  Impl& m = *impl_;
  m.settled();
  if (points.size() % 3 || directions.size() != points.size())
    throw Error("queryField: give xyz per point and one xyz direction per point");
  models::FieldBatch& f = m.pipe->queryBatch();
  const size_t count = points.size() / 3, batch = batchFor(f);
  FieldSamples out;
  out.density.resize(count);
  out.rgb.resize(count * 3);
  gpu::Recorder rec(*m.ctx);
  std::vector<float> pos(batch * 4, 0.0f), dir(batch * 4, 0.0f);
  for (size_t first = 0; first < count; first += batch) {
    const size_t n = std::min(batch, count - first);
    for (size_t i = 0; i < n; ++i) {
      const float* p = &points[3 * (first + i)];
      const float* d = &directions[3 * (first + i)];
      const float len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      for (int k = 0; k < 3; ++k) {
        // As sample_points.comp maps a ray's samples: 2 (x - min) / (max - min) - 1.
        pos[4 * i + k] = 2.0f * (p[k] - m.box.min[k]) / (m.box.max[k] - m.box.min[k]) - 1.0f;
        dir[4 * i + k] = len > 0 ? d[k] / len : (k == 2 ? 1.0f : 0.0f);
      }
    }
    f.positions.upload(pos.data(), n * 16);
    f.directions.upload(dir.data(), n * 16);
    rec.begin();
    m.pipe->recordQuery(rec, uint32_t(n));
    rec.end();
    rec.submitAndWait();
    const auto field = f.field.download<float>(n * 4);
    for (size_t i = 0; i < n; ++i) {
      for (int k = 0; k < 3; ++k) out.rgb[3 * (first + i) + k] = field[4 * i + k];
      out.density[first + i] = field[4 * i + 3];
    }
  }
  return out;
}

Mesh Model::extractMesh(const MeshSettings& s, const std::function<void(uint64_t, uint64_t)>& progress) const {
  Impl& m = *impl_;
  m.settled();
  Context& ctx = *m.ctx;
  const core::GridLayout g = gridOver(s.box.value_or(m.box), s.resolution);
  if (g.points() > nerf::MarchingCubes::maxPoints(ctx))
    throw Error("mesh: " + std::to_string(g.n[0]) + " x " + std::to_string(g.n[1]) + " x " + std::to_string(g.n[2]) +
                " samples exceed what the device's buffers hold; lower the resolution");
  const uint32_t points = uint32_t(g.points());

  // The blocks of the grid to sample: near the occupied cells where the model has an occupancy
  // grid (elsewhere a render never looks, and the grid keeps 0, below any positive threshold).
  std::optional<nerf::OccupancyBits> occupancy;
  if (s.occupiedOnly && s.threshold > 0) occupancy = m.pipe->sampledCells();
  const nerf::SampleBlocks blocks =
      occupancy ? nerf::occupiedSampleBlocks(g, m.box, *occupancy) : nerf::allSampleBlocks(g);
  gpu::Buffer blockIds(ctx, std::max<VkDeviceSize>(4, blocks.ids.size() * 4), "the sampled blocks of the density grid");
  blockIds.upload(blocks.ids);
  nerf::DensityGridSampler sampler(ctx, g, blocks, blockIds);
  if (sampler.slots() > UINT32_MAX) throw Error("mesh: the grid has too many samples; lower the resolution");

  // The density grid, batch by batch through the pipeline's query batch. The direction is any unit
  // vector: the density does not depend on it.
  gpu::Buffer grid(ctx, VkDeviceSize(points) * 4, "the density grid");
  models::FieldBatch& f = m.pipe->queryBatch();
  const uint32_t batch = batchFor(f), slots = uint32_t(sampler.slots());
  std::vector<float> up(size_t(batch) * 4, 0.0f);
  for (size_t i = 0; i < batch; ++i) up[4 * i + 2] = 1.0f;
  f.directions.upload(up);
  gpu::Recorder rec(ctx);
  if (occupancy) grid.zero();  // the float 0.0 where no block is sampled
  for (uint32_t first = 0; first < slots; first += batch) {
    const uint32_t n = std::min(batch, slots - first);
    rec.begin();
    sampler.recordPositions(rec, m.box, first, n, f.positions);
    m.pipe->recordQuery(rec, n);
    sampler.recordDensities(rec, f.field, first, n, grid);
    rec.end();
    rec.submitAndWait();
    if (progress) progress(first + n, slots);
  }

  nerf::MarchingCubes mc(ctx);
  core::TriangleMesh surface = mc.extract(grid, g, s.threshold);
  Mesh mesh;
  mesh.densityQueries = slots;
  mesh.gridSamples = points;
  mesh.positions = std::move(surface.positions);
  mesh.triangles = std::move(surface.triangles);
  // Colour: the field seen from outside, looking along the negative normal.
  std::vector<float> view = vertexNormals({mesh.positions, mesh.triangles});
  for (float& v : view) v = -v;
  const FieldSamples seen = queryField(mesh.positions, view);
  mesh.colors.resize(seen.rgb.size());
  std::transform(seen.rgb.begin(), seen.rgb.end(), mesh.colors.begin(), detail::unitToByte);
  return mesh;
}

}  // namespace vknerf
