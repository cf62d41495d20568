// vknerf.Model: loaded from a checkpoint or taken from a trainer; views rendered into NumPy
// arrays with the GIL released, meshes, and the held-out metrics of `vknerf eval`.
#include <pybind11/stl.h>

#include <optional>

#include "arrays.h"
#include "bindings.h"
#include "camera_arrays.h"
#include "errors.h"
#include "holders.h"
#include "lib/metrics.h"
#include "vknerf/image_io.h"

namespace py = pybind11;

namespace vknerf::python {

namespace {

py::dict renderLocked(const PyModel& m, const Camera& camera) {
  RenderedImage img;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(*m.busy);
    img = m.model->render(camera);
  }
  const py::ssize_t h = img.height, w = img.width;
  py::dict out;
  out["rgb"] = toArray(std::move(img.rgb), {h, w, 3});
  out["depth"] = toArray(std::move(img.depth), {h, w});
  out["opacity"] = toArray(std::move(img.opacity), {h, w});
  out["samples"] = img.samples;  // field samples the render shaded
  py::dict kernels;  // Model.load(profile=True): device ms per kernel of this render
  for (const auto& [name, ms] : img.kernelMs) kernels[py::str(name)] = ms;
  out["kernel_ms"] = kernels;
  return out;
}

Camera cameraFrom(const py::object& camera, const py::object& pose, const py::object& intrinsics,
                  std::optional<uint32_t> width, std::optional<uint32_t> height, const py::object& distortion,
                  const std::string& lens) {
  if (!camera.is_none()) {
    if (!pose.is_none() || !intrinsics.is_none())
      throw InvalidArgument("render takes a camera or a pose with intrinsics, not both");
    Camera c = camera.cast<Camera>();
    if (width || height) {
      // Another size of the same view: the intrinsics scale with it.
      const uint32_t w = width.value_or(c.width), h = height.value_or(c.height);
      if (w == 0 || h == 0) throw InvalidArgument("width and height must be positive");
      const float sx = float(w) / float(c.width), sy = float(h) / float(c.height);
      c.fx *= sx, c.cx *= sx, c.fy *= sy, c.cy *= sy;
      c.width = w, c.height = h;
    }
    return c;
  }
  if (pose.is_none() || intrinsics.is_none() || !width || !height)
    throw InvalidArgument("render needs a camera, or pose, intrinsics, width and height");
  if (*width == 0 || *height == 0) throw InvalidArgument("width and height must be positive");
  Camera c;
  setPose(c, floats(pose, "pose", {4, 4}, "(4, 4)").data());
  setIntrinsics(c, intrinsics, "intrinsics");
  c.width = *width, c.height = *height;
  setLens(c, distortion, lens, "distortion");
  try {
    checkLens(c, "camera");
  } catch (const Error& e) {
    throw InvalidArgument(e.what());
  }
  return c;
}

// Each view rendered and compared with its photo composited over the model's background, as
// `vknerf eval` does (tools/cli/cmd_eval.cpp), with the same metrics (tools/cli/lib/metrics.h).
py::dict evaluate(const PyModel& m, const PyDataset& d) {
  std::vector<double> psnr, ssim;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(*m.busy);
    for (size_t i = 0; i < d.data->cameras.size(); ++i) {
      const RenderedImage img = m.model->render(d.data->cameras[i]);
      const auto truth = compositeOver(d.data->images[i], m.model->config().background);
      psnr.push_back(nerf::psnr(img.rgb, truth));
      ssim.push_back(nerf::ssim(img.rgb, truth, img.width, img.height));
    }
  }
  double meanPsnr = 0, meanSsim = 0;
  for (size_t i = 0; i < psnr.size(); ++i) meanPsnr += psnr[i] / double(psnr.size()), meanSsim += ssim[i] / double(psnr.size());
  py::dict out;
  out["names"] = d.data->names;
  out["psnr"] = toArray(std::move(psnr), {py::ssize_t(d.data->cameras.size())});
  out["ssim"] = toArray(std::move(ssim), {py::ssize_t(d.data->cameras.size())});
  out["mean_psnr"] = meanPsnr;
  out["mean_ssim"] = meanSsim;
  return out;
}

}  // namespace

