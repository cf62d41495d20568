// Bad transforms*.json input: every case is one vknerf::Error naming the file and the field (or
// frame, or image path), never a crash.
#include "support/dataset_files.h"
#include "support/error_message.h"
#include "support/temp_dir.h"

using namespace vknerf;
using namespace vknerf::test;

namespace {

class DatasetErrors : public TempDirTest {
 protected:
  // A valid two-frame transforms.json scene; tests break one thing in it.
  json scene() {
    writePng(dir() / "a.png", patternImage(8, 6, 0));
    writePng(dir() / "b.png", patternImage(8, 6, 1));
    return {{"camera_angle_x", 0.7},
            {"frames",
             {{{"file_path", "a"}, {"transform_matrix", matrixJson(poseLookingAt({4, 0, 1}, {0, 0, 0}))}},
              {{"file_path", "b"}, {"transform_matrix", matrixJson(poseLookingAt({0, 4, 1}, {0, 0, 0}))}}}}};
  }
  std::string file() const { return (dir() / "transforms.json").string(); }
  std::string loadError(const json& j, DatasetOptions o = {.split = "all"}) {
    writeJson(dir() / "transforms.json", j);
    return errorOf([&] { Dataset::load(dir().string(), o); });
  }
};

}  // namespace

TEST_F(DatasetErrors, TheValidSceneLoads) {
  writeJson(dir() / "transforms.json", scene());
  EXPECT_EQ(Dataset::load(dir().string(), {.split = "all"}).cameras.size(), 2u);
}

// One photo has one pose: listed twice with two, an error naming both entries; twice with the same
// pose, mere repetition.
TEST_F(DatasetErrors, OnePhotoListedWithTwoPoses) {
  json j = scene();
  j["frames"][1]["file_path"] = "a";
  EXPECT_MESSAGE_HAS(loadError(j), file() + ": frames[1]: image '" + (dir() / "a.png").string() +
                                       "' is listed again with another pose than at " + file() + ": frames[0]");
  j["frames"][1]["transform_matrix"] = j["frames"][0]["transform_matrix"];
  writeJson(dir() / "transforms.json", j);
  EXPECT_EQ(Dataset::load(dir().string(), {.split = "all"}).cameras.size(), 2u);
}

TEST_F(DatasetErrors, MissingOrUnrecognisedPath) {
  std::string missing = (dir() / "nothing").string();
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::load(missing); }), missing + "' does not exist");
  fs::create_directories(dir() / "empty");
  std::string e = errorOf([&] { Dataset::load((dir() / "empty").string()); });
  EXPECT_MESSAGE_HAS(e, (dir() / "empty").string());
  EXPECT_MESSAGE_HAS(e, "no transforms_train.json, transforms.json, poses_bounds.npy or COLMAP");
  writeText(dir() / "notes.txt", "hello");
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::load((dir() / "notes.txt").string()); }), "not a .json transforms file");
}

TEST_F(DatasetErrors, CorruptJsonNamesFileAndPosition) {
  writeText(dir() / "transforms.json", "{\n  \"camera_angle_x\": 0.7,\n  \"frames\": [ }\n");
  std::string e = errorOf([&] { Dataset::load(dir().string()); });
  EXPECT_MESSAGE_HAS(e, file() + ": invalid JSON");
  EXPECT_MESSAGE_HAS(e, "line 3, column 15");
  // Python writes NaN for a non-finite matrix entry: not JSON. (Columns count from 1.)
  writeText(dir() / "transforms.json", "{\"frames\": [{\"file_path\": \"a\", \"transform_matrix\": [[NaN]]}]}");
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::load(dir().string()); }), "line 1, column 54");
  // An overflowing literal: nlohmann names no position, the loader finds it.
  writeText(dir() / "transforms.json", "{\"camera_angle_x\": 0.7,\n \"frames\": [1e999]}");
  e = errorOf([&] { Dataset::load(dir().string()); });
  EXPECT_MESSAGE_HAS(e, file() + ": invalid JSON: at line 2, column 13");
  EXPECT_MESSAGE_HAS(e, "1e999");
  writeText(dir() / "transforms.json", "[1, 2]");
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::load(dir().string()); }), "top level is not a JSON object");
}

