#pragma once
/// \file
/// A surface with boundary glued to its mirror image along the boundary: the closed surface on
/// which the flow of a component with boundary runs when its boundary edges, which cannot flip,
/// block it (ricci/flow/mesh_flow.hpp, ComponentFlow::doubled).

#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/topology.hpp"

namespace ricci {

/// Mirrored corner k of face f copies corner kMirroredCorner[k]: (a, b, c) becomes (a', c', b').
inline constexpr int kMirroredCorner[3] = {0, 2, 1};

/// What build_doubled_topology returns.
struct DoubledTopology {
  /// #V2 = #V + (interior vertices): the original vertices, then the mirror copy of each
  /// interior vertex in ascending order (boundary vertices are shared).
  int num_vertices = 0;
  /// 2 #F by 3: face f as in the input, then face #F + f its mirror image (reverse
  /// orientation, corner k copying corner kMirroredCorner[k]).
  Triangles triangles;
  /// Its connectivity, made directly: an interior edge joining two boundary vertices and its
  /// mirror image join the same two (shared) vertices, a double edge that build_topology cannot
  /// pair. Input halfedge 3 f + k keeps its index, its mirror image is halfedge
  /// 3 (#F + f) + kMirroredCorner[k], running the other way; a boundary halfedge becomes the twin
  /// of its own mirror image. Input edge e keeps its index; the mirror images of interior edges
  /// follow, in ascending order. One component, closed, no boundary flags.
  Topology topology;
  std::vector<int> original;  ///< #V2: doubled vertex -> input vertex
};

/// The double of a triangulation along its boundary (see DoubledTopology).
/// \pre topology is a build_topology result with at least one boundary edge and one component
DoubledTopology build_doubled_topology(const Topology& topology);

}  // namespace ricci
