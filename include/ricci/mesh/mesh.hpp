#pragma once
/// \file
/// The triangle mesh every algorithm of ricci takes: vertex positions and counter-clockwise
/// triangles, as dense Eigen arrays (they map one to one onto numpy arrays in Python).

#include <Eigen/Core>

namespace ricci {

/// #V by 3 vertex positions.
using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3>;
/// #F by 3 vertex indices of counter-clockwise triangles.
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3>;

/// A triangle mesh in R^3. Algorithms that need a manifold mesh check it on entry
/// (see mesh/validate.hpp); this struct itself enforces nothing.
struct Mesh {
  Positions positions;  ///< #V by 3 vertex positions
  Triangles triangles;  ///< #F by 3 vertex indices, counter-clockwise seen from outside

  int num_vertices() const { return static_cast<int>(positions.rows()); }
  int num_faces() const { return static_cast<int>(triangles.rows()); }
};

}  // namespace ricci
