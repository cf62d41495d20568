#pragma once
// A trained field, loaded from a checkpoint (or a Trainer's, as it trains): rendering views on the
// host or into a caller's command buffer, querying the field, extracting a mesh.
//
//   auto ctx = vknerf::Context::create();
//   auto view = vknerf::Model::load(ctx, "tabletop.vknerf").render(camera);
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "vknerf/camera.h"
#include "vknerf/config.h"
#include "vknerf/context.h"
#include "vknerf/mesh.h"
#include "vknerf/render_settings.h"
#include "vknerf/render_target.h"
#include "vknerf/rendered_image.h"

namespace vknerf {

class Trainer;

// The field at a batch of points (Model::queryField).
struct FieldSamples {
  std::vector<float> density;  // sigma per point, after the model's density activation
  std::vector<float> rgb;      // 3 per point: the colour seen along the point's direction
};

// A trained field: the model configuration, its parameters and the scene box.
class Model {
 public:
  static Model load(std::shared_ptr<Context> ctx, const std::string& checkpoint, const RenderSettings& settings = {});
  ~Model();
  Model(Model&&) noexcept;
  Model& operator=(Model&&) noexcept;

  const TrainConfig& config() const;
  const Aabb& bounds() const;
  // The cameras of the training images in training order, each with its image's name (the path
  // Dataset::names held; may be empty), as the checkpoint recorded them; a Trainer's model gives
  // what Trainer::save would record now. Throws vknerf::Error naming the checkpoint and
  // "training_cameras" when it was written before checkpoints recorded them (it still loads and
  // renders), or the camera's field when one is malformed.
  std::vector<TrainedCamera> trainingCameras() const;
  // The same, read from the checkpoint file alone: no device, no model built.
  static std::vector<TrainedCamera> trainingCamerasOf(const std::string& checkpoint);
  // Renders on the device, waits, and reads the image back.
  // `progress`, when given, is called after each tile of rays with (pixels done, pixels in all).
  RenderedImage render(const Camera& camera,
                       const std::function<void(uint64_t done, uint64_t total)>& progress = {}) const;
  // Records the render of `camera` into the caller's command buffer `cmd` (primary, recording, from
  // a pool of the context's queue family), writing `target`; nothing is submitted. Contract (see
  // docs/embedding.md): before the commands, the caller makes earlier writes to the target visible
  // to VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT / VK_ACCESS_SHADER_WRITE_BIT (and transitions an image
  // to GENERAL); after them, it barriers from COMPUTE_SHADER / SHADER_WRITE to its own use. The
  // model's scratch buffers are reused by every recording: one render of a model may be in flight
  // at a time, and the model must outlive the commands' execution.
  void recordRender(VkCommandBuffer cmd, const Camera& camera, const RenderTarget& target) const;

  // The field at `points` (xyz each, world coordinates) seen along `directions` (xyz each, one per
  // point, normalised here), evaluated on the device in batches. Not while a render is in flight.
  FieldSamples queryField(const std::vector<float>& points, const std::vector<float>& directions) const;
  // The surface where the density crosses settings.threshold: the density sampled on a grid over
  // the box on the device, marching cubes there, each vertex coloured by the field seen from
  // outside (along the negative vertex normal). Throws vknerf::Error for an empty box or a
  // resolution below 2 or beyond what the device's buffers hold. `progress`, when given, is called
  // after each batch of density samples, the long part, with (samples queried, samples to query).
  Mesh extractMesh(const MeshSettings& settings = {},
                   const std::function<void(uint64_t done, uint64_t total)>& progress = {}) const;

 private:
  friend class Trainer;
  struct Impl;
  explicit Model(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace vknerf
