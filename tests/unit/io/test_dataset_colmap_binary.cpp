// COLMAP binary models: the same scenes as the text tests load to identical Datasets from either
// form; truncated and corrupt files, absurd counts and unusable camera models are errors that name
// the file and the record.
#include <cmath>
#include <fstream>
#include <functional>
#include <iterator>

#include "support/colmap_model_files.h"
#include "support/dataset_checks.h"
#include "support/dataset_files.h"
#include "support/error_message.h"
#include "support/temp_dir.h"

using namespace vknerf;
using namespace vknerf::test;

namespace {

const ColmapCameraRecord kPinhole{1, "PINHOLE", 16, 12, {20, 20, 8, 6}};

// test_dataset_colmap's PoseRoundTripAndPointsNormalisation scene: six cameras around (2, 1, 2)
// and an 11^3 grid of points, here with 2-D points and tracks too (which the loader skips).
ColmapModelRecords orbitScene() {
  const Vec3 target{2, 1, 2};
  const std::vector<Vec3> eyes = {{8, 1, 3}, {-4, 0, 2.5}, {2, 7, 1}, {1, -5, 4}, {3, 2, -4}, {2.1, 0.9, 9}};
  ColmapModelRecords m;
  m.cameras = {kPinhole};
  for (uint32_t i = 0; i < eyes.size(); ++i) {
    m.images.push_back(imageRecord(i + 1, poseLookingAt(eyes[i], target), 1, "img" + std::to_string(i) + ".png"));
    m.images.back().points2D = {{1.5, 2.5, int64_t(i) + 1}, {7.25, 3.0, -1}};
  }
  uint64_t id = 1;
  for (int a = 0; a <= 10; ++a)
    for (int b = 0; b <= 10; ++b)
      for (int c = 0; c <= 10; ++c) {
        ColmapPointRecord p;
        p.id = id++;
        p.xyz = {-2 + 0.8 * a, 0.2 * b, 1 + 0.2 * c};
        p.track = {{1, 0}, {uint32_t(1 + a % 6), 1}};
        m.points.push_back(p);
      }
  return m;
}

// test_dataset_colmap's PinholeModelsAndZeroDistortion scene: five camera models, no points.
ColmapModelRecords modelsScene() {
  ColmapModelRecords m;
  m.cameras = {{1, "SIMPLE_PINHOLE", 16, 12, {20, 8, 6}},
               {2, "PINHOLE", 16, 12, {21, 22, 7.5, 6.5}},
               {3, "SIMPLE_RADIAL", 16, 12, {23, 8.25, 6, 0}},
               {4, "RADIAL", 16, 12, {24, 8, 5.75, 0, 0}},
               {5, "OPENCV", 16, 12, {25, 26, 8, 6, 0, 0, 0, 0}}};
  const std::vector<Vec3> eyes = {{4, 0, 0}, {0, 4, 0}, {-4, 0, 1}, {0, -4, 1}, {0, 0, 4}};
  for (uint32_t i = 0; i < eyes.size(); ++i)
    m.images.push_back(imageRecord(i + 1, poseLookingAt(eyes[i], {0, 0, 0}), i + 1, std::string(1, char('a' + i)) + ".png"));
  return m;
}

// A small model for byte-level damage: two cameras, three images with 2-D points (in an order that
// the name sort changes), four points with tracks.
ColmapModelRecords smallScene() {
  ColmapModelRecords m;
  m.cameras = {kPinhole, {2, "SIMPLE_PINHOLE", 16, 12, {19, 8, 6}}};
  m.images = {imageRecord(7, poseLookingAt({4, 0, 0}, {0, 0, 0}), 1, "c.png"),
              imageRecord(2, poseLookingAt({0, 4, 0}, {0, 0, 0}), 2, "a.png"),
              imageRecord(3, poseLookingAt({0, 0, 4}, {0, 0, 0}), 1, "b.png")};
  m.images[0].points2D = {{1, 2, 1}, {3, 4, -1}};
  m.images[2].points2D = {{5, 6, 2}};
  for (uint64_t i = 0; i < 4; ++i) {
    ColmapPointRecord p;
    p.id = 10 + i;
    p.xyz = {0.5 * double(i), -0.25 * double(i), 0.1 + double(i % 2)};
    p.track = {{7, uint32_t(i)}, {3, 0}};
    m.points.push_back(p);
  }
  return m;
}

std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Overwrites sizeof(T) bytes of `p` at `offset` with `v`, little-endian.
template <class T>
void patch(const fs::path& p, size_t offset, T v) {
  std::string bytes = readBytes(p);
  ASSERT_LE(offset + sizeof(T), bytes.size());
  for (size_t i = 0; i < sizeof(T); ++i) bytes[offset + i] = char((uint64_t(v) >> (8 * i)) & 0xff);
  writeText(p, bytes);
}

class DatasetColmapBinary : public TempDirTest {
 protected:
  // The model in `scene`/sparse/0 in the given form, and images (16 x 12) named as its images (that
  // have a name).
  template <class Write>
  fs::path writeScene(const fs::path& scene, const ColmapModelRecords& m, Write write) {
    write(scene / "sparse" / "0", m);
    fs::create_directories(scene / "images");
    for (size_t i = 0; i < m.images.size(); ++i)
      if (!m.images[i].name.empty()) writePng(scene / "images" / m.images[i].name, patternImage(16, 12, uint32_t(i)));
    return scene / "sparse" / "0";
  }
  fs::path writeBinary(const ColmapModelRecords& m) { return writeScene(dir(), m, writeColmapBinary); }
  std::string loadError() {
    return errorOf([&] { Dataset::load(dir().string(), {.split = "all"}); });
  }
};

void expectSameDataset(const Dataset& a, const Dataset& b) {
  test::expectSameCameras(a, b);
  ASSERT_EQ(a.images.size(), b.images.size());
  EXPECT_EQ(a.boundsSource, b.boundsSource);
  for (size_t i = 0; i < a.cameras.size(); ++i) {
    EXPECT_EQ(fs::path(a.names[i]).filename(), fs::path(b.names[i]).filename());
    EXPECT_EQ(a.images[i].rgba, b.images[i].rgba);
  }
}

}  // namespace

