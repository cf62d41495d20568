// vknerf.Dataset: loaded from a scene (Dataset::load) or built from NumPy arrays (Dataset::fromMemory).
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "arrays.h"
#include "bindings.h"
#include "camera_arrays.h"
#include "errors.h"
#include "holders.h"

namespace py = pybind11;

namespace vknerf::python {

namespace {

// (N, H, W, 3|4) uint8 or float32 (in [0, 1], clamped) as RGBA8, alpha 255 for RGB.
std::vector<ImageRGBA8> imagesFrom(const py::array& a) {
  if (a.ndim() != 4 || (a.shape(3) != 3 && a.shape(3) != 4) || a.shape(0) == 0)
    throw InvalidArgument("images must have shape (N, H, W, 3) or (N, H, W, 4) with N >= 1, got " + shapeText(a));
  const char kind = a.dtype().kind();
  const bool bytes = kind == 'u' && a.itemsize() == 1, reals = kind == 'f' && a.itemsize() == 4;
  if (!bytes && !reals)
    throw InvalidArgument("images must be uint8 (sRGB values 0-255) or float32 (0-1), got dtype " +
                          std::string(py::str(a.dtype())));
  checkContiguous(a, "images");
  const size_t n = a.shape(0), h = a.shape(1), w = a.shape(2), ch = a.shape(3), pixels = h * w;
  std::vector<ImageRGBA8> out(n);
  if (reals) {
    const float* v = static_cast<const float*>(a.data());
    for (size_t at = 0; at < n * pixels * ch; ++at)
      if (!std::isfinite(v[at])) throw InvalidArgument("images hold a value that is not finite (image " +
                                                       std::to_string(at / (pixels * ch)) + ")");
  }
  for (size_t i = 0; i < n; ++i) {
    ImageRGBA8& im = out[i];
    im.width = uint32_t(w), im.height = uint32_t(h);
    im.rgba.assign(pixels * 4, 255);
    for (size_t p = 0; p < pixels; ++p)
      for (size_t k = 0; k < ch; ++k) {
        const size_t at = (i * pixels + p) * ch + k;
        im.rgba[p * 4 + k] =
            bytes ? static_cast<const uint8_t*>(a.data())[at]
                  : uint8_t(std::lround(std::clamp(static_cast<const float*>(a.data())[at], 0.0f, 1.0f) * 255.0f));
      }
  }
  return out;
}

// Per-camera rows of a shared or per-camera argument: row i of an (N, ...) array, or the one given.
py::object rowOf(const py::handle& h, size_t i, size_t n, long sharedDims) {
  py::array a = py::array::ensure(h);
  if (a && a.ndim() == sharedDims + 1) {
    if (size_t(a.shape(0)) != n)
      throw InvalidArgument("a per-camera argument has " + std::to_string(a.shape(0)) + " rows for " + std::to_string(n) +
                            " images");
    return a[py::int_(i)];
  }
  return py::reinterpret_borrow<py::object>(h);
}

Dataset fromArrays(const py::array& images, const py::handle& poses, const py::handle& intrinsics,
                   const py::handle& distortion, const std::string& lens, const py::handle& bounds,
                   std::vector<std::string> names, const std::string& convention) {
  std::vector<ImageRGBA8> ims = imagesFrom(images);
  const size_t n = ims.size();
  auto p = floats(poses, "poses", {long(n), 4, 4}, "(N, 4, 4) with N the images' count " + std::to_string(n));
  if (convention != "opengl" && convention != "opencv")
    throw InvalidArgument("convention must be 'opengl' (camera looks down -Z, +Y up) or 'opencv' (+Z, +Y down), got '" +
                          convention + "'");
  // (4,) and (3, 3) are shared; (N, 4) and (N, 3, 3) are one per camera.
  const py::array k = py::array::ensure(intrinsics);
  const bool perCamera = k && (k.ndim() == 3 || (k.ndim() == 2 && k.shape(1) == 4));
  std::vector<Camera> cameras(n);
  for (size_t i = 0; i < n; ++i) {
    Camera& c = cameras[i];
    setPose(c, p.data() + 16 * i);
    if (convention == "opencv")
      for (int r = 0; r < 3; ++r) c.c2w[4 * r + 1] = -c.c2w[4 * r + 1], c.c2w[4 * r + 2] = -c.c2w[4 * r + 2];
    setIntrinsics(c, perCamera ? rowOf(k, i, n, k.ndim() - 1) : py::reinterpret_borrow<py::object>(intrinsics), "intrinsics");
    c.width = ims[i].width, c.height = ims[i].height;
    setLens(c, distortion.is_none() ? distortion : rowOf(distortion, i, n, 1), lens, "distortion");
  }
  std::optional<Aabb> box;
  if (!bounds.is_none()) {
    auto b = floats(bounds, "bounds", {2, 3}, "(2, 3): [min xyz, max xyz]");
    box = Aabb{{b.at(0, 0), b.at(0, 1), b.at(0, 2)}, {b.at(1, 0), b.at(1, 1), b.at(1, 2)}};
  }
  py::gil_scoped_release release;
  try {
    return Dataset::fromMemory(std::move(cameras), std::move(ims), std::move(names), box);
  } catch (const OutOfMemoryError&) {
    throw;
  } catch (const Error& e) {
    throw InvalidArgument(e.what());
  }
}

const Dataset& of(const PyDataset& d) { return *d.data; }

}  // namespace

void bindDataset(py::module_& m) {
  py::class_<PyDataset>(m, "Dataset", "Posed photos: cameras, RGBA8 images and the scene box.")
      .def_static("load", [](const std::string& path, uint32_t downscale, const std::string& split, float holdout) {
             DatasetOptions o;
             o.downscale = downscale;
             o.split = split;
             o.holdoutFraction = holdout;
             py::gil_scoped_release release;
             return PyDataset{std::make_shared<const Dataset>(aboutFile(path, [&] { return Dataset::load(path, o); }))};
           },
           py::arg("path"), py::arg("downscale") = 1, py::arg("split") = "train", py::arg("holdout") = 0.1f,
           "A scene folder or file (transforms*.json, a COLMAP model, LLFF's poses_bounds.npy); split is "
           "train, val, test or all.")
      .def_static("from_arrays", [](const py::array& images, const py::handle& poses, const py::handle& intrinsics,
                                    const py::handle& distortion, const std::string& lens, const py::handle& bounds,
                                    std::vector<std::string> names, const std::string& convention) {
             return PyDataset{std::make_shared<const Dataset>(
                 fromArrays(images, poses, intrinsics, distortion, lens, bounds, std::move(names), convention))};
           },
           py::arg("images"), py::arg("poses"), py::arg("intrinsics"), py::arg("distortion") = py::none(),
           py::arg("lens") = "opencv", py::arg("bounds") = py::none(), py::arg("names") = std::vector<std::string>{},
           py::arg("convention") = "opengl",
           "images (N, H, W, 3|4) uint8 or float32 in [0, 1], C-contiguous; poses (N, 4, 4) camera-to-world; "
           "intrinsics (4,) fx fy cx cy or (3, 3) K, shared or one per image ((N, 4), (N, 3, 3)); distortion "
           "OpenCV's (k1, k2, p1, p2[, k3[, k4, k5, k6]]) or with lens='fisheye' (k1..k4), shared or per image; "
           "bounds (2, 3) the scene box (None: from the cameras); convention 'opengl' or 'opencv' for the poses.")
      .def("__len__", [](const PyDataset& d) { return of(d).cameras.size(); })
      .def_property_readonly("cameras", [](const PyDataset& d) { return of(d).cameras; })
      .def_property_readonly("names", [](const PyDataset& d) { return of(d).names; })
      .def_property_readonly("bounds_source", [](const PyDataset& d) { return of(d).boundsSource; })
      .def_property_readonly("bounds", [](const PyDataset& d) {
        const Aabb& b = of(d).bounds;
        return toArray(std::vector<float>{b.min[0], b.min[1], b.min[2], b.max[0], b.max[1], b.max[2]}, {2, 3});
      }, "(2, 3): [min xyz, max xyz]")
      .def_property_readonly("poses", [](const PyDataset& d) {
        std::vector<float> out;
        for (const Camera& c : of(d).cameras) out.insert(out.end(), c.c2w.begin(), c.c2w.end());
        return toArray(std::move(out), {py::ssize_t(of(d).cameras.size()), 4, 4});
      }, "(N, 4, 4) float32 camera-to-world, OpenGL convention")
      .def("image", [](const PyDataset& d, size_t i) {
        if (i >= of(d).images.size()) throw py::index_error("image " + std::to_string(i) + " of " + std::to_string(of(d).images.size()));
        const ImageRGBA8& im = of(d).images[i];
        return toArray(std::vector<uint8_t>(im.rgba), {im.height, im.width, 4});
      }, py::arg("index"), "(H, W, 4) uint8 RGBA, straight alpha")
      .def("__repr__", [](const PyDataset& d) {
        return "vknerf.Dataset(" + std::to_string(of(d).cameras.size()) + " images, box from " + of(d).boundsSource + ")";
      });
}

}  // namespace vknerf::python
