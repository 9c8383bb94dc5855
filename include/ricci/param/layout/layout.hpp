#pragma once
/// \file
/// Planar layout of a flat metric (tutorial section 5.5, THEORY.md section 7): the sliced mesh is
/// embedded in the plane face by face, breadth-first over a spanning tree of its dual graph
/// rooted near its centre, from the metric's edge lengths alone. Across every cut edge the two
/// copies differ by a rigid motion z -> a z + b (|a| = 1): its rotation is the curvature the cut
/// encloses (pure translations on a flat torus: the periodic flattening of the tutorial's fig. 15).

#include <complex>
#include <vector>

#include <Eigen/Core>

#include "ricci/intrinsic/intrinsic_triangulation.hpp"
#include "ricci/param/cut/cut_graph.hpp"

namespace ricci {

/// The rigid motion z -> rotation * z + translation taking one side of a cut edge to the other:
/// side B (the face of edge_halfedges(e, 1)) onto side A (the face of edge_halfedges(e, 0)). For
/// a segment, side A is that of its first edge and the same side of the path (left or right of
/// its direction) for the others.
struct SeamTransition {
  int edge = -1;                        ///< edge of the original mesh
  int segment = -1;                     ///< cut segment the edge belongs to
  std::complex<double> rotation{1};     ///< unit complex number a
  std::complex<double> translation{0};  ///< b (takes the midpoint of side B's ends onto side A's)
  double angle = 0;                     ///< arg(a), radians in (-pi + 1e-9, pi + 1e-9]
  /// max over the edge's two ends of |a z_B + b - z_A| / length; for a segment, over the ends of
  /// all its edges, each relative to its edge's length
  double mismatch = 0;
};

/// Options of layout_flat.
struct LayoutOptions {
  /// Face placed first (its component's root); -1 picks, per component of the cut mesh, the face
  /// farthest from the cut mesh's boundary in steps across edges (breadth-first over the dual
  /// graph), which keeps the layout tree shallow.
  int root_face = -1;
  /// When the tree layout's largest relative length error exceeds this, refine it by global
  /// least squares (the tree puts the holonomy of the metric's rounding-level residual curvature
  /// on a few edges; least squares spreads it over all). Negative: never refine.
  /// (The tests ask for 1e-9; 5e-10 keeps a margin and spares large regular meshes the cost.)
  double refine_above = 5e-10;
  /// Least-squares solves of the refinement: the first with the propagated rotations, each
  /// further one with the rotations fitted to the previous layout (measured: no gain after one).
  int refine_iterations = 1;
};

/// What layout_flat returns.
struct Layout {
  /// #V_cut by 2: position of each cut-mesh vertex (0 for vertices of no face). Each component
  /// is laid out from its own root: first corner at 0, second on the positive real axis.
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv;
  int root_face = -1;    ///< the root of the first component (or the one requested)
  bool refined = false;  ///< the least-squares refinement ran (LayoutOptions::refine_above)
  /// max over edges of | |uv_i - uv_j| - l_ij | / l_ij: how well the layout reproduces the
  /// metric (1e-9 or better expected).
  double max_length_relative_error = 0;
  /// Faces whose uv signed area is not positive (orientation reversed or collapsed): 0 expected
  /// where the metric is flat with no cone inside the face's neighbourhood.
  int num_flipped_faces = 0;
  std::vector<SeamTransition> transitions;  ///< one per interior cut edge, by edge index
  /// Per segment of the cut: the rigid motion fitted (least squares) to the ends of all its
  /// edges, which share one up to rounding; `edge` is its first edge.
  std::vector<SeamTransition> segment_transitions;
  /// A mesh that is one closed genus-1 component whose segment transitions are all
  /// translations (|angle| < 1e-6: a flat torus, no cones): a reduced basis b1, b2 of the lattice
  /// of the periodic tiling (|b1| <= |b2|, |<b1, b2>| <= |b1|^2 / 2, counter-clockwise), every
  /// seam translation an integer combination of them. Empty otherwise.
  std::vector<std::complex<double>> lattice;
};

/// Lays out a flat metric on the sliced mesh, breadth-first from the root over faces that share
/// an uncut edge. Each face's triangle in the metric (corner 0 at 0, corner 1 on the positive
/// real axis, angles by the half-angle formula of metric/angles.hpp) gets a rotation propagated
/// from its neighbour's across their shared edge; the root is placed as it is, and every later
/// face places its third vertex k from the two it shares (i, j) by its rotated triangle,
/// p_k = ((p_i + R (q_k - q_i)) + (p_j + R (q_k - q_j))) / 2. Each vertex is placed once, by the
/// first face that reaches it. Rounding adds up along the breadth-first tree instead of being
/// multiplied through needles. Linear time (0.16 s for a million faces, relative length error
/// 1.4e-11 on a 1M-face disk).
/// A curvature residual d at an interior vertex shows as a misclosure of about d times the
/// distance to the root: flatten to well below the accuracy wanted.
/// \param topology the original mesh's connectivity
/// \param lengths #E edge lengths of the flat metric (original mesh edges)
/// \param cut the cut the mesh was sliced along (is_cut_edge may be empty: no cut)
/// \param cut_mesh slice(topology, cut), or the mesh itself when it is a disk already
/// \pre the metric is flat at the cut mesh's interior vertices
/// \throw InvalidInput naming the face when the lengths break a triangle inequality (or are not
///        positive and finite), when a component of the cut mesh is not a topological disk, when
///        the cut mesh's corners do not copy the mesh's, when a segment steps across no cut edge,
///        or when root_face is out of range
Layout layout_flat(const Topology& topology, const Eigen::VectorXd& lengths, const CutGraph& cut,
                   const CutMesh& cut_mesh, const LayoutOptions& options = {});

/// The same from the shapes of the faces instead of edge lengths: each face's corners as the
/// metric develops them (develop_input_faces: the input's faces in the flat metric of the
/// intrinsic triangulation a flow with flips ends on). A face whose shape is reversed is laid out
/// reversed (and counted in num_flipped_faces) instead of mirrored by a triangle-inequality
/// reading of its lengths. Edge lengths are read from each edge's first face.
/// 	hrow InvalidInput as above (but for the triangle inequality), or when there is not one
///        shape per face
Layout layout_flat(const Topology& topology, const FaceShapes& shapes, const CutGraph& cut,
                   const CutMesh& cut_mesh, const LayoutOptions& options = {});

}  // namespace ricci