TEST_F(DatasetColmapBinary, BinaryAndTextFormsLoadToIdenticalDatasets) {
  for (const auto& [label, model] : {std::pair{"orbit", orbitScene()}, std::pair{"models", modelsScene()}}) {
    SCOPED_TRACE(label);
    const fs::path text = dir() / label / "text", binary = dir() / label / "binary";
    writeScene(text, model, writeColmapText);
    writeScene(binary, model, writeColmapBinary);
    for (DatasetOptions o : {DatasetOptions{.split = "all"}, DatasetOptions{.split = "test", .holdoutFraction = 0.34f}}) {
      Dataset t = Dataset::load(text.string(), o), b = Dataset::load(binary.string(), o);
      EXPECT_EQ(t.cameras.size(), o.split == "all" ? model.images.size() : 2u);
      expectSameDataset(t, b);
    }
  }
  // What the text tests assert of these scenes holds for the binary form too.
  Dataset orbit = Dataset::load((dir() / "orbit" / "binary").string(), {.split = "all"});
  EXPECT_EQ(orbit.boundsSource, "points3D");
  EXPECT_NEAR(orbit.bounds.max[0], 1, 1e-6);
  EXPECT_NEAR(orbit.bounds.max[1], 1.4 / 4.4, 1e-6);
  Dataset models = Dataset::load((dir() / "models" / "binary").string(), {.split = "all"});
  EXPECT_EQ(models.boundsSource, "cameras");
  EXPECT_EQ(models.cameras[4].fy, 26.0f);
  EXPECT_EQ(models.cameras[2].cx, 8.25f);
}

TEST_F(DatasetColmapBinary, FolderLayoutsAndTextPreferredOverBinary) {
  const fs::path s = dir() / "scene";
  const ColmapModelRecords m = smallScene();
  for (const fs::path& model : {s / "sparse" / "0", s / "sparse", s}) {
    fs::remove_all(s);
    writeScene(s, m, [&](const fs::path&, const ColmapModelRecords& r) { writeColmapBinary(model, r); });
    Dataset d = Dataset::load(s.string(), {.split = "all"});
    ASSERT_EQ(d.cameras.size(), 3u) << model;
    EXPECT_EQ(fs::path(d.names[0]), s / "images" / "a.png");  // sorted by name
    EXPECT_EQ(d.cameras[0].fx, 19.0f);                        // a.png uses camera 2
  }
  // Both forms in one folder: the text one is read.
  ColmapModelRecords edited = m;
  edited.cameras[1].params[0] = 30;
  writeColmapText(s, edited);
  EXPECT_EQ(Dataset::load(s.string(), {.split = "all"}).cameras[0].fx, 30.0f);
  // Half a binary model is an error that names the missing file.
  fs::remove(s / "cameras.txt");
  fs::remove(s / "images.txt");
  fs::remove(s / "images.bin");
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::load(s.string()); }), "cannot open '" + (s / "images.bin").string() + "'");
}

