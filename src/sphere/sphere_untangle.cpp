#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Dense>

#include "sphere/detail/sphere_support.hpp"

namespace ricci::sphere_support {
namespace {

/// A face (v, a, b) of a vertex's star as a constraint on v's position x: the plane through the
/// origin, a and b, with unit normal m; the face keeps its orientation where (x - a) . m > 0.
template <class T>
struct StarSide {
  Point3<T> a, m;
};

/// A vertex of the linear programme may violate a constraint by this fraction of the box (the
/// rounding of the 3 by 3 solve that produced it).
constexpr double kFeasibilitySlack = 1e-12;

/// The offset from x0 to the position deepest inside the constraints of a star (the largest
/// least distance to its planes), within the tangent plane at x0 and a box of twice the
/// shortest edge: a linear programme in (u, w, depth) solved by its vertices (each three active
/// constraints), few enough for a star. Falls back to the mean of the link, `mean` / 2n.
template <class T>
Point3<T> deepest_offset(const Point3<T>& x0, const std::vector<StarSide<T>>& sides,
                         const Point3<T>& mean, double shortest) {
  const Eigen::Vector3d normal = to_double(x0).normalized();
  const Eigen::Vector3d e1 = normal.unitOrthogonal(), e2 = normal.cross(e1);
  // Constraint rows: g . (u, w) - depth >= h, i.e. (x0 + u e1 + w e2 - a) . m >= depth.
  std::vector<Eigen::Vector3d> rows;
  std::vector<double> rhs;
  for (const StarSide<T>& side : sides) {
    const Eigen::Vector3d m = to_double(side.m);
    rows.emplace_back(m.dot(e1), m.dot(e2), -1.0);
    rhs.push_back(-static_cast<double>(dot(difference(x0, side.a), side.m)));
  }
  const double box = 2 * shortest;
  for (const Eigen::Vector3d& r : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-1, 0, 0),
                                   Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, -1, 0)}) {
    rows.push_back(r);
    rhs.push_back(-box);
  }
  const int n = static_cast<int>(rows.size());
  double best_depth = -std::numeric_limits<double>::infinity();
  Eigen::Vector3d best = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      for (int k = j + 1; k < n; ++k) {
        Eigen::Matrix3d A;
        A << rows[i].transpose(), rows[j].transpose(), rows[k].transpose();
        const Eigen::Vector3d b(rhs[i], rhs[j], rhs[k]);
        const Eigen::FullPivLU<Eigen::Matrix3d> lu(A);
        if (!lu.isInvertible()) continue;
        const Eigen::Vector3d x = lu.solve(b);
        if (!x.allFinite() || x[2] <= best_depth) continue;
        bool feasible = true;
        for (int c = 0; c < n && feasible; ++c) {
          feasible = rows[c].dot(x) >= rhs[c] - kFeasibilitySlack * box;
        }
        if (feasible) {
          best_depth = x[2];
          best = x;
        }
      }
    }
  }
  if (!(best_depth > 0)) {
    const T share = T{1} / static_cast<T>(2 * sides.size());
    return {mean[0] * share, mean[1] * share, mean[2] * share};
  }
  const Eigen::Vector3d offset = best[0] * e1 + best[1] * e2;
  return {static_cast<T>(offset.x()), static_cast<T>(offset.y()), static_cast<T>(offset.z())};
}

}  // namespace

