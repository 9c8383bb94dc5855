#pragma once
/// \file
/// Which faces of a layout overlap in uv: the exact check that the packer's atlas, a chart's own
/// layout (a conformal map without flipped faces can still wind over itself) and the tests read.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// What find_uv_overlaps returns.
struct UvOverlaps {
  int count = 0;                          ///< overlapping pairs found
  std::vector<std::array<int, 2>> pairs;  ///< the first max_pairs of them (face indices a < b)
};

/// Pairs of faces whose uv triangles overlap: their interiors intersect (triangles that only
/// touch along an edge or at a point do not). Decided exactly: two triangles' interiors are
/// disjoint if and only if an edge line of one has the other on its outer side, and the side of
/// a point is the sign of an orientation determinant evaluated in exact expansion arithmetic.
/// Faces of zero uv area have no interior and never overlap. Candidate pairs come from a uniform
/// grid over the triangles' bounding boxes.
/// \param uv #UV by 2 positions
/// \param triangles #F by 3 indices into uv
/// \param face_group #F group per face, or empty: with groups only pairs of faces of different
///        groups are tested (charts of an atlas against each other)
/// \param max_pairs how many pairs to list (all are counted)
/// \throw InvalidInput for an index out of range, a non-finite position or a face_group of the
///        wrong size
UvOverlaps find_uv_overlaps(const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv,
                            const Triangles& triangles, const std::vector<int>& face_group = {},
                            int max_pairs = 16);
}  // namespace ricci
