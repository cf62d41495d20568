// COLMAP binary model: cameras.bin, images.bin and (optionally) points3D.bin, parsed into a
// ColmapModel (colmap_scene.cpp gives it its meaning).
//
// Layout (little-endian, no padding), as COLMAP's reconstruction_io_binary.cc writes it:
//   cameras.bin   u64 count, then per camera: u32 camera_id, i32 model_id, u64 width, u64 height,
//                 f64 params[the model's count]
//   images.bin    u64 count, then per image: u32 image_id, f64 qw qx qy qz tx ty tz, u32 camera_id,
//                 the name NUL-terminated, u64 n, n x (f64 x, f64 y, u64 point3D_id)
//   points3D.bin  u64 count, then per point: u64 point3D_id, f64 x y z, u8 r g b, f64 error, u64 n,
//                 n x (u32 image_id, u32 point2D_idx)
// Every read is bounds-checked, and a count is checked against the bytes left before anything is
// sized by it, so a truncated or corrupt file is an error naming the file and the record.
#include <bit>
#include <cmath>
#include <fstream>
#include <iterator>
#include <type_traits>

#include "io/colmap/colmap_model.h"
#include "vknerf/error.h"

namespace vknerf::io::detail {
namespace {

// Smallest record of each file: the fixed fields, the fewest camera parameters (3) and a one-byte
// (empty) name; what a count may claim is bounded by the bytes left divided by these.
constexpr size_t kMinCamera = 4 + 4 + 8 + 8 + 3 * 8;
constexpr size_t kMinImage = 4 + 7 * 8 + 4 + 1 + 8;
constexpr size_t kMinPoint = 8 + 3 * 8 + 3 + 8 + 8;
constexpr size_t kPoint2D = 8 + 8 + 8;
constexpr size_t kTrackElement = 4 + 4;

// The bytes of one file and a cursor into them; messages name the file and the current record.
class BinaryFile {
 public:
  explicit BinaryFile(const fs::path& path) : path_(path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot open '" + path.string() + "'");
    bytes_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (in.bad()) throw Error("cannot read '" + path.string() + "'");
  }

  const fs::path& path() const { return path_; }
  size_t left() const { return bytes_.size() - at_; }
  // "camera 3 (record 2 of 5)", or "record 2 of 5" before the id is read.
  void setRecord(std::string record) { record_ = std::move(record); }
  std::string where() const { return path_.string() + (record_.empty() ? "" : ": " + record_); }
  [[noreturn]] void fail(const std::string& what) const { throw Error(where() + ": " + what); }

  template <class T>
  T read(const char* what) {
    need(sizeof(T), what);
    uint64_t v = 0;
    for (size_t i = 0; i < sizeof(T); ++i) v |= uint64_t(uint8_t(bytes_[at_ + i])) << (8 * i);
    at_ += sizeof(T);
    if constexpr (std::is_same_v<T, double>)
      return std::bit_cast<double>(v);
    else
      return T(v);
  }

  double finite(const char* what) {
    double v = read<double>(what);
    if (!std::isfinite(v)) fail(std::string(what) + " is not finite");
    return v;
  }

  std::string name(const char* what) {
    for (size_t end = at_; end < bytes_.size(); ++end)
      if (bytes_[end] == '\0') {
        std::string s(bytes_.data() + at_, end - at_);
        at_ = end + 1;
        return s;
      }
    fail(std::string("file ends inside the ") + what + " (no terminating NUL byte)");
  }

  // A u64 count of items of at least `itemSize` bytes each, checked against the bytes left.
  uint64_t count(size_t itemSize, const char* what) {
    uint64_t n = read<uint64_t>((std::string("count of ") + what).c_str());
    if (n > left() / itemSize)
      fail("file ends inside the " + std::string(what) + " (" + std::to_string(n) + " claimed, " +
           std::to_string(left()) + " bytes left, at least " + std::to_string(itemSize) + " each)");
    return n;
  }