TEST_F(DatasetErrors, MissingOrEmptyFrames) {
  json j = scene();
  j.erase("frames");
  EXPECT_MESSAGE_HAS(loadError(j), file() + ": field 'frames' is missing");
  j["frames"] = json::array();
  EXPECT_MESSAGE_HAS(loadError(j), file() + ": field 'frames' is empty");
  j["frames"] = 3;
  EXPECT_MESSAGE_HAS(loadError(j), "field 'frames' must be an array");
  j = scene();
  j["frames"][1].erase("file_path");
  EXPECT_MESSAGE_HAS(loadError(j), "field 'frames[1].file_path' is missing");
  j = scene();
  j["frames"][0].erase("transform_matrix");
  EXPECT_MESSAGE_HAS(loadError(j), "field 'frames[0].transform_matrix' is missing");
  j = scene();
  j["frames"][1]["transform_matrix"] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  EXPECT_MESSAGE_HAS(loadError(j), "field 'frames[1].transform_matrix' must be a 4x4 (or 3x4) array of numbers");
  j["frames"][1]["transform_matrix"] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, "x"}, {0, 0, 0, 1}};
  EXPECT_MESSAGE_HAS(loadError(j), "field 'frames[1].transform_matrix' must be a 4x4");
}

TEST_F(DatasetErrors, MissingAndUnreadableImagesNameThePath) {
  json j = scene();
  j["frames"][1]["file_path"] = "train/r_7";
  std::string e = loadError(j);
  EXPECT_MESSAGE_HAS(e, file() + ": frames[1]: image not found");
  EXPECT_MESSAGE_HAS(e, (dir() / "train" / "r_7").string());
  writeText(dir() / "train" / "r_7.png", "not a png");
  e = loadError(j);
  EXPECT_MESSAGE_HAS(e, "cannot read image '" + (dir() / "train" / "r_7.png").string() + "'");
}

// An absolute path from the author's machine with no file of its name here either: the error
// names the json, the frame and file_path, and where else it looked.
TEST_F(DatasetErrors, AbsolutePathMissingEverywhereNamesTheFrameAndFilePath) {
  json j = scene();
  j["frames"][1]["file_path"] = "/nonexistent-vknerf-author/cap/images/r_9.png";
  const std::string e = loadError(j);
  EXPECT_EQ(e.rfind(file() + ": frames[1]: image not found: file_path '/nonexistent-vknerf-author/cap/images/r_9.png' "
                    "does not exist here, nor does r_9.png", 0), 0u) << e;
  EXPECT_MESSAGE_HAS(e, "beside " + file() + " or in " + (dir() / "images").string() + "/");
}

TEST_F(DatasetErrors, ImagesOfDifferentSizes) {
  // Frames may differ in size (nerfstudio's per-frame w/h): each camera takes its image's.
  json j = scene();
  writePng(dir() / "b.png", patternImage(10, 6, 1));
  writeJson(dir() / "transforms.json", j);
  Dataset d = Dataset::load(dir().string(), {.split = "all"});
  ASSERT_EQ(d.cameras.size(), 2u);
  EXPECT_EQ(d.cameras[0].width, 8u);
  EXPECT_EQ(d.cameras[1].width, 10u);
  EXPECT_EQ(d.images[1].width, 10u);
  // A JSON w/h that disagrees with the image.
  j = scene();
  j["w"] = 8;
  j["h"] = 7;
  EXPECT_MESSAGE_HAS(loadError(j), "frames[0]: image '" + (dir() / "a.png").string() + "' is 8x6 but the camera says 8x7");
}