void bindModel(py::module_& m) {
  py::class_<PyModel>(m, "Model", "A trained field: renders views, extracts meshes.")
      .def_static("load", [](const std::string& path, const PyContext& ctx, uint32_t marchSteps, uint32_t coarse,
                             uint32_t fine, std::optional<uint32_t> appearance, bool profile) {
             RenderSettings s;
             s.marchSteps = marchSteps, s.coarseSamples = coarse, s.fineSamples = fine, s.appearancePhoto = appearance;
             s.profile = profile;
             py::gil_scoped_release release;
             auto model = std::make_shared<const Model>(aboutFile(path, [&] { return Model::load(ctx.ctx, path, s); }));
             return PyModel{ctx.ctx, model, std::make_shared<std::mutex>()};
           },
           py::arg("path"), py::arg("context"), py::arg("march_steps") = 0, py::arg("coarse_samples") = 0,
           py::arg("fine_samples") = 0, py::arg("appearance") = py::none(), py::arg("profile") = false)
      .def_static("of_trainer", [](const PyTrainer& t) {
             // The trainer's live model: it keeps the trainer's state (and so the trainer) alive.
             std::shared_ptr<const Model> model(t.state, &t.state->trainer->model());
             return PyModel{t.state->ctx, model, std::shared_ptr<std::mutex>(t.state, &t.state->busy)};
           }, py::arg("trainer"))
      .def("render", [](const PyModel& self, const py::object& camera, const py::object& pose, const py::object& intrinsics,
                        std::optional<uint32_t> width, std::optional<uint32_t> height, const py::object& distortion,
                        const std::string& lens) {
             return renderLocked(self, cameraFrom(camera, pose, intrinsics, width, height, distortion, lens));
           },
           py::arg("camera") = py::none(), py::kw_only(), py::arg("pose") = py::none(), py::arg("intrinsics") = py::none(),
           py::arg("width") = py::none(), py::arg("height") = py::none(), py::arg("distortion") = py::none(),
           py::arg("lens") = "opencv",
           "A view as a dict of arrays: rgb (H, W, 3), depth (H, W), opacity (H, W), float32; samples; kernel_ms.")
      .def("mesh", [](const PyModel& self, uint32_t resolution, float threshold, bool occupiedOnly) {
             Mesh mesh;
             {
               MeshSettings s;
               s.resolution = resolution, s.threshold = threshold, s.occupiedOnly = occupiedOnly;
               py::gil_scoped_release release;
               std::lock_guard<std::mutex> lock(*self.busy);
               mesh = self.model->extractMesh(s);
             }
             const py::ssize_t v = mesh.positions.size() / 3, f = mesh.triangles.size() / 3;
             return py::make_tuple(toArray(std::move(mesh.positions), {v, 3}), toArray(std::move(mesh.triangles), {f, 3}),
                                   toArray(std::move(mesh.colors), {v, 3}));
           },
           py::arg("resolution") = 256, py::arg("threshold") = MeshSettings::kDefaultThreshold, py::arg("occupied_only") = true,
           "(vertices (V, 3) float32, faces (F, 3) uint32, colours (V, 3) uint8) where the density crosses threshold.")
      .def_property_readonly("config", [](const PyModel& self) { return self.model->config(); })
      .def_property_readonly("bounds", [](const PyModel& self) {
        const Aabb& b = self.model->bounds();
        return toArray(std::vector<float>{b.min[0], b.min[1], b.min[2], b.max[0], b.max[1], b.max[2]}, {2, 3});
      })
      .def("training_cameras", [](const PyModel& self) {
        std::vector<Camera> out;
        for (const TrainedCamera& c : self.model->trainingCameras()) out.push_back(c.camera);
        return out;
      });
  m.def("_evaluate", &evaluate, py::arg("model"), py::arg("dataset"));
}

}  // namespace vknerf::python
