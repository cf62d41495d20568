#pragma once
// One function per part of the API, each in its own file, called by module.cpp in this order
// (a later part's signatures name the earlier parts' classes).
#include <pybind11/pybind11.h>

namespace vknerf::python {

void bindContext(pybind11::module_& m);
void bindCamera(pybind11::module_& m);
void bindDataset(pybind11::module_& m);
void bindConfig(pybind11::module_& m);
void bindTrainer(pybind11::module_& m);
void bindModel(pybind11::module_& m);

}  // namespace vknerf::python
