// SPDX-License-Identifier: MIT
#include "errors.h"

#include <map>

namespace py = pybind11;

namespace dualgraph::python {
namespace {

// The classes, created once at import (module-lifetime objects; leaked on purpose so no destructor runs
// after the interpreter is finalised).
std::map<StatusCode, py::object>& classes() {
  static auto* by_code = new std::map<StatusCode, py::object>();
  return *by_code;
}
py::object& optimizationErrorClass() {
  static auto* cls = new py::object();
  return *cls;
}

py::object makeClass(py::module_& module, const char* name, py::tuple bases, const char* doc) {
  py::dict namespace_;
  namespace_["__doc__"] = doc;
  namespace_["__module__"] = module.attr("__name__");
  py::object cls = py::module_::import("builtins").attr("type")(name, bases, namespace_);
  module.attr(name) = cls;
  return cls;
}

[[noreturn]] void raiseWith(const py::object& cls, const std::string& code, const std::string& message) {
  py::object error = cls(message);
  error.attr("code") = code;
  PyErr_SetObject(cls.ptr(), error.ptr());
  throw py::error_already_set();
}

}  // namespace

void registerExceptions(py::module_& module) {
  py::object base = makeClass(module, "Error", py::make_tuple(py::handle(PyExc_RuntimeError)),
                              "Base of every error the library reports; str(e) is its message, e.code the status code.");
  auto sub = [&](StatusCode code, const char* name, py::handle builtin, const char* doc) {
    py::tuple bases = builtin ? py::make_tuple(base, builtin) : py::make_tuple(base);
    classes()[code] = makeClass(module, name, bases, doc);
  };
  sub(StatusCode::kInvalidArgument, "InvalidArgumentError", PyExc_ValueError,
      "A value out of its domain: NaN, wrong array shape, unknown or duplicate id in a batch, bad parameter.");
  sub(StatusCode::kParseError, "ParseError", PyExc_ValueError, "A file that could not be read (file:line: field).");
  sub(StatusCode::kNotFound, "NotFoundError", PyExc_LookupError, "An id, tag or file that does not exist.");
  sub(StatusCode::kAlreadyExists, "AlreadyExistsError", PyExc_ValueError, "A duplicate id or tag.");
  sub(StatusCode::kIoError, "IoError", PyExc_OSError, "The operating system refused a read or write.");
  sub(StatusCode::kNotPositiveDefinite, "NotPositiveDefiniteError", PyExc_ArithmeticError,
      "A matrix that must be symmetric positive definite is not (e.g. no gauge fixed).");
  sub(StatusCode::kNumericalError, "NumericalError", PyExc_ArithmeticError, "NaN/Inf produced during computation.");
  sub(StatusCode::kFailedPrecondition, "FailedPreconditionError", py::handle(),
      "The call is not valid in the object's current state.");
  optimizationErrorClass() = makeClass(module, "OptimizationError", py::make_tuple(base),
                                       "An optimisation ended without a usable result; e.code is the termination.");
}

void raise(const Status& status) {
  auto found = classes().find(status.code());
  if (found == classes().end()) {  // kOk is a caller's bug; keep Python alive all the same
    PyErr_SetString(PyExc_RuntimeError, ("dualgraph: " + status.toString()).c_str());
    throw py::error_already_set();
  }
  raiseWith(found->second, statusCodeName(status.code()), status.message());
}

void raiseOptimizationError(const std::string& termination, const std::string& message) {
  raiseWith(optimizationErrorClass(), termination, message);
}

void raiseInvalid(const std::string& message) { raise(Status(StatusCode::kInvalidArgument, message)); }

}  // namespace dualgraph::python
