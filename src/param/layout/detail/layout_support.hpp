#pragma once
/// \file
/// What the flat and the hyperbolic layouts share (internal): input checks, the choice of root
/// faces, the order in which vertices are placed, and which cut segment and side each cut edge
/// belongs to. Positions are computed by the callers, each in its own geometry.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/param/cut/cut_graph.hpp"
#include "ricci/param/layout/layout.hpp"

namespace ricci::layout_support {

/// Throws InvalidInput, naming `who`, when the lengths, cut flags, cut mesh, root face or
/// segments do not fit the mesh, or when a component of the cut mesh is not a disk.
void check_inputs(const char* who, const Topology& topology, const Eigen::VectorXd& lengths,
                  const CutGraph& cut, const CutMesh& cut_mesh, int root_face);

/// Per component of the cut mesh, the face farthest from its boundary in steps across edges of
/// the dual graph (or the requested root_face for its component): the roots of the layout.
/// \param[out] first_root the root of the first component, or root_face when given
std::vector<int> root_faces(const Topology& cut_topology, int root_face, int& first_root);

/// Root faces chosen ahead of the layout: root_faces(cut_topology, root_face, first).
struct Roots {
  std::vector<int> faces;
  int first = -1;
};

/// layout_flat(topology, shapes, cut, cut_mesh, options) (ricci/param/layout/layout.hpp; defined in
/// layout.cpp) with the roots chosen ahead, from cut_mesh.topology and options.root_face: the
/// breadth-first search for them needs only the cut mesh, so parameterize runs it beside the flow.
Layout layout_flat_with_roots(const Topology& topology, const FaceShapes& shapes,
                              const CutGraph& cut, const CutMesh& cut_mesh,
                              const LayoutOptions& options, const Roots& roots);

/// The order in which the layout places the cut mesh's vertices after the roots' corners: one
/// halfedge t per vertex, whose face t / 3 has its other two corners placed already; the vertex
/// at corner t % 3 is placed from edge (tail(t), head(t)). Vertices are taken in the order of
/// least estimated error growth (Dijkstra with the ratio l_ik / l_ij as the cost of a step:
/// about one per step on a regular mesh, where it is breadth-first, and large through needles),
/// each from its best-conditioned face. A plain breadth-first order lets errors grow
/// geometrically through needle triangles: on face.obj with a vertex-scaling metric this cuts the
/// largest length error from 1.3e-6 (breadth-first) to 2.8e-8, and on a 1M-face torus from
/// 3.5e-10 to 2.0e-10.
std::vector<int> placement_order(const Topology& topology, const Topology& cut_topology,
                                 const Eigen::VectorXd& lengths, const std::vector<int>& roots);

/// The cut's edges grouped by segment.
struct SegmentEdges {
  std::vector<int> edge_segment;                ///< #E: segment of each cut edge, -1 elsewhere
  std::vector<std::vector<int>> segment_edges;  ///< per segment, its edges in path order
  /// #E: the halfedge of each cut edge on its segment's side A (the side of
  /// edge_halfedges(e, 0) for the segment's first edge, and the same side of the path, left or
  /// right of its direction, for the others); -1 for a boundary edge or an edge of no segment.
  std::vector<int> side_a_halfedge;
};

/// \throw InvalidInput naming `who` when a segment steps across a pair of vertices that is not a
///        cut edge
SegmentEdges segment_edges(const char* who, const Topology& topology, const CutGraph& cut);

}  // namespace ricci::layout_support
