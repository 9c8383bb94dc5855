#pragma once
/// \file
/// Shared helpers of the pybind11 module `_ricci`: a binder for plain options and result structs
/// (fields by name, keyword-argument constructor, repr, copy), enum fields that also take their
/// ricci names as strings, per-element flags as numpy bool arrays, and the progress callback.

#include <pybind11/complex.h>
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ricci/enum_names.hpp"
#include "ricci/flow/ricci_flow.hpp"

namespace ricci::python {

namespace py = pybind11;

void bind_mesh(py::module_& m);
void bind_flow(py::module_& m);
void bind_param(py::module_& m);
void bind_hyperbolic_param(py::module_& m);
void bind_sphere(py::module_& m);
void bind_match(py::module_& m);
void bind_spline(py::module_& m);
void bind_batch(py::module_& m);

/// Option fixes (ricci/errors.hpp) phrased as Python keywords: 'try: cones="auto", or
/// flips="delaunay"' (numbers unquoted, an empty value as None); empty when there are none. The one
/// place Python phrases the library's OptionFix, for exceptions and for results' messages alike.
inline std::string phrase_fixes(const std::vector<OptionFix>& fixes) {
  std::string out;
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    const OptionFix& fix = fixes[i];
    const bool number =
        !fix.value.empty() && fix.value.find_first_not_of("0123456789") == std::string::npos;
    const bool boolean = fix.value == "true" || fix.value == "false";
    out += (i == 0 ? "try: " : ", or ") + fix.option + "=" +
           (fix.value.empty() ? std::string("None")  // the option unset
            : boolean         ? (fix.value == "true" ? "True" : "False")
            : number          ? fix.value
                              : "\"" + fix.value + "\"");
  }
  return out;
}

/// A result's message with its fixes phrased on a line of their own.
inline std::string message_with_fixes(const std::string& message,
                                      const std::vector<OptionFix>& fixes) {
  return fixes.empty() ? message : message + "\n" + phrase_fixes(fixes);
}

/// The fixes as (keyword, value) pairs.
inline py::list fix_pairs(const std::vector<OptionFix>& fixes) {
  py::list out;
  for (const OptionFix& fix : fixes) out.append(py::make_tuple(fix.option, fix.value));
  return out;
}

/// Gives a bound enum the names ricci prints and parses, from its EnumNames table, as the class
/// attribute `names` (a tuple, in the order of the table): what the pure-Python layer checks
/// strings against instead of a copy of the list.
template <class E>
void bind_enum_names(py::enum_<E>& e) {
  py::list names;
  for (const std::string& name : enum_primary_names<E>()) names.append(name);
  e.attr("names") = py::tuple(names);
}

/// Short repr of a field value: arrays by shape, lists of arrays and long lists by length, tuples
/// item by item.
inline std::string field_repr(const py::handle& value) {
  if (py::isinstance<py::tuple>(value)) {
    std::string out = "(";
    for (std::size_t i = 0; i < py::len(value); ++i) {
      out += (i ? ", " : "") + field_repr(value[py::int_(i)]);
    }
    return out + (py::len(value) == 1 ? ",)" : ")");
  }
  if (py::isinstance<py::array>(value)) {
    const auto shape = py::str(value.attr("shape"));
    return "array(shape=" + std::string(shape) +
           ", dtype=" + std::string(py::str(value.attr("dtype"))) + ")";
  }
  if (py::isinstance<py::list>(value) && py::len(value) > 0 &&
      py::isinstance<py::array>(value[py::int_(0)])) {
    return "[" + std::to_string(py::len(value)) + " arrays]";
  }
  if (py::isinstance<py::list>(value) && py::len(value) > 8) {
    return "[... " + std::to_string(py::len(value)) + " items]";
  }
  return std::string(py::repr(value));
}

/// A py::class_ for a plain struct that remembers the names of its fields, so that the class takes
/// them as keyword arguments (`FlowOptions(tolerance=1e-8)`) and shows them in its repr. A struct
/// derived from another bound one names that one as Base: it inherits the base's fields.
template <class T, class... Base>
class StructBinding {
 public:
  StructBinding(py::handle scope, const char* name, const char* doc)
      : cls_(scope, name, doc),
        name_(name),
        fields_(std::make_shared<std::vector<std::string>>()) {}

  /// A class derived from the `bases`' classes: their fields first, in the order of the bases.
  template <class... B>
  StructBinding(py::handle scope, const char* name, const char* doc,
                const StructBinding<B>&... bases)
      : cls_(scope, name, doc), name_(name), fields_(std::make_shared<std::vector<std::string>>()) {
    (fields_->insert(fields_->end(), bases.field_names().begin(), bases.field_names().end()), ...);
  }

  const std::vector<std::string>& field_names() const { return *fields_; }

  /// A field Python may read and assign.
  template <class D>
  StructBinding& field(const char* name, D T::*member, const char* doc) {
    cls_.def_readwrite(name, member, doc);
    fields_->push_back(name);
    return *this;
  }

  /// A field Python only reads (results).
  template <class D>
  StructBinding& readonly(const char* name, D T::*member, const char* doc) {
    cls_.def_readonly(name, member, doc);
    fields_->push_back(name);
    return *this;
  }

