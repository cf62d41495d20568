// Model: loading a checkpoint and rendering a view on the host (model_record.cpp records a view
// into a caller's command buffer).
#include "vknerf/model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "api/model_impl.h"
#include "gpu/dispatch/recorder.h"
#include "io/checkpoint/checkpoint.h"
#include "io/checkpoint/checkpoint_record.h"
#include "io/dataset/dataset_loaders.h"
#include "nerf/rays/pose_correction.h"
#include "nerf/rays/rays.h"
#include "vknerf/error.h"

namespace vknerf {

namespace {
// Each kernel's device time summed over the submissions' dispatches of it, in first-recorded order.
KernelTimes kernelTotals(const std::vector<gpu::SubmissionTiming>& submissions) {
  KernelTimes totals;
  for (const gpu::SubmissionTiming& sub : submissions) addKernelTimes(totals, sub.kernels);
  return totals;
}
}  // namespace

RenderedImage Model::Impl::render(const Camera& cam, const std::function<void(uint64_t, uint64_t)>& progress) const {
  if (cam.width == 0 || cam.height == 0) throw Error("render: camera has an empty image size");
  if (!(cam.fx > 0) || !(cam.fy > 0)) throw Error("render: camera focal length must be positive");
  Context& c = *ctx;
  auto packed = nerf::packCameras(std::span<const Camera>(&cam, 1));
  auto camBuf = gpu::Buffer::of(c, packed);
  const uint32_t total = cam.width * cam.height, cap = pipe->rayCapacity();
  RenderedImage img;
  img.width = cam.width;
  img.height = cam.height;
  img.rgb.resize(size_t(total) * 3);
  img.depth.resize(total);
  img.opacity.resize(total);
  img.background.resize(size_t(total) * 3);
  gpu::Recorder rec(c, profile);
  if (profile) rec.startLog();
  const uint64_t samplesBefore = pipe->renderedSamples();
  for (uint32_t first = 0; first < total; first += cap) {
    const uint32_t n = std::min(cap, total - first);
    rec.begin();
    pipe->recordRender(rec, {camBuf, 0, first, n, config.background}, true);
    rec.end();
    rec.submitAndWait();
    auto color = pipe->color().download<float>(size_t(n) * 4);
    auto depth = pipe->depth().download<float>(n);
    auto background = pipe->backgrounds().download<float>(size_t(n) * 4);
    for (uint32_t i = 0; i < n; ++i) {
      const size_t p = first + i;
      for (int k = 0; k < 3; ++k) img.rgb[p * 3 + k] = color[i * 4 + k], img.background[p * 3 + k] = background[i * 4 + k];
      const float o = color[i * 4 + 3];
      img.opacity[p] = o;
      img.depth[p] = o > 1e-4f ? depth[i] / o : 0.0f;
    }
    if (progress) progress(first + n, total);
  }
  img.samples = pipe->renderedSamples() - samplesBefore;
  if (profile) img.kernelMs = kernelTotals(rec.submissions());
  return img;
}

Model::Model(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Model::~Model() = default;
Model::Model(Model&&) noexcept = default;
Model& Model::operator=(Model&&) noexcept = default;
const TrainConfig& Model::config() const { return impl_->config; }
const Aabb& Model::bounds() const { return impl_->box; }
std::vector<TrainedCamera> Model::trainingCameras() const {
  impl_->settled();
  return impl_->trainingCameras();
}

namespace {

// The record reads back whatever floats were written (CheckpointRecord); a camera that training
// wrote also is what the loader accepts of a scene's: a rigid pose, values within the range the
// device computes with, a lens it can invert. A crafted one would be exported as a scene that
// `train` then refuses, or rendered at: one line naming the camera and the field instead.
std::vector<TrainedCamera> checkedTrainingCameras(const io::CheckpointRecord& record, const std::string& path) {
  std::vector<TrainedCamera> cameras = record.trainingCameras();
  for (size_t i = 0; i < cameras.size(); ++i) {
    const Camera& c = cameras[i].camera;
    const std::string where = path + ": checkpoint training_cameras[" + std::to_string(i) + "]";
    const auto inRange = [&](double v, const char* field) {
      if (std::fabs(v) <= io::detail::kDeviceLimit) return;
      char text[32];
      std::snprintf(text, sizeof text, "%g", v);
      throw Error(where + ": " + field + " value " + text + " is beyond the range the device computes with (|x| <= 1e15)");
    };
    inRange(c.fx, "fx"), inRange(c.fy, "fy"), inRange(c.cx, "cx"), inRange(c.cy, "cy");
    std::array<double, 16> pose;
    for (int k = 0; k < 16; ++k) inRange(pose[k] = c.c2w[k], "c2w");
    io::detail::checkRigid(pose, where, "c2w");
    checkLens(c, where);
  }
  return cameras;
}

}  // namespace

std::vector<TrainedCamera> Model::trainingCamerasOf(const std::string& checkpoint) {
  return checkedTrainingCameras(io::CheckpointRecord(io::Checkpoint::load(checkpoint)), checkpoint);
}

RenderedImage Model::render(const Camera& camera, const std::function<void(uint64_t, uint64_t)>& progress) const {
  impl_->settled();
  return impl_->render(camera, progress);
}

namespace {

// The corrections' section: CameraRefinement's parameters (src/models/common/camera_refinement.h).
constexpr const char* kCameraCorrections = "cameras.params";

// Camera refinement's corrections (w, tau) per camera, as training leaves them: it starts each at 0
// and an L2 penalty holds it near there, and a camera moved out of sight of the box gets no
// gradient to move further. A rotation beyond a half turn, or a shift of ten times the box, is
// therefore no trained value: a finite 1e30 would give NaN poses on the next step or save.
void checkCameraCorrections(const io::Checkpoint& ck, const std::string& section, const std::vector<float>& values,
                            const Aabb& box) {
  double side = 0;
  for (int k = 0; k < 3; ++k) side = std::max(side, double(box.max[k]) - double(box.min[k]));
  const double maxShift = 10 * side;
  constexpr double kPi = 3.14159265358979323846;
  char text[160];
  for (size_t c = 0; c + nerf::kCorrectionFloats <= values.size(); c += nerf::kCorrectionFloats) {
    const float* v = values.data() + c;
    const double angle = std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]);
    const double shift = std::sqrt(double(v[3]) * v[3] + double(v[4]) * v[4] + double(v[5]) * v[5]);
    if (angle > kPi)
      std::snprintf(text, sizeof text, "camera %zu's rotation correction (w) turns %g radians, more than a half turn",
                    c / nerf::kCorrectionFloats, angle);
    else if (shift > maxShift)
      std::snprintf(text, sizeof text, "camera %zu's translation correction (tau) is %g long, beyond 10 times the "
                    "scene box's side (%g)", c / nerf::kCorrectionFloats, shift, side);
    else
      continue;
    throw Error(ck.path + ": checkpoint section '" + section + "': " + text + "; training produces no such value");
  }
}

}  // namespace

