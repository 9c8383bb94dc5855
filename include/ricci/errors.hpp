#pragma once
/// \file
/// The exception hierarchy of ricci. Every throw names the function that detected the problem and
/// the offending element (file and line, vertex, edge or face index) in its message.
/// Non-convergence is never an exception: solvers report it in their result structs.

#include <stdexcept>
#include <string>

namespace ricci {

/// Base of every exception ricci throws on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The caller's data breaks a precondition: non-finite coordinates, a target that violates
/// Gauss-Bonnet, an option out of range, a zero-area face.
class InvalidInput : public Error {
 public:
  using Error::Error;
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
