#pragma once
// Model's insides, shared by the files that implement it (trainer.cpp: loading, host rendering;
// model_record.cpp: rendering into a caller's command buffer).
#include <memory>

#include "models/field_pipeline.h"
#include "vknerf/trainer.h"

namespace vknerf {

namespace nerf {
// What Model::recordRender keeps between recordings (model_record.cpp): the camera buffer and the
// render-target writer, created on the first recording. Deleted through a function defined there,
// so the files that destroy a Model need not see its definition.
struct RecordState;
struct RecordStateDeleter {
  void operator()(RecordState* s) const;
};
}  // namespace nerf

struct Model::Impl {
  std::shared_ptr<Context> ctx;
  TrainConfig config;
  Aabb box;
  std::unique_ptr<nerf::FieldPipeline> own;  // a loaded model's inference pipeline
  nerf::FieldPipeline* pipe = nullptr;       // own, or the trainer's
  // Last member: destroyed first, while the pipeline and the context still exist.
  mutable std::unique_ptr<nerf::RecordState, nerf::RecordStateDeleter> record;

  RenderedImage render(const Camera& camera, const std::function<void(uint64_t, uint64_t)>& progress) const;
};

}  // namespace vknerf
