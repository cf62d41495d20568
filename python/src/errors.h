#pragma once
// vknerf's errors as Python exceptions: every vknerf::Error is a vknerf.Error with the same one-line
// message; where the cause is a bad argument, a file or memory, a subclass that is also Python's
// ValueError, OSError or MemoryError, so that `except ValueError` works as a Python user expects.
#include <pybind11/pybind11.h>

#include <stdexcept>
#include <string>

namespace vknerf::python {

void registerErrors(pybind11::module_& m);

// Thrown by the bindings for what the caller passed (a shape, a dtype, a field's value).
struct InvalidArgument : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// A vknerf::Error about a file the caller named: turned into vknerf.FileError.
struct FileProblem : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Runs `f`, turning a vknerf::Error into FileProblem when `path` does not name a readable file or
// folder: the error is then about the file, not its contents.
template <class F>
auto aboutFile(const std::string& path, F&& f) -> decltype(f());
bool pathIsMissing(const std::string& path);

}  // namespace vknerf::python

#include "vknerf/error.h"

template <class F>
auto vknerf::python::aboutFile(const std::string& path, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const OutOfMemoryError&) {
    throw;
  } catch (const Error& e) {
    if (pathIsMissing(path)) throw FileProblem(e.what());
    throw;
  }
}
