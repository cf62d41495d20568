// instant-ngp's camera path (io/camera_path/ngp_camera_path.h). Every convention here follows instant-ngp's own
// sources: CameraKeyframe and CameraPath::eval_camera_path (camera_path.h / camera_path.cu), the
// dataset's scale and offset and ngp_matrix_to_nerf (nerf_loader.cu / nerf_loader.h), the vertical
// fov (Testbed::set_fov with the default fov axis 1) and run.py's frame times.
#include "io/camera_path/ngp_camera_path.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include "io/dataset/dataset_loaders.h"
#include "vknerf/error.h"

namespace vknerf::io::detail {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

constexpr double kMaxSize = 16384;
constexpr double kMaxFrames = 1e6;

// v as exactly N finite numbers; `field` names it in the error.
template <size_t N>
std::array<double, N> numbersOf(const JsonFile& f, const json& v, const std::string& field) {
  const std::string what = "must be an array of " + std::to_string(N) + " finite numbers";
  if (!v.is_array() || v.size() != N) fieldError(f, field, what);
  std::array<double, N> out{};
  for (size_t i = 0; i < N; ++i) {
    if (!v[i].is_number() || !std::isfinite(v[i].get<double>())) fieldError(f, field, what);  // NaN is written as null
    out[i] = v[i].get<double>();
  }
  return out;
}

template <size_t N>
std::array<double, N> numbers(const JsonFile& f, const json& obj, const char* key, const std::string& prefix) {
  auto it = obj.find(key);
  if (it == obj.end()) fieldError(f, prefix + key, "is missing");
  return numbersOf<N>(f, *it, prefix + key);
}

double dot4(const std::array<double, 4>& a, const std::array<double, 4>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
}

}  // namespace

std::vector<NgpKeyframe> readNgpKeyframes(const JsonFile& f) {
  if (auto loop = f.root.find("loop"); loop != f.root.end() && loop->is_boolean() && loop->get<bool>())
    fieldError(f, "loop", "is true: looping paths (instant-ngp's newer timed format) are not read");
  const json& list = f.root.at("path");
  if (!list.is_array()) fieldError(f, "path", "must be an array of keyframes");
  if (list.empty()) fieldError(f, "path", "is empty: an instant-ngp camera path needs at least one keyframe");
  std::vector<NgpKeyframe> keys;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string prefix = "path[" + std::to_string(i) + "].";
    const json& entry = list[i];
    if (!entry.is_object()) fieldError(f, "path[" + std::to_string(i) + "]", "must be an object");
    if (entry.contains("timestamp"))
      fieldError(f, prefix + "timestamp", "is present: instant-ngp's newer timed format is not read");
    NgpKeyframe k;
    k.R = numbers<4>(f, entry, "R", prefix);
    const double norm = std::sqrt(dot4(k.R, k.R));
    if (std::abs(norm - 1) > 1e-3)
      fieldError(f, prefix + "R", "must be a unit quaternion (x, y, z, w), its length is " + std::to_string(norm));
    k.T = numbers<3>(f, entry, "T", prefix);
    auto fov = optNumber(f, entry, "fov", prefix);
    if (!fov) fieldError(f, prefix + "fov", "is missing");
    if (!(*fov > 0 && *fov < 180)) fieldError(f, prefix + "fov", "must be in (0, 180) degrees, got " + std::to_string(*fov));
    k.fov = *fov;
    keys.push_back(k);
  }
  return keys;
}

NgpKeyframe evalNgpPath(std::span<const NgpKeyframe> keys, double t) {
  const int n = int(keys.size());
  auto key = [&](int i) -> const NgpKeyframe& { return keys[size_t(std::clamp(i, 0, n - 1))]; };
  t *= double(n - 1);
  const int i1 = int(std::floor(t));
  const double u = t - std::floor(t), uu = u * u, uuu = uu * u;
  const double w[4] = {(1 - u) * (1 - u) * (1 - u) / 6, (3 * uuu - 6 * uu + 4) / 6, (-3 * uuu + 3 * uu + 3 * u + 1) / 6,
                       uuu / 6};
  // As instant-ngp's CameraKeyframe sum p0 * a + p1 * b + p2 * c + p3 * d: each quaternion joins the
  // running sum with its sign flipped when it points away from it.
  NgpKeyframe out;
  out.R = {0, 0, 0, 0};
  out.T = {0, 0, 0};
  out.fov = 0;
  for (int j = 0; j < 4; ++j) {
    const NgpKeyframe& k = key(i1 - 1 + j);
    std::array<double, 4> q;
    for (int c = 0; c < 4; ++c) q[size_t(c)] = k.R[size_t(c)] * w[j];
    const double sign = dot4(q, out.R) < 0 ? -1 : 1;
    for (size_t c = 0; c < 4; ++c) out.R[c] += sign * q[c];
    for (size_t c = 0; c < 3; ++c) out.T[c] += w[j] * k.T[c];
    out.fov += w[j] * k.fov;
  }
  const double norm = std::sqrt(dot4(out.R, out.R));
  for (double& c : out.R) c /= norm;
  return out;
}

