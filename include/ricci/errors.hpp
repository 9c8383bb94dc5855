#pragma once
/// \file
/// The exception hierarchy of ricci. Every throw names the function that detected the problem and
/// the offending element (file and line, vertex, edge or face index) in its message.
/// Non-convergence is never an exception: solvers report it in their result structs.

#include <initializer_list>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ricci {

/// Base of every exception ricci throws on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An option setting that avoids an InvalidInput: the option's name, the same for the command
/// line's flag and Python's keyword (`target`, `cones`, `boundary`, `scheme`, `geometry`), and the
/// value to give it ("natural", "auto", "disk", "vertex-scaling", "euclidean"). The command line
/// prints it as `--target natural`, Python as `target="natural"`; in C++ it names the field of
/// the options struct the message mentions. The value "true" turns a flag on (`--repair`,
/// `repair=True`); "false" turns one off and an empty value unsets an option (`drop --strict`,
/// `drop --cones`; Python `cones=None`).
///
/// The library's messages never name a flag of one front end: they name the option field
/// ("FlowOptions::flips = Delaunay") and carry the fix as an OptionFix (InvalidInput::fixes for
/// refusals, FlowResult::fixes for a flow that stopped short), which apps/ricci/fixes.hpp and
/// python/src/bindings.hpp phrase.
struct OptionFix {
  std::string option;
  std::string value;
  bool operator==(const OptionFix&) const = default;
};

/// Fixes from (option, value) pairs of literals: `fixes_of({{"cones", "auto"}})`. (A function,
/// not a braced list of strings in the throw expression, where GCC 12 warns of maybe-uninitialized
/// temporaries.)
std::vector<OptionFix> fixes_of(std::initializer_list<std::pair<const char*, const char*>> pairs);

/// The caller's data breaks a precondition: non-finite coordinates, a target that violates
/// Gauss-Bonnet, an option out of range, a zero-area face. When another option value would have
/// worked, fixes() says which (the front ends print them: every refusal names the option that
/// works).
class InvalidInput : public Error {
 public:
  using Error::Error;
  InvalidInput(const std::string& message, std::vector<OptionFix> fixes)
      : Error(message), fixes_(std::move(fixes)) {}
  /// Option settings that avoid this error, best first; empty when none is known.
  const std::vector<OptionFix>& fixes() const { return fixes_; }

 private:
  std::vector<OptionFix> fixes_;
};

/// The mesh is not an oriented manifold triangle mesh (non-manifold edge or vertex,
/// inconsistent orientation, non-orientable surface).
class TopologyError : public InvalidInput {
 public:
  using InvalidInput::InvalidInput;
};

/// Reading or writing a file failed: missing, empty, truncated or malformed file, unknown format.
class IoError : public Error {
 public:
  using Error::Error;
};

/// A numerical breakdown the solver cannot step around (factorisation failed, NaN appeared).
class SolverError : public Error {
 public:
  using Error::Error;
};

}  // namespace ricci