TEST_F(DatasetErrors, NonRigidOrNonFinitePoses) {
  json j = scene();
  auto m = poseLookingAt({0, 4, 1}, {0, 0, 0});
  auto scaled = m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) scaled[4 * r + c] *= 2;
  j["frames"][1]["transform_matrix"] = matrixJson(scaled);
  std::string e = loadError(j);
  EXPECT_MESSAGE_HAS(e, file() + ": frames[1]: transform_matrix rotation part is not orthonormal");

  auto mirrored = m;
  for (int r = 0; r < 3; ++r) mirrored[4 * r] = -mirrored[4 * r];  // negate the x axis: det -1
  j["frames"][1]["transform_matrix"] = matrixJson(mirrored);
  EXPECT_MESSAGE_HAS(loadError(j), "frames[1]: transform_matrix rotation part has determinant -1");

  auto sheared = m;
  sheared[1] += 0.01;  // small but far beyond print rounding
  j["frames"][1]["transform_matrix"] = matrixJson(sheared);
  EXPECT_MESSAGE_HAS(loadError(j), "frames[1]: transform_matrix rotation part is not orthonormal");

  auto badRow = m;
  badRow[14] = 0.5;
  j["frames"][1]["transform_matrix"] = matrixJson(badRow);
  EXPECT_MESSAGE_HAS(loadError(j), "frames[1]: transform_matrix last row is not (0, 0, 0, 1)");

  // Rounding to 5 decimals, as some exporters print, is still rigid enough.
  auto rounded = m;
  for (double& v : rounded) v = std::round(v * 1e5) / 1e5;
  j["frames"][1]["transform_matrix"] = matrixJson(rounded);
  writeJson(dir() / "transforms.json", j);
  EXPECT_EQ(Dataset::load(dir().string(), {.split = "all"}).cameras.size(), 2u);
}

TEST_F(DatasetErrors, FocalLengthsAndAngles) {
  for (double a : {0.0, -0.5, M_PI, 4.0}) {
    json j = scene();
    j["camera_angle_x"] = a;
    EXPECT_MESSAGE_HAS(loadError(j), file() + ": field 'camera_angle_x' must be in (0, pi) radians");
  }
  json j = scene();
  j["frames"][1]["camera_angle_y"] = 3.2;
  EXPECT_MESSAGE_HAS(loadError(j), "field 'frames[1].camera_angle_y' must be in (0, pi)");
  for (double f : {0.0, -3.0}) {
    j = scene();
    j["fl_x"] = f;
    EXPECT_MESSAGE_HAS(loadError(j), file() + ": field 'fl_x' must be positive");
    j = scene();
    j["frames"][0]["fl_y"] = f;
    EXPECT_MESSAGE_HAS(loadError(j), "field 'frames[0].fl_y' must be positive");
  }
  j = scene();
  j["fl_x"] = "500";
  EXPECT_MESSAGE_HAS(loadError(j), "field 'fl_x' must be a number");
  j = scene();
  j.erase("camera_angle_x");
  EXPECT_MESSAGE_HAS(loadError(j), file() + ": frames[0]: no focal length (fl_x or camera_angle_x)");
  j = scene();
  j["w"] = 8.5;
  EXPECT_MESSAGE_HAS(loadError(j), "field 'w' must be a whole number of pixels");
}