std::array<double, 16> ngpPoseToDataset(const NgpKeyframe& k, const NgpFrame& frame) {
  const double x = k.R[0], y = k.R[1], z = k.R[2], w = k.R[3];
  // The keyframe's 3x4 matrix: the rotation of the (unit) quaternion, then T.
  const double m[3][4] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w), k.T[0]},
                          {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w), k.T[1]},
                          {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y), k.T[2]}};
  // ngp_matrix_to_nerf: rows cycled (dataset x, y, z = ngp z, x, y), the y and z columns negated
  // (instant-ngp's camera looks down +z with y down, the dataset's down -z with y up), and the
  // position taken back through the offset and scale.
  const int fromRow[3] = {2, 0, 1};
  const double colSign[3] = {1, -1, -1};
  std::array<double, 16> out{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out[size_t(4 * r + c)] = colSign[c] * m[fromRow[r]][c];
    out[size_t(4 * r + 3)] = (m[fromRow[r]][3] - frame.offset[size_t(r)]) / frame.scale;
  }
  out[15] = 1;
  return out;
}

NgpFrame ngpFrameOfScene(const std::string& scene) {
  NgpFrame frame;
  if (scene.empty()) return frame;
  std::error_code ec;
  fs::path file = scene;
  if (fs::is_directory(file, ec)) {
    if (fs::is_regular_file(file / "transforms.json", ec))
      file /= "transforms.json";
    else if (fs::is_regular_file(file / "transforms_train.json", ec))
      file /= "transforms_train.json";
    else {
      frame.source = "instant-ngp's defaults (no transforms.json in " + scene + ")";
      return frame;
    }
  }
  const JsonFile f = readJson(file, "transforms file");
  const json& r = f.root;
  if (auto s = optNumber(f, r, "scale", "")) {
    if (!(*s > 0)) fieldError(f, "scale", "must be positive");
    frame.scale = *s;
  }
  if (auto o = r.find("offset"); o != r.end()) {
    if (o->is_number())  // instant-ngp also takes one number for all three axes
      frame.offset.fill(*optNumber(f, r, "offset", ""));
    else
      frame.offset = numbers<3>(f, r, "offset", "");
  }
  if (r.contains("aabb")) {  // overrides both: the box's longest side becomes 1, its centre 0.5
    const json& a = r.at("aabb");
    if (!a.is_array() || a.size() != 2) fieldError(f, "aabb", "must be [[min x, y, z], [max x, y, z]]");
    const auto lo = numbersOf<3>(f, a[0], "aabb[0]"), hi = numbersOf<3>(f, a[1], "aabb[1]");
    double side = 1e-6;
    for (size_t k = 0; k < 3; ++k) side = std::max(side, std::abs(hi[k] - lo[k]));
    frame.scale = 1 / side;
    for (size_t k = 0; k < 3; ++k) frame.offset[k] = 0.5 - 0.5 * (lo[k] + hi[k]) * frame.scale;
  }
  frame.source = file.string();
  return frame;
}

CameraPath readNgpCameraPath(const JsonFile& f, const CameraPathOptions& o) {
  const std::vector<NgpKeyframe> keys = readNgpKeyframes(f);
  if (!(o.width >= 1 && o.width <= kMaxSize && o.height >= 1 && o.height <= kMaxSize))
    throw Error(f.name() + ": the frame size must be 1..16384 pixels a side");
  if (!(o.fps > 0 && o.fps <= 1000)) throw Error(f.name() + ": the frame rate must be in (0, 1000]");
  const double frames = std::round(o.fps * o.seconds);
  if (!(frames >= 1 && frames <= kMaxFrames))
    throw Error(f.name() + ": " + std::to_string(o.fps) + " frames/s for " + std::to_string(o.seconds) +
                " s gives no whole frame (or more than a million)");
  const NgpFrame frame = ngpFrameOfScene(o.scene);
  CameraPath out;
  out.format = CameraPath::Format::instantNgp;
  out.fps = o.fps;
  const size_t n = size_t(frames);
  for (size_t i = 0; i < n; ++i) {
    const NgpKeyframe k = evalNgpPath(keys, double(i) / double(n));  // run.py: frame i starts at i / n
    FrameSpec spec;
    spec.where = f.name() + ": the path at frame " + std::to_string(i);
    spec.c2w = ngpPoseToDataset(k, frame);
    checkRigid(spec.c2w, spec.where, "the pose");
    spec.intrinsics.angleY = k.fov * std::numbers::pi / 180;
    spec.intrinsics.focalFieldX = spec.intrinsics.focalFieldY = "fov";
    spec.poseField = "the pose (R, T)";
    spec.intrinsics.width = o.width;
    spec.intrinsics.height = o.height;
    out.cameras.push_back(completeCamera(spec, o.width, o.height));
  }
  char note[256];
  std::snprintf(note, sizeof note, "scale %g, offset (%g, %g, %g) from %s", frame.scale, frame.offset[0],
                frame.offset[1], frame.offset[2], frame.source.c_str());
  out.frameNote = note;
  return out;
}

}  // namespace vknerf::io::detail
