#pragma once
/// \file
/// Layout of a hyperbolic metric in the Poincare disk (THEORY.md section 9): the sliced mesh is
/// embedded triangle by triangle, as the flat layout does in the plane, with hyperbolic
/// isometries (Moebius maps) in place of rigid motions. Across every cut segment the two copies
/// differ by one deck transformation, a Moebius map of the disk; going once around a node of the
/// cut graph, the deck transformations of the segments crossed compose to the identity. These
/// are the data of the surface's Fuchsian group (ricci/hyperbolic/fuchsian.hpp).

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ricci/hyperbolic/hyperbolic_refinement.hpp"
#include "ricci/intrinsic/intrinsic_triangulation.hpp"
#include "ricci/numerics/mobius.hpp"
#include "ricci/param/cut/cut_graph.hpp"

namespace ricci {

/// Options of layout_hyperbolic.
struct HyperbolicLayoutOptions {
  /// Face placed first, its first corner at the centre of the disk; -1 picks, per component of
  /// the cut mesh, the face farthest from the cut in steps across edges (as layout_flat does).
  int root_face = -1;
  /// Move the fundamental domain's centre to the centre of the disk afterwards (an isometry:
  /// the layout's shape and accuracy do not change, the picture and the maps' matrices become
  /// balanced). The centre: the area-weighted mean of the face centroids, made the origin by a
  /// few fixed-point steps of z -> (z - c) / (1 - conj(c) z).
  bool recentre = true;
};

/// The deck transformation of one cut segment.
struct SegmentIsometry {
  int segment = -1;
  int edge = -1;  ///< the segment's first edge (its side A is that of edge_halfedges(edge, 0))
  /// Takes the positions of side B of the segment onto those of side A (the sides as in
  /// layout_support: the same side of the path along the whole segment).
  Mobius map;
  /// The same map as computed, in long double (map is it normalised and rounded).
  WideMobius wide_map;
  /// max over the ends of the segment's edges of the hyperbolic distance between the image of
  /// the side-B copy and the side-A copy, relative to the edge's length.
  double mismatch = 0;
  double translation_length = 0;  ///< how far the map moves the points of its axis
};

/// What layout_hyperbolic returns.
struct HyperbolicLayout {
  /// #V_cut by 2: the position of each cut-mesh vertex in the Poincare disk (|z| < 1).
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv;
  int root_face = -1;
  /// max over edges of |d(p_i, p_j) - l_ij| / l_ij with d the hyperbolic distance of the disk.
  double max_length_relative_error = 0;
  /// Faces whose three corners are not counter-clockwise in the disk: 0 expected.
  int num_flipped_faces = 0;
  double max_radius = 0;                      ///< largest |z| of a vertex
  std::vector<SegmentIsometry> segment_maps;  ///< one per cut segment
  /// Per node of the cut graph (CutGraph::nodes, same order) on a closed component: the cut
  /// segments crossed going once around the node, as (segment, +1) when the crossing goes from
  /// side A to side B and (segment, -1) the other way. The product of the segment maps (or their
  /// inverses) in this order is the identity. Nodes on a boundary get an empty word.
  std::vector<std::vector<std::pair<int, int>>> node_words;
};

/// Lays out a hyperbolic metric on the sliced mesh, placing each vertex from an edge whose ends
/// are placed: in the frame that moves p_i to 0 and p_j onto the positive real axis, p_k sits at
/// tanh(l_ik / 2) e^{i theta_i}. Vertices are placed in the flat layout's order of least error
/// growth; linear time.
/// \param lengths #E hyperbolic edge lengths (original mesh edges)
/// \param cut, cut_mesh as for layout_flat
/// \throw InvalidInput as layout_flat (naming layout_hyperbolic), and when the lengths break a
///        triangle inequality
HyperbolicLayout layout_hyperbolic(const Topology& topology, const Eigen::VectorXd& lengths,
                                   const CutGraph& cut, const CutMesh& cut_mesh,
                                   const HyperbolicLayoutOptions& options = {});

/// The same from long double lengths (refine_hyperbolic_metric): the positions are computed in
/// long double in either case; from double lengths the metric's own rounding (curvature about
/// 1e-15 per vertex) limits how well the sides of the cut match.
HyperbolicLayout layout_hyperbolic(const Topology& topology, const WideVector& lengths,
                                   const CutGraph& cut, const CutMesh& cut_mesh,
                                   const HyperbolicLayoutOptions& options = {});

/// The same from the shapes of the faces in the disk instead of edge lengths: each face's corners
/// as the metric develops them (develop_input_faces_hyperbolic: the input's faces in the
/// hyperbolic metric of the intrinsic triangulation a flow with flips ends on). A face whose
/// shape is reversed is laid out reversed (and counted in num_flipped_faces). Edge lengths are
/// read from each edge's first face.
/// \throw InvalidInput as above (but for the triangle inequality), or when there is not one
///        shape per face
HyperbolicLayout layout_hyperbolic(const Topology& topology, const WideFaceShapes& shapes,
                                   const CutGraph& cut, const CutMesh& cut_mesh,
                                   const HyperbolicLayoutOptions& options = {});

}  // namespace ricci
