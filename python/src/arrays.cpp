#include "arrays.h"

#include "errors.h"

namespace py = pybind11;

namespace vknerf::python {

std::string shapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

void checkContiguous(const py::array& a, const std::string& name) {
  if (!(a.flags() & py::array::c_style))
    throw InvalidArgument(name + " must be C-contiguous (numpy.ascontiguousarray makes it so)");
}

void checkShape(const py::array& a, const std::string& name, const std::vector<long>& dims, const std::string& expected) {
  bool ok = a.ndim() == py::ssize_t(dims.size());
  for (size_t i = 0; ok && i < dims.size(); ++i) ok = dims[i] < 0 || a.shape(py::ssize_t(i)) == dims[i];
  if (!ok) throw InvalidArgument(name + " must have shape " + expected + ", got " + shapeText(a));
  checkContiguous(a, name);
}

py::array_t<float, py::array::c_style> floats(const py::handle& h, const std::string& name, const std::vector<long>& dims,
                                              const std::string& expected) {
  py::array a = py::array::ensure(h);
  if (!a) throw InvalidArgument(name + " must be an array of shape " + expected);
  if (a.dtype().kind() != 'f' && a.dtype().kind() != 'i' && a.dtype().kind() != 'u')
    throw InvalidArgument(name + " must hold numbers, got dtype " + std::string(py::str(a.dtype())));
  checkShape(a, name, dims, expected);
  if (a.dtype().kind() == 'f' && a.itemsize() == 4) return py::reinterpret_borrow<py::array_t<float, py::array::c_style>>(a);
  // numpy's own conversion: the copy is small (a pose, a few intrinsics).
  return py::reinterpret_steal<py::array_t<float, py::array::c_style>>(
      a.attr("astype")("float32").release());
}

}  // namespace vknerf::python
