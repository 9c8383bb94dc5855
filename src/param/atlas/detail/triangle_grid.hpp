#pragma once
// Private to the param module: the faces of a growing planar patch by cell of a hashed square
// grid, and whether a new triangle overlaps one of them. The unfolding of a component into patches
// and the split of a layout into embedded pieces (unfolding.cpp) both grow patches breadth first
// and ask this of every face before it joins.

#include <array>
#include <cmath>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "ricci/numerics/predicates.hpp"

namespace ricci::param_detail {

/// A triangle's three corners in the plane.
using PlanarTriangle = std::array<Eigen::Vector2d, 3>;

class TriangleGrid {
 public:
  /// \param cell the side of a cell, about twice the faces' size, so that a face touches a few
  ///        cells and a cell holds a few faces
  explicit TriangleGrid(double cell) : cell_(cell) {}

  /// Forgets every face (a new patch starts).
  void clear() { cells_.clear(); }

  /// Face f, with these corners, joins the patch.
  void insert(int f, const PlanarTriangle& corners) {
    for_cells(corners, [&](long long key) { cells_[key].push_back(f); });
  }

  /// Whether `shape` overlaps a face of the patch (triangles_overlap: interiors meet).
  /// \param corners_of corners_of(f) gives the corners face f was inserted with
  template <class CornersOf>
  bool overlaps(const PlanarTriangle& shape, const CornersOf& corners_of) const {
    bool found = false;
    for_cells(shape, [&](long long key) {
      if (found) return;
      const auto it = cells_.find(key);
      if (it == cells_.end()) return;
      for (int other : it->second) {
        if (triangles_overlap(shape, corners_of(other))) {
          found = true;
          return;
        }
      }
    });
    return found;
  }

 private:
  /// Calls visit(key) for the key of every cell the triangle's bounding box meets.
  template <class Visit>
  void for_cells(const PlanarTriangle& p, const Visit& visit) const {
    const Eigen::Vector2d lo = p[0].cwiseMin(p[1]).cwiseMin(p[2]) / cell_;
    const Eigen::Vector2d hi = p[0].cwiseMax(p[1]).cwiseMax(p[2]) / cell_;
    for (auto i = static_cast<long long>(std::floor(lo.x())); i <= std::floor(hi.x()); ++i) {
      for (auto j = static_cast<long long>(std::floor(lo.y())); j <= std::floor(hi.y()); ++j) {
        visit((i << 32) ^ (j & 0xffffffffLL));
      }
    }
  }

  double cell_;
  std::unordered_map<long long, std::vector<int>> cells_;
};

}  // namespace ricci::param_detail
