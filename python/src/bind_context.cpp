// vknerf.Context and vknerf.devices().
#include <pybind11/stl.h>

#include <optional>

#include "bindings.h"
#include "holders.h"

namespace py = pybind11;

namespace vknerf::python {

namespace {

const char* typeName(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    default: return "other";
  }
}

}  // namespace

void bindContext(py::module_& m) {
  m.def("devices", [] {
    py::list out;
    for (const DeviceInfo& d : Context::listDevices()) {
      py::dict info;
      info["index"] = d.index;
      info["name"] = d.name;
      info["type"] = typeName(d.type);
      info["api_version"] = py::make_tuple(VK_API_VERSION_MAJOR(d.apiVersion), VK_API_VERSION_MINOR(d.apiVersion));
      info["usable"] = d.usable;
      out.append(info);
    }
    return out;
  }, "The Vulkan devices: a dict each (index, name, type, api_version, usable).");

  py::class_<PyContext>(m, "Context", "A Vulkan compute context on one device.")
      .def(py::init([](std::optional<std::string> device, bool validation, std::optional<std::string> profile) {
             ContextOptions o;
             o.device = device.value_or("");
             o.validation = validation;
             o.profile = profile.value_or("");
             py::gil_scoped_release release;  // creating the device takes a while
             return PyContext{Context::create(o)};
           }),
           py::arg("device") = py::none(), py::arg("validation") = false, py::arg("profile") = py::none(),
           "device: an index into devices() or a case-insensitive part of its name (None: VKNERF_DEVICE, else "
           "the best); validation: run under VK_LAYER_KHRONOS_validation and count its messages "
           "(VKNERF_VALIDATION=1 turns it on too); profile: behave like another class of device.")
      .def_property_readonly("name", [](const PyContext& c) { return c.ctx->deviceName(); })
      .def_property_readonly("is_cpu", [](const PyContext& c) { return c.ctx->isCpu(); })
      .def_property_readonly("profile", [](const PyContext& c) { return c.ctx->profile(); })
      .def_property_readonly("validation_enabled", [](const PyContext& c) { return c.ctx->validationEnabled(); })
      .def_property_readonly("validation_messages", [](const PyContext& c) { return c.ctx->validationMessages(); },
                             "Validation-layer warnings and errors reported since creation.")
      .def("capabilities", [](const PyContext& c) { return c.ctx->capabilities(); })
      .def("describe", [](const PyContext& c) { return c.ctx->describe(); })
      .def("__repr__", [](const PyContext& c) { return "vknerf.Context(" + c.ctx->describe() + ")"; });
}

}  // namespace vknerf::python