  void skip(uint64_t n, size_t itemSize) { at_ += size_t(n) * itemSize; }  // after count(): in bounds

  void expectEnd() {
    setRecord("");
    if (left() != 0) fail(std::to_string(left()) + " bytes after the last record (a wrong count, or not a COLMAP model)");
  }

 private:
  void need(size_t n, const char* what) const {
    if (left() < n) fail(std::string("file ends inside the ") + what);
  }

  fs::path path_;
  std::vector<char> bytes_;
  size_t at_ = 0;
  std::string record_;
};

std::string recordOf(uint64_t i, uint64_t n) { return "record " + std::to_string(i + 1) + " of " + std::to_string(n); }

void readCameras(const fs::path& path, ColmapModel& model) {
  BinaryFile f(path);
  const uint64_t n = f.count(kMinCamera, "cameras");
  for (uint64_t i = 0; i < n; ++i) {
    const std::string record = recordOf(i, n);
    f.setRecord(record);
    const uint32_t id = f.read<uint32_t>("camera id");
    f.setRecord("camera " + std::to_string(id) + " (" + record + ")");
    ColmapCamera c;
    c.where = f.where();
    const int32_t modelId = f.read<int32_t>("model id");
    c.model = colmapModelById(modelId);
    if (!c.model) f.fail("model id " + std::to_string(modelId) + " is not a COLMAP camera model");
    c.width = f.read<uint64_t>("width");
    c.height = f.read<uint64_t>("height");
    // The model fixes the parameter count: check it against the bytes left before sizing by it.
    if (f.left() < c.model->params * 8)
      f.fail(std::string("file ends inside the ") + c.model->name + " parameters");
    c.params.resize(c.model->params);
    for (double& p : c.params) p = f.read<double>("parameters");
    model.addCamera(id, std::move(c));
  }
  f.expectEnd();
}

void readImages(const fs::path& path, ColmapModel& model) {
  BinaryFile f(path);
  const uint64_t n = f.count(kMinImage, "images");
  model.images.reserve(n);
  for (uint64_t i = 0; i < n; ++i) {
    const std::string record = recordOf(i, n);
    f.setRecord(record);
    const uint32_t id = f.read<uint32_t>("image id");
    f.setRecord("image " + std::to_string(id) + " (" + record + ")");
    ColmapImage img;
    img.where = f.where();
    for (double& v : img.q) v = f.finite("quaternion");
    for (double& v : img.t) v = f.finite("translation");
    img.cameraId = f.read<uint32_t>("camera id");
    img.name = f.name("name");
    if (img.name.empty()) f.fail("the image name is empty");
    f.skip(f.count(kPoint2D, "2-D points"), kPoint2D);
    model.images.push_back(std::move(img));
  }
  f.expectEnd();
}

void readPoints(const fs::path& path, ColmapModel& model) {
  BinaryFile f(path);
  const uint64_t n = f.count(kMinPoint, "points");
  model.points.reserve(n);
  for (uint64_t i = 0; i < n; ++i) {
    const std::string record = recordOf(i, n);
    f.setRecord(record);
    const uint64_t id = f.read<uint64_t>("point id");
    f.setRecord("point " + std::to_string(id) + " (" + record + ")");
    std::array<double, 3> p;
    for (double& v : p) v = f.finite("position");
    for (int k = 0; k < 3; ++k) f.read<uint8_t>("colour");
    f.read<double>("error");
    f.skip(f.count(kTrackElement, "track"), kTrackElement);
    model.points.push_back(p);
  }
  f.expectEnd();
}

}  // namespace

ColmapModel readColmapBinary(const fs::path& modelDir) {
  ColmapModel model;
  model.camerasFile = modelDir / "cameras.bin";
  model.imagesFile = modelDir / "images.bin";
  readCameras(model.camerasFile, model);
  readImages(model.imagesFile, model);
  std::error_code ec;
  if (fs::is_regular_file(modelDir / "points3D.bin", ec)) readPoints(modelDir / "points3D.bin", model);
  return model;
}

}  // namespace vknerf::io::detail
