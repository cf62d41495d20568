#include "camera_arrays.h"

#include <algorithm>

#include "arrays.h"
#include "errors.h"

namespace py = pybind11;

namespace vknerf::python {

void setPose(Camera& c, const float* m) { std::copy(m, m + 16, c.c2w.begin()); }

void setIntrinsics(Camera& c, const py::handle& intrinsics, const std::string& name) {
  py::array a = py::array::ensure(intrinsics);
  if (a && a.ndim() == 2) {
    auto k = floats(a, name, {3, 3}, "(4,) fx fy cx cy or (3, 3) K");
    const float* p = k.data();
    c.fx = p[0], c.cx = p[2], c.fy = p[4], c.cy = p[5];
    if (p[1] != 0 || p[3] != 0 || p[6] != 0 || p[7] != 0 || p[8] != 1)
      throw InvalidArgument(name + ": K must be [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] (no skew)");
  } else {
    auto k = floats(intrinsics, name, {4}, "(4,) fx fy cx cy or (3, 3) K");
    c.fx = k.data()[0], c.fy = k.data()[1], c.cx = k.data()[2], c.cy = k.data()[3];
  }
}

void setLens(Camera& c, const py::handle& distortion, const std::string& lens, const std::string& name) {
  c.lens = Lens{};
  if (distortion.is_none()) {
    if (lens != "opencv" && lens != "pinhole") throw InvalidArgument(name + ": lens '" + lens + "' needs its distortion");
    return;
  }
  auto d = floats(distortion, name, {-1}, "(n,)");
  const float* k = d.data();
  const long n = long(d.size());
  if (lens == "opencv") {
    if (n != 4 && n != 5 && n != 8)
      throw InvalidArgument(name + ": OpenCV distortion is (k1, k2, p1, p2[, k3[, k4, k5, k6]]): 4, 5 or 8 values, got " +
                            std::to_string(n));
    c.lens.model = LensModel::OpenCV;
    c.lens.k1 = k[0], c.lens.k2 = k[1], c.lens.p1 = k[2], c.lens.p2 = k[3];
    if (n >= 5) c.lens.k3 = k[4];
    if (n == 8) c.lens.k4 = k[5], c.lens.k5 = k[6], c.lens.k6 = k[7];
  } else if (lens == "fisheye") {
    if (n != 4) throw InvalidArgument(name + ": fisheye distortion is (k1, k2, k3, k4), got " + std::to_string(n) + " values");
    c.lens.model = LensModel::Fisheye;
    c.lens.k1 = k[0], c.lens.k2 = k[1], c.lens.k3 = k[2], c.lens.k4 = k[3];
  } else {
    throw InvalidArgument(name + ": lens must be 'opencv' or 'fisheye', got '" + lens + "'");
  }
}

py::array_t<float> poseArray(const Camera& c) {
  return toArray(std::vector<float>(c.c2w.begin(), c.c2w.end()), {4, 4});
}

py::array_t<float> distortionArray(const Lens& l) {
  switch (l.model) {
    case LensModel::OpenCV: return toArray(std::vector<float>{l.k1, l.k2, l.p1, l.p2, l.k3, l.k4, l.k5, l.k6}, {8});
    case LensModel::Fisheye: return toArray(std::vector<float>{l.k1, l.k2, l.k3, l.k4}, {4});
    default: return toArray(std::vector<float>{}, {0});
  }
}

const char* lensName(LensModel m) {
  switch (m) {
    case LensModel::OpenCV: return "opencv";
    case LensModel::Fisheye: return "fisheye";
    default: return "pinhole";
  }
}

}  // namespace vknerf::python