// A NaN or infinite parameter would render as garbage (or crash the depth writer) without a word.
void uploadState(const io::Checkpoint& ck, models::FieldPipeline& pipe, const Aabb& box) {
  for (const models::StateArray& a : pipe.state()) {
    auto values = ck.get<float>(a.name, a.count);
    for (size_t i = 0; a.numbers && i < values.size(); ++i)
      if (!std::isfinite(values[i]))
        throw Error(ck.path + ": checkpoint section '" + a.name + "' holds a non-finite value at index " + std::to_string(i));
    if (a.name == kCameraCorrections) checkCameraCorrections(ck, a.name, values, box);
    a.buffer->upload(values);
  }
}

Model Model::load(std::shared_ptr<Context> ctx, const std::string& path, const RenderSettings& settings) {
  auto ck = io::Checkpoint::load(path);
  const io::CheckpointRecord record(ck);
  auto impl = std::make_unique<Impl>();
  impl->ctx = ctx;
  impl->config = record.config();
  impl->box = record.bounds();
  impl->trainingCameras = [record, path] { return checkedTrainingCameras(record, path); };
  impl->profile = settings.profile;
  // State kept per training photo (the fast model's appearance vectors) is sized by their count.
  const models::TrainingPhotos photos{record.trainingPhotoCount().value_or(0)};
  const uint32_t rays = settings.raysPerBatch ? settings.raysPerBatch : models::renderRaysOf(impl->config);
  impl->own = models::makeFieldPipeline(*ctx, impl->config, impl->box, rays, false, settings, photos);
  impl->pipe = impl->own.get();
  uploadState(ck, *impl->pipe, impl->box);
  return Model(std::move(impl));
}

}  // namespace vknerf
