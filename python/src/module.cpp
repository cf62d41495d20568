// `_vknerf`: the extension the pure-Python package vknerf/ wraps (python/vknerf/__init__.py).
#include "bindings.h"
#include "errors.h"

PYBIND11_MODULE(_vknerf, m) {
  m.doc() = "vknerf: NeRF training and rendering on Vulkan compute (the extension under the vknerf package)";
  vknerf::python::registerErrors(m);
  vknerf::python::bindContext(m);
  vknerf::python::bindCamera(m);
  vknerf::python::bindDataset(m);
  vknerf::python::bindConfig(m);
  vknerf::python::bindTrainer(m);
  vknerf::python::bindModel(m);
}