TEST_F(DatasetColmapBinary, TruncationAtEveryOffsetNamesTheFile) {
  const fs::path model = writeBinary(smallScene());
  ASSERT_EQ(Dataset::load(dir().string(), {.split = "all"}).cameras.size(), 3u);
  for (const char* name : {"cameras.bin", "images.bin", "points3D.bin"}) {
    const std::string whole = readBytes(model / name);
    for (size_t size = 0; size < whole.size(); ++size) {
      writeText(model / name, whole.substr(0, size));
      const std::string e = loadError();
      EXPECT_MESSAGE_HAS(e, (model / name).string() + ": ");
      EXPECT_MESSAGE_HAS(e, "file ends inside the");
      if (::testing::Test::HasFailure()) FAIL() << name << " cut to " << size << " of " << whole.size() << " bytes";
    }
    writeText(model / name, whole);
  }
  // A few of those messages in full: they name the record and what was being read. A cut in an
  // early record mostly leaves too few bytes for the count of records (each at least 48 bytes for
  // cameras, 73 for images), so these cut the last record.
  const std::string images = readBytes(model / "images.bin");
  // Image 3 starts after the count and images 7 (4 + 56 + 4 + 6 + 8 + 2 * 24 bytes) and 2
  // (4 + 56 + 4 + 6 + 8); its name "b.png" starts 64 bytes in, its 2-D points 78 bytes in.
  const size_t image3 = 8 + 126 + 78;
  writeText(model / "images.bin", images.substr(0, image3 + 64 + 3));
  EXPECT_MESSAGE_HAS(loadError(), "images.bin: image 3 (record 3 of 3): file ends inside the name (no terminating NUL");
  writeText(model / "images.bin", images.substr(0, image3 + 78 + 10));
  EXPECT_MESSAGE_HAS(loadError(), "images.bin: image 3 (record 3 of 3): file ends inside the 2-D points (1 claimed");
  writeText(model / "images.bin", images);
  // Camera 2 (SIMPLE_PINHOLE) starts after the count and camera 1 (56 bytes); its 3 parameters 24 bytes in.
  const std::string cameras = readBytes(model / "cameras.bin");
  writeText(model / "cameras.bin", cameras.substr(0, 8 + 56 + 24 + 16));
  EXPECT_MESSAGE_HAS(loadError(), "cameras.bin: camera 2 (record 2 of 2): file ends inside the SIMPLE_PINHOLE parameters");
  writeText(model / "cameras.bin", "");
  EXPECT_MESSAGE_HAS(loadError(), "cameras.bin: file ends inside the count of cameras");
}

TEST_F(DatasetColmapBinary, AbsurdCountsAreRejectedBeforeAllocating) {
  const ColmapModelRecords m = smallScene();
  const uint64_t huge = ~uint64_t(0);
  struct Case {
    const char* file;
    size_t offset;
    std::string expected;
  };
  const Case cases[] = {
      {"cameras.bin", 0, "cameras.bin: file ends inside the cameras (18446744073709551615 claimed"},
      {"images.bin", 0, "images.bin: file ends inside the images (18446744073709551615 claimed"},
      {"points3D.bin", 0, "points3D.bin: file ends inside the points (18446744073709551615 claimed"},
      // Image 7's 2-D point count follows its id, pose, camera id and "c.png\0".
      {"images.bin", 8 + 4 + 56 + 4 + 6, "images.bin: image 7 (record 1 of 3): file ends inside the 2-D points"},
      // Point 10's track length follows its id, xyz, colour and error.
      {"points3D.bin", 8 + 8 + 24 + 3 + 8, "points3D.bin: point 10 (record 1 of 4): file ends inside the track"},
  };
  for (const Case& c : cases) {
    fs::remove_all(dir());
    const fs::path model = writeBinary(m);
    patch<uint64_t>(model / c.file, c.offset, huge);
    EXPECT_MESSAGE_HAS(loadError(), c.expected);
    // A count one too large: at the top the file ends inside the last record, or the count
    // itself is too large; inside a record the rest of the file is misread, still naming the file.
    fs::remove_all(dir());
    writeBinary(m);
    std::string bytes = readBytes(model / c.file);
    uint64_t count = 0;
    for (int i = 0; i < 8; ++i) count |= uint64_t(uint8_t(bytes[c.offset + i])) << (8 * i);
    patch<uint64_t>(model / c.file, c.offset, count + 1);
    const std::string e = loadError();
    EXPECT_MESSAGE_HAS(e, (model / c.file).string() + ": ");
    if (c.offset == 0) EXPECT_MESSAGE_HAS(e, "file ends inside the");
  }
  // A count too small leaves bytes after the last record.
  fs::remove_all(dir());
  const fs::path model = writeBinary(m);
  patch<uint64_t>(model / "points3D.bin", 0, 3);
  EXPECT_MESSAGE_HAS(loadError(), "points3D.bin: 67 bytes after the last record");
}

