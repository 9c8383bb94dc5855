#pragma once
/// \file
/// How the intrinsic triangulation a flow with edge flips ends on corresponds to the input
/// triangulation, and how the input's own faces sit in the final metric.
///
/// A flow with Ptolemy flips (ricci/metric/delaunay_flips.hpp) ends on a triangulation T' of the
/// same surface with the same vertices: the input triangulation T after a sequence of flips.
/// flip_edge is a deterministic function of the topology and the edge, so the list of flipped
/// edges is the whole correspondence: replaying it on T gives T', and every intermediate
/// triangulation on the way.
///
/// The final metric is flat (or has its target curvature) at the vertices and is a Euclidean
/// triangle on every face of T'. A face of T is a disk on the surface with no vertex inside, so
/// the metric develops it into the plane; its three corners land at three points, the exact
/// images of the input vertices. develop_input_faces computes them by undoing the flips one by
/// one: undoing the flip of edge e glues its two current faces along e (a rigid motion taking
/// one face's copy of e onto the other's) and reads the old faces' corners off that quad. No
/// flip changes a face's index, so every face of T ends with its own corners. Delta-complexes
/// (double edges, loops, a face using a vertex twice) need nothing special: faces are developed
/// as abstract triangles, corner by corner.
///
/// A hyperbolic metric (curvature -1 in every triangle) is developed the same way into the
/// Poincare disk, with hyperbolic isometries (Moebius maps of the disk) in place of rigid motions,
/// in long double: the hyperbolic layout and the Fuchsian group it leads to amplify every rounding
/// error (ricci/flow/hyperbolic_refinement.hpp).

#include <array>
#include <complex>
#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/topology.hpp"
#include "ricci/metric/hyperbolic.hpp"

namespace ricci {

/// Per face of a triangulation, its three corners in a plane of its own (corner k is the vertex
/// triangles(f, k)); the faces of one development are each placed up to a rigid motion.
using FaceShapes = std::vector<std::array<std::complex<double>, 3>>;

/// Applies flip_edge to each edge in order, on a copy of `input`.
/// \throw InvalidInput naming the position in the list when an edge is out of range or cannot be
///        flipped (boundary edge, or inside one self-glued face)
Topology replay_flips(const Topology& input, const std::vector<int>& flipped_edges);

/// What develop_input_faces returns.
struct Development {
  FaceShapes shapes;  ///< #F: the input faces' corners, each face in a frame of its own
  /// #E of the input: each input edge's length in the final metric (the distance between its
  /// developed ends), as seen from its first face.
  Eigen::VectorXd lengths;
  /// max over interior input edges of the relative difference between the lengths the edge gets
  /// in its two faces (0 in exact arithmetic; a few ulps times the number of flips undone
  /// across the edge in practice).
  double max_length_mismatch = 0;
  int flipped_faces = 0;     ///< input faces developed with negative orientation
  int degenerate_faces = 0;  ///< input faces developed with (relative) zero area
};

/// Develops every face of the input triangulation in the final metric (see the file comment).
/// \param input the input triangulation T (edges as in the flow's input)
/// \param flipped_edges the flips that turned T into the final triangulation T' (replayed here)
/// \param final_lengths #E lengths of T''s edges (a flip reuses the index of the edge it removes)
/// \pre final_lengths satisfy the triangle inequalities on every face of T'
/// \throw InvalidInput when the flips cannot be replayed or a final face breaks a triangle
///        inequality
Development develop_input_faces(const Topology& input, const std::vector<int>& flipped_edges,
                                const Eigen::VectorXd& final_lengths);

/// The shapes of a triangulation's faces from its edge lengths: corner 0 at 0, corner 1 on the
/// positive real axis, corner 2 above it (angles by the half-angle formula).
/// \throw InvalidInput naming the face when its lengths break a triangle inequality
FaceShapes face_shapes_from_lengths(const Topology& topology, const Eigen::VectorXd& lengths);

/// Per face of a triangulation, its three corners in the Poincare disk (|z| < 1), in long double;
/// each face in a frame of its own: corner 0 at the centre, corner 1 on the positive real axis.
using WideFaceShapes = std::vector<std::array<std::complex<long double>, 3>>;

/// What develop_input_faces_hyperbolic returns.
struct HyperbolicDevelopment {
  WideFaceShapes shapes;  ///< #F: the input faces' corners in the disk, each in its own frame
  /// #E of the input: each input edge's hyperbolic length in the final metric, as seen from its
  /// first face.
  WideVector lengths;
  /// max over interior input edges of the relative difference between the hyperbolic lengths the
  /// edge gets in its two faces (0 in exact arithmetic).
  double max_length_mismatch = 0;
  int flipped_faces = 0;     ///< input faces developed with negative orientation
  int degenerate_faces = 0;  ///< input faces developed with (relative) zero area
};

/// develop_input_faces for a hyperbolic metric: every face of the input triangulation developed
/// into the Poincare disk, in long double, by undoing the flips with hyperbolic isometries.
/// \param final_lengths #E hyperbolic lengths of T''s edges (refine_hyperbolic_metric's)
/// \pre final_lengths satisfy the triangle inequalities on every face of T'
/// \throw InvalidInput when the flips cannot be replayed or a final face breaks a triangle
///        inequality
HyperbolicDevelopment develop_input_faces_hyperbolic(const Topology& input,
                                                     const std::vector<int>& flipped_edges,
                                                     const WideVector& final_lengths);

/// The shapes of a triangulation's hyperbolic faces from their edge lengths: corner 0 at the
/// centre of the disk, corner 1 on the positive real axis at tanh(l / 2), corner 2 above it.
/// \throw InvalidInput naming the face when its lengths break a triangle inequality
WideFaceShapes hyperbolic_face_shapes_from_lengths(const Topology& topology,
                                                   const WideVector& lengths);

}  // namespace ricci
