// Camera paths (vknerf/camera_path.h, nerfstudio's format) and `vknerf render --path ... --video`:
// the cameras are the path's poses with the focal length its vertical fov gives; every malformed
// field is one error naming the file and the field; a video has the path's frame count, size and
// rate, and a missing ffmpeg is a clear error before anything is rendered.
#include <cmath>
#include <cstdlib>
#include <functional>
#include <numbers>
#include <string>

#include "support/cli_run.h"
#include "support/dataset_files.h"
#include "support/error_message.h"
#include "vknerf/camera_path.h"

using namespace vknerf;
using namespace vknerf::test;

namespace {

class CameraPathTest : public TempDirTest {
 protected:
  // Four views around the origin, 40 x 30 pixels, vertical fov 50 degrees, 8 frames/s.
  json path() const {
    json p = {{"camera_type", "perspective"}, {"render_width", 40}, {"render_height", 30}, {"fps", 8},
              {"seconds", 0.5}, {"camera_path", json::array()}};
    for (int i = 0; i < 4; ++i) {
      json flat = json::array();
      for (double v : poseAt(i)) flat.push_back(v);
      p["camera_path"].push_back({{"camera_to_world", flat}, {"fov", 50}, {"aspect", 4.0 / 3}});
    }
    return p;
  }
  static std::array<double, 16> poseAt(int i) {
    const double a = 2 * std::numbers::pi * i / 4;
    return poseLookingAt({4 * std::cos(a), 4 * std::sin(a), 1.5}, {0, 0, 0});
  }
  std::string write(const json& p, const std::string& name = "path.json") const {
    writeJson(dir() / name, p);
    return (dir() / name).string();
  }
  std::string errorWith(const std::function<void(json&)>& edit) const {
    json p = path();
    edit(p);
    const std::string file = write(p, "bad.json");
    return errorOf([&] { loadCameraPath(file); });
  }
};

}  // namespace

TEST_F(CameraPathTest, CamerasAreThePosesWithTheFocalLengthOfTheVerticalFov) {
  CameraPath cp = loadCameraPath(write(path()));
  ASSERT_EQ(cp.cameras.size(), 4u);
  EXPECT_EQ(cp.fps, 8);
  const double fy = 15 / std::tan(25 * std::numbers::pi / 180);  // (H / 2) / tan(fov / 2)
  for (int i = 0; i < 4; ++i) {
    const Camera& c = cp.cameras[size_t(i)];
    EXPECT_EQ(c.width, 40u);
    EXPECT_EQ(c.height, 30u);
    EXPECT_NEAR(c.fy, fy, 1e-4 * fy);
    EXPECT_EQ(c.fx, c.fy);  // square pixels
    EXPECT_EQ(c.cx, 20);
    EXPECT_EQ(c.cy, 15);
    const auto m = poseAt(i);
    for (int k = 0; k < 16; ++k) EXPECT_EQ(c.c2w[size_t(k)], float(m[size_t(k)])) << i << " " << k;
  }
}

TEST_F(CameraPathTest, RowsOfFourAreReadLikeTheFlatMatrix) {
  json p = path();
  for (int i = 0; i < 4; ++i) p["camera_path"][size_t(i)]["camera_to_world"] = matrixJson(poseAt(i));
  CameraPath rows = loadCameraPath(write(p, "rows.json")), flat = loadCameraPath(write(path()));
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(rows.cameras[i].c2w, flat.cameras[i].c2w);
}

TEST_F(CameraPathTest, EveryMalformedFieldNamesTheFileAndTheField) {
  const std::string file = (dir() / "bad.json").string() + ": field '";
  struct Case {
    std::function<void(json&)> edit;
    std::string fragment;
  };
  const Case cases[] = {
      {[](json& p) { p.erase("render_width"); }, "render_width' is missing"},
      {[](json& p) { p["render_height"] = 0; }, "render_height' must be in [1"},
      {[](json& p) { p["render_height"] = 20.5; }, "render_height' must be a whole number"},
      {[](json& p) { p["fps"] = -1; }, "fps' must be in (0"},
      {[](json& p) { p["camera_type"] = "fisheye"; }, "camera_type' must be \"perspective\""},
      {[](json& p) { p["camera_path"] = json::array(); }, "camera_path' is empty"},
      {[](json& p) { p["camera_path"] = 3; }, "camera_path' must be an array"},
      {[](json& p) { p["camera_path"][1].erase("fov"); }, "camera_path[1].fov' is missing"},
      {[](json& p) { p["camera_path"][2]["fov"] = 180; }, "camera_path[2].fov' must be below 180"},
      {[](json& p) { p["camera_path"][0]["fov"] = "wide"; }, "camera_path[0].fov' must be a number"},
      {[](json& p) { p["camera_path"][3]["camera_to_world"].erase(0); }, "camera_path[3].camera_to_world' must be a 4x4"},
      {[](json& p) { p["camera_path"][3].erase("camera_to_world"); }, "camera_path[3].camera_to_world' is missing"},
  };
  for (const Case& c : cases) EXPECT_MESSAGE_HAS(errorWith(c.edit), file + c.fragment);
  // A pose that is not rigid: the message names the entry.
  EXPECT_MESSAGE_HAS(errorWith([](json& p) { p["camera_path"][1]["camera_to_world"][0] = 2.0; }),
                     "bad.json: camera_path[1].camera_to_world: the pose rotation part is not orthonormal");
  EXPECT_MESSAGE_HAS(errorOf([&] { loadCameraPath((dir() / "none.json").string()); }), "none.json");
}

// End to end through the command line: a tiny model of the sample scene rendered along the path.
TEST_F(CameraPathTest, RenderWritesAVideoOfThePathOrSaysFfmpegIsMissing) {
  const std::string model = (dir() / "tiny.vknerf").string();
  auto t = runCli("train " + scene() + " -o " + model + " --downscale 4 --steps 2");
  ASSERT_EQ(t.code, 0) << t.output;
  const std::string file = write(path()), video = (dir() / "path.mp4").string();

  // Without ffmpeg on PATH: a clear error before any frame, and no video.
  const std::string savedPath = std::getenv("PATH") ? std::getenv("PATH") : "";
  setenv("PATH", dir().c_str(), 1);
  auto missing = runCli("render " + model + " --path " + file + " --video " + video);
  setenv("PATH", savedPath.c_str(), 1);
  EXPECT_EQ(missing.code, 1) << missing.output;
  EXPECT_MESSAGE_HAS(missing.output, "ffmpeg is not installed (Debian package: ffmpeg)");
  EXPECT_EQ(missing.output.find("frame 0000"), std::string::npos) << missing.output;
  EXPECT_FALSE(fs::exists(video));

  if (std::system("ffprobe -version > /dev/null 2>&1") != 0) GTEST_SKIP() << "ffmpeg is not installed here";
  auto r = runCli("render " + model + " --path " + file + " --video " + video);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_MESSAGE_HAS(r.output, "frame 0003 (4/4)");
  const std::string probe = (dir() / "probe.txt").string();
  ASSERT_EQ(std::system(("ffprobe -v error -count_frames -select_streams v:0 -show_entries "
                         "stream=nb_read_frames,width,height,r_frame_rate,pix_fmt -of csv=p=0 " +
                         video + " > " + probe)
                            .c_str()),
            0);
  std::ifstream in(probe);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "40,30,yuv420p,8/1,4");  // size, player-safe format, the path's rate, every frame
  for (const auto& e : fs::directory_iterator(dir()))  // no temporary file is left behind
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
}
