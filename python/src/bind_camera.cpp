// vknerf.Camera: pose, intrinsics, image size and lens.
#include "arrays.h"
#include "bindings.h"
#include "camera_arrays.h"
#include "errors.h"

namespace py = pybind11;

namespace vknerf::python {

void bindCamera(py::module_& m) {
  py::class_<Camera>(m, "Camera",
                     "A posed camera: camera-to-world pose (4x4, OpenGL convention: looking down -Z, +Y up), "
                     "intrinsics in pixels, image size, optional OpenCV lens distortion.")
      .def(py::init([](const py::handle& pose, const py::handle& intrinsics, uint32_t width, uint32_t height,
                       const py::handle& distortion, const std::string& lens) {
             if (width == 0 || height == 0) throw InvalidArgument("width and height must be positive");
             Camera c;
             setPose(c, floats(pose, "pose", {4, 4}, "(4, 4)").data());
             setIntrinsics(c, intrinsics, "intrinsics");
             c.width = width, c.height = height;
             setLens(c, distortion, lens, "distortion");
             try {
               checkLens(c, "camera");
             } catch (const Error& e) {
               throw InvalidArgument(e.what());
             }
             return c;
           }),
           py::arg("pose"), py::arg("intrinsics"), py::arg("width"), py::arg("height"),
           py::arg("distortion") = py::none(), py::arg("lens") = "opencv")
      .def_property("pose", &poseArray,
                    [](Camera& c, const py::handle& p) { setPose(c, floats(p, "pose", {4, 4}, "(4, 4)").data()); })
      .def_readwrite("fx", &Camera::fx)
      .def_readwrite("fy", &Camera::fy)
      .def_readwrite("cx", &Camera::cx)
      .def_readwrite("cy", &Camera::cy)
      .def_readwrite("width", &Camera::width)
      .def_readwrite("height", &Camera::height)
      .def_property_readonly("intrinsics", [](const Camera& c) {
        return toArray(std::vector<float>{c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1}, {3, 3});
      }, "K, 3x3")
      .def_property_readonly("lens", [](const Camera& c) { return lensName(c.lens.model); })
      .def_property_readonly("distortion", [](const Camera& c) { return distortionArray(c.lens); },
                             "OpenCV's order: (k1, k2, p1, p2, k3, k4, k5, k6); fisheye (k1, k2, k3, k4)")
      .def("__repr__", [](const Camera& c) {
        return "vknerf.Camera(" + std::to_string(c.width) + "x" + std::to_string(c.height) + ", fx=" +
               std::to_string(c.fx) + ", lens=" + lensName(c.lens.model) + ")";
      });
}

}  // namespace vknerf::python