TEST_F(DatasetColmapBinary, UnknownAndUnusableCameraModelsNameTheRecord) {
  const ColmapModelRecords m = smallScene();
  fs::path model = writeBinary(m);
  // Camera 2's model id follows the count, camera 1 (4 + 4 + 8 + 8 + 4 * 8 bytes) and its id.
  patch<int32_t>(model / "cameras.bin", 8 + 56 + 4, 42);
  EXPECT_MESSAGE_HAS(loadError(), "cameras.bin: camera 2 (record 2 of 2): model id 42 is not a COLMAP camera model");
  patch<int32_t>(model / "cameras.bin", 8 + 56 + 4, -1);
  EXPECT_MESSAGE_HAS(loadError(), "cameras.bin: camera 2 (record 2 of 2): model id -1 is not a COLMAP camera model");
  const ColmapCameraRecord unusable[] = {{2, "FOV", 16, 12, {19, 19, 8, 6, 0.1}},
                                         {2, "THIN_PRISM_FISHEYE", 16, 12, {19, 19, 8, 6, 0, 0, 0, 0, 0, 0, 0, 0}}};
  for (const ColmapCameraRecord& c : unusable) {
    ColmapModelRecords bad = m;
    bad.cameras[1] = c;
    fs::remove_all(dir());
    model = writeBinary(bad);
    const std::string e = loadError();
    EXPECT_MESSAGE_HAS(e, "cameras.bin: camera 2 (record 2 of 2)");
    EXPECT_MESSAGE_HAS(e, c.model);
  }
}

TEST_F(DatasetColmapBinary, CorruptRecordsNameFileAndRecord) {
  struct Case {
    std::function<void(ColmapModelRecords&)> damage;
    std::string expected;
  };
  const Case cases[] = {
      {[](auto& m) { m.images[1].q[2] = std::nan(""); }, "images.bin: image 2 (record 2 of 3): quaternion is not finite"},
      {[](auto& m) { m.images[2].t[0] = INFINITY; }, "images.bin: image 3 (record 3 of 3): translation is not finite"},
      {[](auto& m) { m.images[1].q = {0, 0, 0, 0}; }, "images.bin: image 2 (record 2 of 3): quaternion is not unit length"},
      {[](auto& m) { m.images[1].camera = 9; },
       "images.bin: image 2 (record 2 of 3): image 'a.png' uses camera 9, which cameras.bin does not define"},
      {[](auto& m) { m.images[0].name = ""; }, "images.bin: image 7 (record 1 of 3): the image name is empty"},
      {[](auto& m) { m.points[3].xyz[1] = -INFINITY; }, "points3D.bin: point 13 (record 4 of 4): position is not finite"},
      {[](auto& m) { m.cameras[1].id = 1; }, "cameras.bin: camera 1 (record 2 of 2): camera 1 is defined twice"},
      {[](auto& m) { m.cameras[1].params[0] = -19; }, "cameras.bin: camera 2 (record 2 of 2): focal length must be positive"},
      {[](auto& m) { m.cameras[0].width = 0; }, "cameras.bin: camera 1 (record 1 of 2): image size 0x12 is not valid"},
      {[](auto& m) { m.cameras.clear(); }, "cameras.bin' defines no cameras"},
      {[](auto& m) { m.images.clear(); }, "images.bin' lists no images"},
  };
  for (const Case& c : cases) {
    ColmapModelRecords m = smallScene();
    c.damage(m);
    fs::remove_all(dir());
    writeBinary(m);
    EXPECT_MESSAGE_HAS(loadError(), c.expected);
  }
}
