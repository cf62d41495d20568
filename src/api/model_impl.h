#pragma once
// Model's insides, shared by the files that implement it (model.cpp: loading, host rendering;
// model_record.cpp: rendering into a caller's command buffer; trainer.cpp: the model it trains).
#include <functional>
#include <memory>
#include <vector>

#include "models/field_pipeline.h"
#include "vknerf/model.h"

namespace vknerf {

namespace io {
struct Checkpoint;
}  // namespace io

namespace detail {
// What Model::recordRender keeps between recordings (model_record.cpp): the camera buffer and the
// render-target writer, created on the first recording. Deleted through a function defined there,
// so the files that destroy a Model need not see its definition.
struct RecordState;
struct RecordStateDeleter {
  void operator()(RecordState* s) const;
};
}  // namespace detail

// Uploads the arrays of `ck` into the pipeline's state (model.cpp). A checksum proves the bytes are
// as written, not that they are a model: throws vknerf::Error for a non-finite parameter, and for a
// camera correction beyond what training produces in the scene box `box` (cameras.params).
void uploadState(const io::Checkpoint& ck, models::FieldPipeline& pipe, const Aabb& box);

struct Model::Impl {
  std::shared_ptr<Context> ctx;
  TrainConfig config;
  Aabb box;
  std::unique_ptr<models::FieldPipeline> own;  // a loaded model's inference pipeline
  models::FieldPipeline* pipe = nullptr;       // own, or the trainer's
  // Model::trainingCameras: the checkpoint's record, read when asked (a checkpoint written before
  // the cameras were recorded loads, and fails only there), or the trainer's cameras.
  std::function<std::vector<TrainedCamera>()> trainingCameras;
  bool profile = false;  // RenderSettings::profile: render() times its kernels
  // A trainer's model: waits for the training step in flight before the host reads the state
  // (Trainer::submitStep). Empty for a loaded model.
  std::function<void()> settle;
  void settled() const {
    if (settle) settle();
  }
  // Last member: destroyed first, while the pipeline and the context still exist.
  mutable std::unique_ptr<detail::RecordState, detail::RecordStateDeleter> record;

  RenderedImage render(const Camera& camera, const std::function<void(uint64_t, uint64_t)>& progress) const;
};

}  // namespace vknerf
