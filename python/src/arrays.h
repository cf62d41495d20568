#pragma once
// NumPy arrays in and out of the bindings. In: the array checked for its dtype, shape and layout,
// each failure an InvalidArgument naming the argument and what it was; out: a std::vector handed
// to NumPy without a copy (the array owns it).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <vector>

namespace vknerf::python {

// The shape as "(2, 3, 4)", for messages.
std::string shapeText(const pybind11::array& a);

// `a` must be C-contiguous with `ndim` dimensions; `dims[i]` of -1 accepts any size there.
void checkShape(const pybind11::array& a, const std::string& name, const std::vector<long>& dims,
                const std::string& expected);
void checkContiguous(const pybind11::array& a, const std::string& name);

// A float array of any float dtype as float32, checked for `dims` (a copy only for another dtype:
// poses and intrinsics are small).
pybind11::array_t<float, pybind11::array::c_style> floats(const pybind11::handle& h, const std::string& name,
                                                           const std::vector<long>& dims, const std::string& expected);

// `values` as an array of `shape`, owning the vector.
template <class T>
pybind11::array_t<T> toArray(std::vector<T>&& values, std::vector<pybind11::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(values));
  pybind11::capsule free(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return pybind11::array_t<T>(shape, owned->data(), free);
}

}  // namespace vknerf::python