TEST_F(DatasetErrors, LensFields) {
  // A lens that does not invert over the image names the file, the frame and the coefficients.
  json j = scene();
  j["k1"] = -10;
  EXPECT_MESSAGE_HAS(loadError(j), file() + ": frames[0]: k1 = -10: lens distortion does not invert over the image (fails at pixel (");
  j = scene();
  j["frames"][1]["k1"] = -10;
  EXPECT_MESSAGE_HAS(loadError(j), file() + ": frames[1]: k1 = -10: lens distortion does not invert");
  j = scene();
  j["k1"] = 1e39;
  EXPECT_MESSAGE_HAS(loadError(j), file() + ": field 'k1' is not finite as a 32-bit float");
  // instant-ngp's keys: k4 only with is_fisheye, no tangential terms on the fisheye.
  j = scene();
  j["k4"] = 0.01;
  EXPECT_MESSAGE_HAS(loadError(j), file() + ": field 'k4' is nonzero: k4 belongs to the fisheye model");
  j = scene();
  j["is_fisheye"] = true;
  j["frames"][1]["p2"] = -0.001;
  EXPECT_MESSAGE_HAS(loadError(j), "field 'frames[1].p2' is nonzero: the fisheye model has no tangential terms");
  j = scene();
  j["is_fisheye"] = "yes";
  EXPECT_MESSAGE_HAS(loadError(j), "field 'is_fisheye' must be true or false");
  // nerfstudio's camera_model.
  j = scene();
  j["camera_model"] = "EQUIRECTANGULAR";
  EXPECT_MESSAGE_HAS(loadError(j), file() + ": field 'camera_model' 'EQUIRECTANGULAR' is not handled (PINHOLE, OPENCV or OPENCV_FISHEYE)");
  j = scene();
  j["camera_model"] = 3;
  EXPECT_MESSAGE_HAS(loadError(j), "field 'camera_model' must be a string");
  j = scene();
  j["camera_model"] = "PINHOLE";
  j["frames"][0]["k1"] = 0.1;
  EXPECT_MESSAGE_HAS(loadError(j), "field 'frames[0].k1' is nonzero: camera_model 'PINHOLE' has no distortion");
  j = scene();
  j["camera_model"] = "OPENCV";
  j["is_fisheye"] = true;
  EXPECT_MESSAGE_HAS(loadError(j), "field 'is_fisheye' contradicts camera_model 'OPENCV'");
}

TEST_F(DatasetErrors, BadBoxFields) {
  json j = scene();
  j["aabb"] = {{0, 0, 0}, {1, -1, 1}};
  EXPECT_MESSAGE_HAS(loadError(j), file() + ": field 'aabb' must be [[min x, y, z], [max x, y, z]] with min < max");
  j = scene();
  j["aabb_scale"] = 0;
  EXPECT_MESSAGE_HAS(loadError(j), "field 'aabb_scale' must be positive");
  j = scene();
  j["offset"] = {0.5, 0.5};
  EXPECT_MESSAGE_HAS(loadError(j), "field 'offset' must be an array of 3 numbers");
}

TEST_F(DatasetErrors, OptionsAndSplits) {
  json j = scene();
  EXPECT_MESSAGE_HAS(loadError(j, {.split = "all", .downscale = 0}), "DatasetOptions.downscale must be at least 1");
  EXPECT_MESSAGE_HAS(loadError(j, {.split = "training"}), "DatasetOptions.split must be train, val, test or all");
  EXPECT_MESSAGE_HAS(loadError(j, {.holdoutFraction = 1.0f}), "DatasetOptions.holdoutFraction must be in [0, 1)");
  std::string e = loadError(j, {.split = "test", .holdoutFraction = 0});
  EXPECT_MESSAGE_HAS(e, "split 'test' is empty");
  EXPECT_MESSAGE_HAS(e, dir().string());
  EXPECT_MESSAGE_HAS(loadError(j, {.split = "all", .downscale = 7}), "is smaller than the downscale factor 7");
  // Split files: asking for a split whose file is absent names that file.
  fs::remove(dir() / "transforms.json");
  writeJson(dir() / "transforms_train.json", j);
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::load(dir().string(), {.split = "val"}); }),
                     (dir() / "transforms_val.json").string() + "' not found (split 'val')");
  // A broken test split does not stop the train split from loading.
  writeText(dir() / "transforms_test.json", "{ broken");
  EXPECT_EQ(Dataset::load(dir().string()).cameras.size(), 2u);
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::load(dir().string(), {.split = "test"}); }), "transforms_test.json: invalid JSON");
}
