// Model::recordRender: the render of one view recorded into the embedding application's command
// buffer (see docs/embedding.md for the contract). Nothing here submits or waits.
#include <algorithm>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "api/model_impl.h"
#include "nerf/rays/rays.h"
#include "nerf/render/render_target_writer.h"
#include "vknerf/error.h"

namespace vknerf {
namespace detail {

struct RecordState {
  // The camera of the recording, written by vkCmdUpdateBuffer inside the command buffer (not by a
  // host upload), so that several recordings in one command buffer each render their own camera.
  gpu::Buffer camera;
  nerf::RenderTargetWriter writer;
  explicit RecordState(Context& ctx) : camera(ctx, sizeof(nerf::CameraGpu)), writer(ctx) {}
};

void RecordStateDeleter::operator()(RecordState* s) const { delete s; }

}  // namespace detail

void Model::recordRender(VkCommandBuffer cmd, const Camera& camera, const RenderTarget& target) const {
  Impl& m = *impl_;
  Context& ctx = *m.ctx;
  // Everything is checked before the first command is recorded: a bad call leaves `cmd` untouched.
  if (cmd == VK_NULL_HANDLE) throw Error("recordRender: command buffer is VK_NULL_HANDLE");
  nerf::checkRenderTarget(ctx, camera, target);
  // The caller may submit on a queue of its own, unordered with the trainer's: the step in flight
  // finishes before the render reads the weights.
  m.settled();
  if (!m.record) m.record.reset(new detail::RecordState(ctx));
  detail::RecordState& rs = *m.record;

  const auto bound = rs.writer.bind(target, m.pipe->color(), m.pipe->depth());
  const auto packed = nerf::packCameras(std::span<const Camera>(&camera, 1));
  // The recorder puts a barrier before its first command (earlier work on these buffers, in this
  // command buffer or an earlier submission, completes first) and between consecutive commands.
  gpu::Recorder rec(ctx, cmd);
  rec.update(rs.camera, 0, packed.data(), sizeof(nerf::CameraGpu));
  const uint32_t total = camera.width * camera.height, cap = m.pipe->rayCapacity();
  for (uint32_t first = 0; first < total; first += cap) {
    const uint32_t n = std::min(cap, total - first);
    m.pipe->recordRender(rec, {rs.camera, 0, first, n, m.config.background}, /*mayWait=*/false);
    rs.writer.record(rec, bound, first, n);
  }
}

}  // namespace vknerf
