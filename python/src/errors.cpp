#include "errors.h"

#include <filesystem>

namespace py = pybind11;

namespace vknerf::python {

namespace {

// A new exception class `vknerf.<name>` deriving from every class in `bases`.
// The reference returned is kept for the life of the process: the translator below uses it, and
// exception types are never unloaded.
PyObject* newException(py::module_& m, const char* name, py::tuple bases, const char* doc) {
  const std::string qualified = std::string("vknerf.") + name;
  PyObject* cls = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (!cls) throw py::error_already_set();
  m.attr(name) = py::handle(cls);
  return cls;
}

}  // namespace

bool pathIsMissing(const std::string& path) {
  std::error_code ec;
  return path.empty() || !std::filesystem::exists(path, ec);
}

void registerErrors(py::module_& m) {
  static PyObject *error, *invalid, *file, *memory;
  error = newException(m, "Error", py::make_tuple(py::handle(PyExc_RuntimeError)),
                       "Every failure vknerf reports: one line naming what failed.");
  invalid = newException(m, "InvalidArgumentError", py::make_tuple(py::handle(error), py::handle(PyExc_ValueError)),
                         "A bad argument: an array's shape or dtype, a configuration field's value.");
  file = newException(m, "FileError", py::make_tuple(py::handle(error), py::handle(PyExc_OSError)),
                      "A file or folder that does not exist or cannot be read or written.");
  memory = newException(m, "OutOfMemoryError", py::make_tuple(py::handle(error), py::handle(PyExc_MemoryError)),
                        "The device or the host ran out of memory for what was asked (ask for less).");
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InvalidArgument& e) {
      PyErr_SetString(invalid, e.what());
    } catch (const FileProblem& e) {
      PyErr_SetString(file, e.what());
    } catch (const OutOfMemoryError& e) {
      PyErr_SetString(memory, e.what());
    } catch (const Error& e) {
      PyErr_SetString(error, e.what());
    }
  });
}

}  // namespace vknerf::python