/// Moves vertices of the faces the map inverts so that every face of their stars keeps its
/// orientation: a needle the flat metric reverses (vertex scaling bends them over), or a very
/// obtuse face whose chordal triangle the projection bends over. det(x, a, b) = (x - a) .
/// (a x (b - a)) is linear in x, so the positions of a vertex that orient its whole star form
/// a convex cone; the vertex moves along the great circle towards the mean of its link, a
/// quarter of the way into that cone past its boundary (the least move that leaves a margin).
/// Of a face's three corners the one moving least relative to its shortest edge moves. Faces
/// below double resolution are left to the count of inverted_by_rounding: no move in T
/// survives their rounding. Returns the vertices moved.
template <class T>
int untangle(const DiskMap& in, std::vector<Point3<T>>& sphere, SphereResult& result) {
  const Triangles& F = in.mesh.triangles;
  const int nf = in.mesh.num_faces();
  std::vector<int> bad;
  for (int f = 0; f < nf; ++f) {
    if (!(face_determinant(sphere, F(f, 0), F(f, 1), F(f, 2)) > 0)) bad.push_back(f);
  }
  if (bad.empty()) return 0;
  const std::vector<std::vector<int>>& stars = in.stars;
  int moved = 0;
  for (int f : bad) {
    if (face_determinant(sphere, F(f, 0), F(f, 1), F(f, 2)) > 0) continue;  // fixed meanwhile
    Point3<T> best_position{};
    int best_vertex = -1;
    double best_move = std::numeric_limits<double>::infinity();
    for (int corner = 0; corner < 3; ++corner) {
      const int v = F(f, corner);
      const Point3<T> x0 = sphere[v];
      // Each face (v, a, b) of the star: the plane through the origin, a and b, normal m.
      std::vector<StarSide<T>> sides;
      Point3<T> mean{T{0}, T{0}, T{0}};  // mean offset of the link from x0
      double shortest = std::numeric_limits<double>::infinity();
      for (int g : stars[v]) {
        int k = 0;
        while (F(g, k) != v) ++k;
        const Point3<T>& a = sphere[F(g, (k + 1) % 3)];
        const Point3<T>& b = sphere[F(g, (k + 2) % 3)];
        const Point3<T> m = cross(a, difference(b, a));
        const double length = to_double(m).norm();
        if (!(length > 0)) continue;
        const T scale = static_cast<T>(1 / length);
        sides.push_back({a, {m[0] * scale, m[1] * scale, m[2] * scale}});
        const Point3<T> da = difference(a, x0);
        for (int c = 0; c < 3; ++c) mean[c] += da[c];
        shortest = std::min(shortest, to_double(da).norm());
      }
      if (sides.size() != stars[v].size() || !(shortest > kDoubleResolution)) continue;
      // The margin of a position: its least signed distance to the star's planes, over the
      // shortest edge.
      auto margin = [&](const Point3<T>& x) {
        double least = std::numeric_limits<double>::infinity();
        for (const StarSide<T>& side : sides) {
          least = std::min(least, static_cast<double>(dot(difference(x, side.a), side.m)));
        }
        return least / shortest;
      };
      // x(t) on the great circle from x0 towards the star's deepest point, as an offset from x0.
      const Point3<T> towards = deepest_offset(x0, sides, mean, shortest);
      auto at = [&](double t) {
        const T tt = static_cast<T>(t);
        const Point3<T> y{x0[0] + tt * towards[0], x0[1] + tt * towards[1],
                          x0[2] + tt * towards[2]};
        const T norm = square_root(dot(y, y));
        return Point3<T>{y[0] / norm, y[1] / norm, y[2] / norm};
      };
      const double goal = margin(at(1.0));
      if (!(goal > 0)) continue;
      double low = 0, high = 1;  // margin(at(low)) <= goal / 4 < margin(at(high))
      for (int bisection = 0; bisection < 60; ++bisection) {
        const double mid = (low + high) / 2;
        (margin(at(mid)) > goal / 4 ? high : low) = mid;
      }
      const Point3<T> x = at(high);
      const double move = to_double(difference(x, x0)).norm() / shortest;
      if (move < best_move) {
        best_move = move;
        best_vertex = v;
        best_position = x;
      }
    }
    if (best_vertex < 0) continue;
    const double chord = to_double(difference(best_position, sphere[best_vertex])).norm();
    sphere[best_vertex] = best_position;
    ++moved;
    ++result.untangled_vertices;
    result.max_untangle_move = std::max(result.max_untangle_move, chord);
    result.max_untangle_relative_move = std::max(result.max_untangle_relative_move, best_move);
  }
  return moved;
}

template int untangle<double>(const DiskMap&, std::vector<Point3<double>>&, SphereResult&);
template int untangle<long double>(const DiskMap&, std::vector<Point3<long double>>&,
                                   SphereResult&);
#ifdef RICCI_HAVE_QUAD
template int untangle<Quad>(const DiskMap&, std::vector<Point3<Quad>>&, SphereResult&);
#endif

}  // namespace ricci::sphere_support
