// Dataset::fromMemory: what an application holds becomes the Dataset a scene file of the same
// cameras and images loads to, box included; what a loader would refuse is refused here too.
#include "support/dataset_files.h"
#include "support/error_message.h"
#include "support/temp_dir.h"

using namespace vknerf;
using namespace vknerf::test;

namespace {

class DatasetMemory : public TempDirTest {
 protected:
  // Three views of the origin, the first with a transparent third (so the box is carved).
  Dataset loaded() {
    writePng(dir() / "a.png", patternImage(12, 8, 0, true));
    writePng(dir() / "b.png", patternImage(12, 8, 1));
    writePng(dir() / "c.png", patternImage(12, 8, 2));
    json j = {{"camera_angle_x", 0.7},
              {"frames",
               {{{"file_path", "a"}, {"transform_matrix", matrixJson(poseLookingAt({4, 0, 1}, {0, 0, 0}))}},
                {{"file_path", "b"}, {"transform_matrix", matrixJson(poseLookingAt({0, 4, 1}, {0, 0, 0}))}},
                {{"file_path", "c"}, {"transform_matrix", matrixJson(poseLookingAt({-3, -3, 2}, {0, 0, 0}))}}}}};
    writeJson(dir() / "transforms.json", j);
    return Dataset::load(dir().string(), {.split = "all"});
  }
};

}  // namespace

TEST_F(DatasetMemory, MatchesTheSceneFileOfTheSameViews) {
  const Dataset file = loaded();
  const Dataset memory = Dataset::fromMemory(file.cameras, file.images);
  EXPECT_EQ(file.boundsSource, "cameras+alpha");  // the carving path, which needs the images
  EXPECT_EQ(memory.boundsSource, file.boundsSource);
  EXPECT_EQ(memory.bounds.min, file.bounds.min);
  EXPECT_EQ(memory.bounds.max, file.bounds.max);
  ASSERT_EQ(memory.images.size(), 3u);
  EXPECT_EQ(memory.images[2].rgba, file.images[2].rgba);
  EXPECT_EQ(memory.names[1], "image 1");
}

TEST_F(DatasetMemory, KeepsAGivenBox) {
  const Dataset file = loaded();
  const Aabb box{{-0.5f, -0.5f, -0.25f}, {0.5f, 0.5f, 0.75f}};
  const Dataset memory = Dataset::fromMemory(file.cameras, file.images, {"a", "b", "c"}, box);
  EXPECT_EQ(memory.boundsSource, "given");
  EXPECT_EQ(memory.bounds.max, box.max);
  EXPECT_EQ(memory.names[2], "c");
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::fromMemory(file.cameras, file.images, {}, Aabb{{0, 0, 0}, {1, 0, 1}}); }),
                     "min must be below its max");
}

TEST_F(DatasetMemory, RefusesWhatALoaderWould) {
  const Dataset file = loaded();
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::fromMemory({}, {}); }), "no cameras");
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::fromMemory(file.cameras, {file.images[0]}); }), "3 cameras but 1 images");
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::fromMemory(file.cameras, file.images, {"a"}); }), "3 cameras but 1 names");
  auto cameras = file.cameras;
  cameras[1].width = 13;
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::fromMemory(cameras, file.images); }), "camera 1: camera is 13x8 but its image is 12x8");
  cameras = file.cameras;
  cameras[2].fx = 0;
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::fromMemory(cameras, file.images); }), "camera 2: focal lengths");
  cameras = file.cameras;
  cameras[0].lens = {.model = LensModel::OpenCV, .k1 = -10};
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::fromMemory(cameras, file.images); }), "does not invert");
  auto images = file.images;
  images[0].rgba.pop_back();
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::fromMemory(file.cameras, images); }), "not width x height x 4");
}
