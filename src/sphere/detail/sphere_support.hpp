#pragma once
/// \file
/// What the stages of the sphere map share (internal; src/sphere/sphere.cpp runs them): points in
/// the arithmetic T each stage runs in (double, long double or Quad,
/// ricci/numerics/wide_float.hpp), the disk's data, and the two stages with files of their own, the
/// disk's layout (sphere_layout.cpp) and the untangling of inverted faces (sphere_untangle.cpp),
/// each compiled for the three arithmetics.

#include <algorithm>
#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ricci/intrinsic/intrinsic_triangulation.hpp"
#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/numerics/wide_float.hpp"
#include "ricci/sphere/sphere.hpp"

namespace ricci::sphere_support {

template <class T>
using Point2 = std::array<T, 2>;
template <class T>
using Point3 = std::array<T, 3>;

template <class T>
Point3<T> difference(const Point3<T>& a, const Point3<T>& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

template <class T>
Point3<T> cross(const Point3<T>& a, const Point3<T>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

template <class T>
T dot(const Point3<T>& a, const Point3<T>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

template <class T>
Eigen::Vector3d to_double(const Point3<T>& a) {
  return {static_cast<double>(a[0]), static_cast<double>(a[1]), static_cast<double>(a[2])};
}

/// The smallest altitude of the triangle with edge vectors e1, e2 (twice its area over its
/// longest edge): how far a corner must move to flatten it.
inline double smallest_altitude(const Eigen::Vector3d& e1, const Eigen::Vector3d& e2) {
  const double longest = std::max({e1.norm(), e2.norm(), (e2 - e1).norm()});
  return longest > 0 ? e1.cross(e2).norm() / longest : 0.0;
}

/// Smallest altitude below which a face's double positions keep its shape only roughly:
/// 2^-46, 64 units in the last place of a coordinate of the unit sphere.
constexpr double kDoubleResolution = 0x1p-46;

/// What the precise stages read: the disk, its faces' shapes, and where its vertices go.
struct DiskMap {
  const Mesh& mesh;
  const Topology& disk;                        ///< the disk's connectivity (disk vertex indices)
  const FaceShapes& shapes;                    ///< per disk face, its corners in the flat metric
  const std::vector<int>& disk_vertices;       ///< disk vertex -> mesh vertex
  const std::vector<int>& referenced;          ///< the mesh's vertices on faces
  const Eigen::VectorXd& weights;              ///< per mesh face, its share of the 3D area
  const std::vector<std::vector<int>>& stars;  ///< per mesh vertex, its faces
  int pole = -1;
};

/// z w for complex numbers stored as (real, imaginary) pairs.
template <class T>
Point2<T> times(const Point2<T>& z, const Point2<T>& w) {
  return {z[0] * w[0] - z[1] * w[1], z[0] * w[1] + z[1] * w[0]};
}

/// det(P_i, P_j, P_k) from the differences, in T: exact to rounding at any scale.
template <class T>
T face_determinant(const std::vector<Point3<T>>& sphere, int i, int j, int k) {
  return dot(sphere[i], cross(difference(sphere[j], sphere[i]), difference(sphere[k], sphere[i])));
}

/// The disk laid out in the plane in arithmetic T, smallest faces first (sphere_layout.cpp):
/// one position per disk vertex, in the flat metric's unit, up to a rigid motion. Compiled for
/// double, long double and Quad.
template <class T>
std::vector<Point2<T>> develop_disk(const DiskMap& in);

/// Moves vertices of the faces the map inverts so that every face of their stars keeps its
/// orientation (sphere_untangle.cpp); adds to result.untangled_vertices and the largest moves.
/// Returns the vertices moved. Compiled for double, long double and Quad.
template <class T>
int untangle(const DiskMap& in, std::vector<Point3<T>>& sphere, SphereResult& result);

}  // namespace ricci::sphere_support
