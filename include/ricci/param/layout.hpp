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

#include "ricci/param/cut_graph.hpp"

namespace ricci {

/// The rigid motion z -> rotation * z + translation taking one side of a cut edge to the other.
struct SeamTransition {
  int edge = -1;                     ///< edge of the original mesh
  int segment = -1;                  ///< cut segment the edge belongs to
  std::complex<double> rotation{1};  ///< unit complex number a
  std::complex<double> translation{0};  ///< b
  double angle = 0;                  ///< arg(a), radians in (-pi, pi]
  double mismatch = 0;  ///< max over the edge's two ends of |a z_side + b - z_other| / length
};

/// Options of layout_flat.
struct LayoutOptions {
  int root_face = -1;  ///< face placed first; -1 picks the face farthest from the cut
};

/// What layout_flat returns.
struct Layout {
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv;  ///< per vertex of the cut mesh
  int root_face = -1;
  /// max over edges of | |uv_i - uv_j| - l_ij | / l_ij: how well the layout reproduces the
  /// metric (1e-9 or better expected).
  double max_length_relative_error = 0;
  /// Faces whose uv signed area is not positive (orientation reversed or collapsed): 0 expected
  /// where the metric is flat with no cone inside the face's neighbourhood.
  int num_flipped_faces = 0;
  std::vector<SeamTransition> transitions;  ///< one per cut edge
  /// Per segment: the transition of its edges (they share one rigid motion up to rounding).
  std::vector<SeamTransition> segment_transitions;
  /// Genus-1 closed surfaces without cones: two independent translations generating the
  /// lattice of the periodic tiling (empty otherwise).
  std::vector<std::complex<double>> lattice;
};

/// Lays out a flat metric on the sliced mesh.
/// \param topology the original mesh's connectivity
/// \param lengths #E edge lengths of the flat metric (original mesh edges)
/// \pre the cut mesh is a topological disk and the metric is flat at its interior vertices
/// \throw InvalidInput when the lengths break a triangle inequality
Layout layout_flat(const Topology& topology, const Eigen::VectorXd& lengths, const CutGraph& cut,
                   const CutMesh& cut_mesh, const LayoutOptions& options = {});

}  // namespace ricci