  /// An enum field that also accepts a string, converted by `parse` (which throws InvalidInput
  /// listing the valid names).
  template <class E>
  StructBinding& enum_field(const char* name, E T::*member, E (*parse)(const std::string&),
                            const char* doc) {
    cls_.def_property(
        name, [member](const T& self) { return self.*member; },
        [member, parse](T& self, const py::object& value) {
          self.*member =
              py::isinstance<py::str>(value) ? parse(value.cast<std::string>()) : value.cast<E>();
        },
        doc);
    fields_->push_back(name);
    return *this;
  }

  /// A field with its own getter and setter (e.g. a callback held as a Python callable).
  template <class Getter, class Setter>
  StructBinding& property(const char* name, Getter&& get, Setter&& set, const char* doc) {
    cls_.def_property(name, std::forward<Getter>(get), std::forward<Setter>(set), doc);
    fields_->push_back(name);
    return *this;
  }

  /// A computed read-only field (a convenience view of the struct's own fields).
  template <class Getter>
  StructBinding& computed(const char* name, Getter&& get, const char* doc) {
    cls_.def_property_readonly(name, std::forward<Getter>(get), doc);
    fields_->push_back(name);
    return *this;
  }

  /// A per-element flag vector (std::vector<char>) read as a numpy bool array.
  StructBinding& flags(const char* name, std::vector<char> T::*member, const char* doc) {
    cls_.def_property_readonly(
        name,
        [member](const T& self) {
          const std::vector<char>& v = self.*member;
          py::array_t<bool> out(static_cast<py::ssize_t>(v.size()));
          auto data = out.mutable_unchecked<1>();
          for (py::ssize_t i = 0; i < static_cast<py::ssize_t>(v.size()); ++i) data(i) = v[i] != 0;
          return out;
        },
        doc);
    fields_->push_back(name);
    return *this;
  }

  /// Options structs: a constructor taking any of the fields as keyword arguments, and copies.
  StructBinding& keyword_constructor() {
    const auto fields = fields_;
    const std::string type_name = name_;
    cls_.def(py::init([fields, type_name](const py::kwargs& kwargs) {
               py::object self = py::cast(T{});
               for (const auto& item : kwargs) {
                 const auto key = item.first.cast<std::string>();
                 if (std::find(fields->begin(), fields->end(), key) == fields->end()) {
                   std::string names;
                   for (const std::string& f : *fields) names += (names.empty() ? "" : ", ") + f;
                   throw py::type_error(type_name + ": unknown field '" + key +
                                        "'; its fields are " + names);
                 }
                 py::setattr(self, item.first, item.second);
               }
               return self.cast<T>();
             }),
             ("A " + type_name +
              " with its defaults, changed by keyword arguments named as its "
              "fields.")
                 .c_str());
    cls_.def("__copy__", [](const T& self) { return T(self); });
    cls_.def("__deepcopy__", [](const T& self, const py::dict&) { return T(self); });
    return *this;
  }

  /// Defines __repr__ over the fields bound so far.
  StructBinding& repr() {
    const auto fields = fields_;
    const std::string type_name = name_;
    cls_.def("__repr__", [fields, type_name](const py::object& self) {
      std::string out = type_name + "(";
      for (std::size_t i = 0; i < fields->size(); ++i) {
        out += (i ? ", " : "") + (*fields)[i] + "=" + field_repr(self.attr((*fields)[i].c_str()));
      }
      return out + ")";
    });
    return *this;
  }

  py::class_<T, Base...>& cls() { return cls_; }

 private:
  py::class_<T, Base...> cls_;
  std::string name_;
  std::shared_ptr<std::vector<std::string>> fields_;
};

/// The progress callback as a Python callable: called holding the GIL; returning False stops the
/// flow, anything else (None included) lets it go on. The Python object is held through a
/// shared_ptr whose deleter takes the GIL, so that copies of the options made while the GIL is
/// released never touch Python reference counts.
struct PythonProgress {
  std::shared_ptr<py::object> callable;

  bool operator()(const IterationRecord& record) const {
    py::gil_scoped_acquire gil;
    const py::object answer = (*callable)(record);
    return answer.is_none() || answer.cast<bool>();
  }
};

/// Wraps a Python callable (or None) as a FlowProgress.
inline FlowProgress make_progress(const py::object& callable) {
  if (callable.is_none()) return {};
  if (!PyCallable_Check(callable.ptr())) {
    throw py::type_error("progress must be a callable taking an IterationRecord, or None");
  }
  auto held = std::shared_ptr<py::object>(new py::object(callable), [](py::object* p) {
    py::gil_scoped_acquire gil;
    delete p;
  });
  return PythonProgress{std::move(held)};
}

/// The Python callable behind a FlowProgress, or None.
inline py::object progress_callable(const FlowProgress& progress) {
  if (const auto* p = progress.template target<PythonProgress>()) return *p->callable;
  return py::none();
}

/// Runs `work` without the GIL. The options' progress callback is wrapped so that it also checks
/// for signals (Ctrl-C raises KeyboardInterrupt out of the flow) after every iteration.
template <class Result, class Work>
Result run_without_gil(FlowOptions& flow, Work&& work) {
  flow.progress = [user = flow.progress](const IterationRecord& record) {
    {
      py::gil_scoped_acquire gil;
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    }
    return user ? user(record) : true;
  };
  py::gil_scoped_release no_gil;
  return work();
}

}  // namespace ricci::python
