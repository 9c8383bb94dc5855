/// \file
/// The extension module `_ricci`: exception classes and the bindings of each module of ricci.
/// The pure-Python package `ricci` on top of it checks array shapes and dtypes.

#include <exception>

#include "bindings.hpp"
#include "ricci/errors.hpp"
#include "ricci/version.hpp"

namespace ricci::python {
namespace {

/// Creates an exception class `_ricci.<name>` with the given bases (a class or a tuple).
py::handle make_exception(py::module_& m, const char* name, const py::handle& bases,
                          const char* doc) {
  // Named as the package `ricci` re-exports them.
  const std::string qualified = std::string("ricci.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (type == nullptr) throw py::error_already_set();
  m.add_object(name, py::handle(type));  // the module holds the new reference
  return type;
}

/// The exception classes, held by the module for the life of the interpreter (translators are
/// plain function pointers, so they find the classes here).
struct ExceptionClasses {
  py::handle error, invalid_input, topology_error, io_error, solver_error;
};
ExceptionClasses exception_classes;

/// An InvalidInput as a Python exception: the message with the fixes phrased as keywords
/// ('try: cones="auto", or cones="one"'), and the fixes as `exc.fixes`, a list of
/// (keyword, value) pairs.
void set_invalid_input(const py::handle& type, const InvalidInput& e) {
  py::object exc =
      py::reinterpret_borrow<py::object>(type)(message_with_fixes(e.what(), e.fixes()));
  exc.attr("fixes") = fix_pairs(e.fixes());
  PyErr_SetObject(type.ptr(), exc.ptr());
}

// By value: pybind11's ExceptionTranslator is void (*)(std::exception_ptr).
void translate_exception(std::exception_ptr p) {  // NOLINT(performance-unnecessary-value-param)
  const ExceptionClasses& c = exception_classes;
  try {
    if (p) std::rethrow_exception(p);
  } catch (const TopologyError& e) {
    set_invalid_input(c.topology_error, e);
  } catch (const InvalidInput& e) {
    set_invalid_input(c.invalid_input, e);
  } catch (const IoError& e) {
    PyErr_SetString(c.io_error.ptr(), e.what());
  } catch (const SolverError& e) {
    PyErr_SetString(c.solver_error.ptr(), e.what());
  } catch (const Error& e) {
    PyErr_SetString(c.error.ptr(), e.what());
  }
}

}  // namespace
}  // namespace ricci::python

PYBIND11_MODULE(_ricci, m) {
  namespace py = pybind11;
  using namespace ricci::python;
  m.doc() =
      "ricci: discrete surface Ricci flow and conformal parameterization (C++ bindings; "
      "use the package `ricci`, which checks array shapes).";
  // The C++ library's version (CMake's project version), re-exported as ricci.__version__.
  m.attr("__version__") = ricci::version();

  // The hierarchy of ricci/errors.hpp, each class also deriving from the built-in exception a
  // Python caller would expect (so `except ValueError` catches bad input).
  const py::handle error = make_exception(m, "Error", PyExc_Exception,
                                          "Base of every exception ricci raises on purpose.");
  const py::handle invalid_input = make_exception(
      m, "InvalidInput", py::make_tuple(error, py::handle(PyExc_ValueError)),
      "The caller's data breaks a precondition (non-finite coordinates, a target that violates "
      "Gauss-Bonnet, an option out of range).");
  const py::handle topology_error = make_exception(
      m, "TopologyError", invalid_input, "The mesh is not an oriented manifold triangle mesh.");
  const py::handle io_error = make_exception(
      m, "IoError", py::make_tuple(error, py::handle(PyExc_OSError)),
      "Reading or writing a file failed (missing, empty, truncated or malformed file).");
  const py::handle solver_error = make_exception(
      m, "SolverError", py::make_tuple(error, py::handle(PyExc_RuntimeError)),
      "A numerical breakdown the solver cannot step around (factorisation failed, NaN).");

  exception_classes = {error, invalid_input, topology_error, io_error, solver_error};
  py::register_exception_translator(&translate_exception);

  bind_mesh(m);
  bind_flow(m);
  bind_param(m);
  bind_hyperbolic_param(m);
  bind_sphere(m);
  bind_match(m);
  bind_spline(m);
  bind_batch(m);
}
