// instant-ngp's camera path (base_cam.json) read by loadCameraPath and `vknerf render --path`: the
// frames are run.py's samples of the clamped uniform cubic B-spline over the keyframes, brought from
// instant-ngp's internal frame back to the dataset's with the scene's scale and offset. The expected
// values are computed here independently: the B-spline weights written out by hand at the sample
// points, rotations applied as q v q*, the frame change written as a permutation and a flip.
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>

#include "io/camera_path/ngp_camera_path.h"
#include "support/cli_run.h"
#include "support/dataset_files.h"
#include "support/error_message.h"
#include "vknerf/camera_path.h"

using namespace vknerf;
using namespace vknerf::test;
using io::detail::NgpFrame;
using io::detail::NgpKeyframe;

namespace {

using Vec3 = std::array<double, 3>;
using Quat = std::array<double, 4>;  // x y z w

Quat aboutAxis(Vec3 axis, double degrees) {
  const double h = 0.5 * degrees * std::numbers::pi / 180, s = std::sin(h);
  return {axis[0] * s, axis[1] * s, axis[2] * s, std::cos(h)};
}

// v rotated by the unit quaternion q: q v q*, written with the vector part u: v + 2w(u x v) + 2u x (u x v).
Vec3 rotate(const Quat& q, const Vec3& v) {
  auto cross = [](const Vec3& a, const Vec3& b) {
    return Vec3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  const Vec3 u{q[0], q[1], q[2]};
  const Vec3 t = cross(u, v), tt = cross(u, t);
  return {v[0] + 2 * q[3] * t[0] + 2 * tt[0], v[1] + 2 * q[3] * t[1] + 2 * tt[1], v[2] + 2 * q[3] * t[2] + 2 * tt[2]};
}

// instant-ngp's internal coordinates (x, y, z) are the dataset's (y, z, x) after p * scale + offset;
// its camera looks down +z with +y down, vknerf's (OpenGL) down -z with +y up.
Vec3 toDataset(const Vec3& ngp) { return {ngp[2], ngp[0], ngp[1]}; }

std::array<double, 16> expectedPose(const Quat& q, const Vec3& t, const NgpFrame& frame) {
  const Vec3 right = toDataset(rotate(q, {1, 0, 0})), down = toDataset(rotate(q, {0, 1, 0})),
             forward = toDataset(rotate(q, {0, 0, 1})), p = toDataset(t);
  std::array<double, 16> m{};
  for (int r = 0; r < 3; ++r) {
    m[size_t(4 * r + 0)] = right[size_t(r)];
    m[size_t(4 * r + 1)] = -down[size_t(r)];
    m[size_t(4 * r + 2)] = -forward[size_t(r)];
    m[size_t(4 * r + 3)] = (p[size_t(r)] - frame.offset[size_t(r)]) / frame.scale;
  }
  m[15] = 1;
  return m;
}

struct Key {
  Quat R;
  Vec3 T;
  double fov;
};

// Three keyframes turning about instant-ngp's z and moving.
const Key kKeys[3] = {{aboutAxis({0, 0, 1}, 0), {0.5, 0.5, 0.2}, 40},
                      {aboutAxis({0, 0, 1}, 30), {0.7, 0.4, 0.3}, 50},
                      {aboutAxis({0, 1, 0}, 50), {0.9, 0.6, 0.25}, 70}};

// sum of w[k] * key[k], quaternion normalised (all in one hemisphere here, so no sign to align).
Key blend(const std::array<double, 3>& w) {
  Key out{{0, 0, 0, 0}, {0, 0, 0}, 0};
  for (size_t k = 0; k < 3; ++k) {
    for (size_t c = 0; c < 4; ++c) out.R[c] += w[k] * kKeys[k].R[c];
    for (size_t c = 0; c < 3; ++c) out.T[c] += w[k] * kKeys[k].T[c];
    out.fov += w[k] * kKeys[k].fov;
  }
  const double n = std::sqrt(out.R[0] * out.R[0] + out.R[1] * out.R[1] + out.R[2] * out.R[2] + out.R[3] * out.R[3]);
  for (double& c : out.R) c /= n;
  return out;
}

class NgpCameraPathTest : public TempDirTest {
 protected:
  static json keyframe(const Key& k) {
    return {{"R", {k.R[0], k.R[1], k.R[2], k.R[3]}}, {"T", {k.T[0], k.T[1], k.T[2]}}, {"fov", k.fov},
            {"slice", 0.0}, {"scale", 1.5}, {"aperture_size", 0.0}};
  }
  static json path() {
    json p = {{"time", 0.37}, {"path", json::array()}};
    for (const Key& k : kKeys) p["path"].push_back(keyframe(k));
    return p;
  }
  std::string write(const json& p, const std::string& name = "base_cam.json") const {
    writeJson(dir() / name, p);
    return (dir() / name).string();
  }
  // 40 x 30 pixels, 4 frames: t = 0, 1/4, 1/2, 3/4.
  static CameraPathOptions fourFrames(const std::string& scene = "") {
    CameraPathOptions o;
    o.width = 40;
    o.height = 30;
    o.fps = 4;
    o.seconds = 1;
    o.scene = scene;
    return o;
  }
  std::string errorWith(const std::function<void(json&)>& edit) const {
    json p = path();
    edit(p);
    const std::string file = write(p, "bad.json");
    return errorOf([&] { loadCameraPath(file, fourFrames()); });
  }
};

void expectCamera(const Camera& c, const Key& k, const NgpFrame& frame, const std::string& what) {
  const auto m = expectedPose(k.R, k.T, frame);
  for (size_t i = 0; i < 16; ++i) EXPECT_NEAR(c.c2w[i], m[i], 2e-5) << what << " element " << i;
  const double fy = 15 / std::tan(0.5 * k.fov * std::numbers::pi / 180);  // vertical fov over 30 rows
  EXPECT_NEAR(c.fy, fy, 1e-4 * fy) << what;
  EXPECT_EQ(c.fx, c.fy) << what;
  EXPECT_EQ(c.cx, 20) << what;
  EXPECT_EQ(c.cy, 15) << what;
  EXPECT_EQ(c.width, 40u) << what;
  EXPECT_EQ(c.height, 30u) << what;
}

}  // namespace

TEST_F(NgpCameraPathTest, FramesAreTheClampedBsplineAtRunPyTimesInTheScenesFrame) {
  // The scene's own scale and offset (as instant-ngp reads them from transforms.json).
  writeJson(dir() / "transforms.json", {{"scale", 0.5}, {"offset", {0.1, 0.2, 0.3}}, {"frames", json::array()}});
  CameraPath cp = loadCameraPath(write(path()), fourFrames(dir().string()));
  EXPECT_EQ(cp.format, CameraPath::Format::instantNgp);
  EXPECT_EQ(cp.fps, 4);
  ASSERT_EQ(cp.cameras.size(), 4u);
  EXPECT_MESSAGE_HAS(cp.frameNote, "scale 0.5, offset (0.1, 0.2, 0.3) from " + (dir() / "transforms.json").string());
  NgpFrame frame;
  frame.scale = 0.5;
  frame.offset = {0.1, 0.2, 0.3};
  // t * (keyframes - 1) = 0, 0.5, 1, 1.5. At a knot the cubic B-spline weighs the neighbours
  // 1/6, 4/6, 1/6; half way between, 1/48, 23/48, 23/48, 1/48; indices past the ends are the ends.
  expectCamera(cp.cameras[0], blend({5.0 / 6, 1.0 / 6, 0}), frame, "t = 0");
  expectCamera(cp.cameras[1], blend({24.0 / 48, 23.0 / 48, 1.0 / 48}), frame, "t = 1/4");
  expectCamera(cp.cameras[2], blend({1.0 / 6, 4.0 / 6, 1.0 / 6}), frame, "t = 1/2");
  expectCamera(cp.cameras[3], blend({1.0 / 48, 23.0 / 48, 24.0 / 48}), frame, "t = 3/4");
}

TEST_F(NgpCameraPathTest, OneKeyframeIsThatPoseEverywhere) {
  json p = path();
  p["path"].erase(1);
  p["path"].erase(1);
  CameraPath cp = loadCameraPath(write(p), fourFrames());
  ASSERT_EQ(cp.cameras.size(), 4u);
  for (size_t i = 0; i < 4; ++i) expectCamera(cp.cameras[i], kKeys[0], NgpFrame{}, "frame " + std::to_string(i));
  EXPECT_MESSAGE_HAS(cp.frameNote, "scale 0.33, offset (0.5, 0.5, 0.5) from instant-ngp's defaults");
}

TEST_F(NgpCameraPathTest, AQuaternionsSignDoesNotChangeThePath) {
  json flipped = path();
  for (auto& c : flipped["path"][1]["R"]) c = -c.get<double>();
  CameraPath a = loadCameraPath(write(path()), fourFrames()), b = loadCameraPath(write(flipped, "flipped.json"), fourFrames());
  for (size_t i = 0; i < 4; ++i)
    for (size_t k = 0; k < 16; ++k) EXPECT_NEAR(a.cameras[i].c2w[k], b.cameras[i].c2w[k], 1e-6) << i << " " << k;
}

TEST_F(NgpCameraPathTest, RunPysDefaultsAreSixtyFramesOfFullHd) {
  CameraPath cp = loadCameraPath(write(path()));
  EXPECT_EQ(cp.cameras.size(), 60u);
  EXPECT_EQ(cp.fps, 60);
  EXPECT_EQ(cp.cameras[0].width, 1920u);
  EXPECT_EQ(cp.cameras[0].height, 1080u);
}

// instant-ngp's ngp_matrix_to_nerf on two poses worked out by hand.
TEST(NgpCameraFrame, PosesConvertAsWorkedOutByHand) {
  const NgpFrame defaults;  // scale 0.33, offset 0.5
  // The identity: instant-ngp's camera looks down its +z (the dataset's +x) with its +y (the
  // dataset's +z) down. Position (0.5, 0.6, 0.7) is the dataset's (0.7, 0.5, 0.6) * 0.33 + 0.5.
  NgpKeyframe k;
  k.R = {0, 0, 0, 1};
  k.T = {0.5, 0.6, 0.7};
  const std::array<double, 16> identity{0, 0, -1, 0.2 / 0.33,  //
                                        1, 0, 0,  0,           //
                                        0, -1, 0, 0.1 / 0.33,  //
                                        0, 0, 0,  1};
  auto m = io::detail::ngpPoseToDataset(k, defaults);
  for (size_t i = 0; i < 16; ++i) EXPECT_NEAR(m[i], identity[i], 1e-12) << i;
  // 90 degrees about instant-ngp's y: right = ngp -z (dataset -x), down = ngp +y (dataset +z),
  // forward = ngp +x (dataset +y).
  k.R = {0, std::sqrt(0.5), 0, std::sqrt(0.5)};
  k.T = {0.5, 0.5, 0.5};
  const std::array<double, 16> turned{-1, 0, 0,  0,  //
                                      0,  0, -1, 0,  //
                                      0,  -1, 0, 0,  //
                                      0,  0, 0,  1};
  m = io::detail::ngpPoseToDataset(k, defaults);
  for (size_t i = 0; i < 16; ++i) EXPECT_NEAR(m[i], turned[i], 1e-12) << i;
}

TEST_F(NgpCameraPathTest, SceneFrameComesFromTransformsJsonAsInstantNgpReadsIt) {
  // "aabb" overrides scale and offset: its longest side becomes 1, its centre (0.5, 0.5, 0.5).
  writeJson(dir() / "box.json", {{"scale", 3.0}, {"aabb", {{0, 0, 0}, {2, 4, 2}}}});
  NgpFrame f = io::detail::ngpFrameOfScene((dir() / "box.json").string());
  EXPECT_DOUBLE_EQ(f.scale, 0.25);
  EXPECT_DOUBLE_EQ(f.offset[0], 0.25);
  EXPECT_DOUBLE_EQ(f.offset[1], 0.0);
  EXPECT_DOUBLE_EQ(f.offset[2], 0.25);
  // One number is the offset of every axis; a split scene's transforms_train.json is read.
  fs::create_directories(dir() / "split");
  writeJson(dir() / "split" / "transforms_train.json", {{"offset", 0.25}});
  f = io::detail::ngpFrameOfScene((dir() / "split").string());
  EXPECT_DOUBLE_EQ(f.scale, 0.33);
  EXPECT_EQ(f.offset, (std::array<double, 3>{0.25, 0.25, 0.25}));
  // A folder with no transforms file (a COLMAP scene): instant-ngp's defaults, said so.
  fs::create_directories(dir() / "colmap");
  f = io::detail::ngpFrameOfScene((dir() / "colmap").string());
  EXPECT_DOUBLE_EQ(f.scale, 0.33);
  EXPECT_MESSAGE_HAS(f.source, "instant-ngp's defaults (no transforms.json in");
  writeJson(dir() / "bad.json", {{"scale", -1}});
  EXPECT_MESSAGE_HAS(errorOf([&] { io::detail::ngpFrameOfScene((dir() / "bad.json").string()); }),
                     "bad.json: field 'scale' must be positive");
}

TEST_F(NgpCameraPathTest, EveryMalformedFieldNamesTheFileAndTheField) {
  const std::string file = (dir() / "bad.json").string() + ": field '";
  struct Case {
    std::function<void(json&)> edit;
    std::string fragment;
  };
  const Case cases[] = {
      {[](json& p) { p["path"][1].erase("R"); }, "path[1].R' is missing"},
      {[](json& p) { p["path"][0]["R"] = {0, 0, 0, 2}; }, "path[0].R' must be a unit quaternion (x, y, z, w), its length is 2"},
      {[](json& p) { p["path"][2]["R"][1] = NAN; }, "path[2].R' must be an array of 4 finite numbers"},  // NaN: null
      {[](json& p) { p["path"][2]["R"] = {0, 0, 1}; }, "path[2].R' must be an array of 4 finite numbers"},
      {[](json& p) { p["path"][1].erase("T"); }, "path[1].T' is missing"},
      {[](json& p) { p["path"][0]["fov"] = 0; }, "path[0].fov' must be in (0, 180) degrees"},
      {[](json& p) { p["path"][0]["fov"] = 180; }, "path[0].fov' must be in (0, 180) degrees"},
      {[](json& p) { p["path"][2].erase("fov"); }, "path[2].fov' is missing"},
      {[](json& p) { p["path"] = json::array(); }, "path' is empty"},
      {[](json& p) { p["path"] = 1; }, "path' must be an array of keyframes"},
      {[](json& p) { p["path"][0]["timestamp"] = 0.5; }, "path[0].timestamp' is present: instant-ngp's newer timed format"},
      {[](json& p) { p["loop"] = true; }, "loop' is true"},
      {[](json& p) { p.erase("path"); }, "camera_path' is missing (nor is there instant-ngp's keyframe list 'path')"},
  };
  for (const Case& c : cases) EXPECT_MESSAGE_HAS(errorWith(c.edit), file + c.fragment);
  // Duration and rate that give no frame.
  const std::string good = write(path());
  CameraPathOptions o = fourFrames();
  o.seconds = 0.01;
  EXPECT_MESSAGE_HAS(errorOf([&] { loadCameraPath(good, o); }), "base_cam.json: 4.000000 frames/s for 0.010000 s gives no whole frame");
}

// Through the command line: --seconds/--width/--height are refused for a nerfstudio path (before
// any model is read), and an instant-ngp path renders fps * seconds frames of the asked size.
TEST_F(NgpCameraPathTest, RenderSamplesTheKeyframesAtTheAskedRateAndSize) {
  json ns = {{"render_width", 8}, {"render_height", 6}, {"camera_path", json::array()}};
  json flat = json::array();
  for (double v : poseLookingAt({4, 0, 1}, {0, 0, 0})) flat.push_back(v);
  ns["camera_path"].push_back({{"camera_to_world", flat}, {"fov", 50}});
  const std::string nsFile = write(ns, "ns.json");
  auto refused = runCli("render " + (dir() / "none.vknerf").string() + " --path " + nsFile + " --seconds 2 -o " +
                        (dir() / "out").string());
  EXPECT_NE(refused.code, 0) << refused.output;
  EXPECT_MESSAGE_HAS(refused.output, "is a nerfstudio camera path, which lists its frames and their size");

  const std::string model = (dir() / "tiny.vknerf").string();
  auto t = runCli("train " + scene() + " -o " + model + " --downscale 4 --steps 2");
  ASSERT_EQ(t.code, 0) << t.output;
  auto r = runCli("render " + model + " --path " + write(path()) + " --fps 4 --seconds 0.5 --width 16 --height 12 -o " +
                  (dir() / "frames").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_MESSAGE_HAS(r.output, "instant-ngp camera path, 2 frames at 4 frames/s; its frame: scale 0.33, offset (0.5, "
                               "0.5, 0.5) from instant-ngp's defaults (give the SCENE");
  EXPECT_MESSAGE_HAS(r.output, "frame 0001 (2/2): 16x12");
  EXPECT_TRUE(fs::exists(dir() / "frames" / "rgb_0001.png"));
  EXPECT_FALSE(fs::exists(dir() / "frames" / "rgb_0002.png"));
}
