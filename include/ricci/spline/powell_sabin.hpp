#pragma once
/// \file
/// Quadratic Powell-Sabin splines over a flat metric with cones (docs/splines.md; Powell and
/// Sabin 1977, "Piecewise quadratic approximations on triangles"). Every face is split into six
/// quadratic Bezier pieces around its incenter Z; the 19 ordinates of a face follow from the
/// values and gradients at its three corners. The construction uses only distances and angles of
/// the face's chart, so it commutes with the rigid chart transitions of a flat metric: two faces
/// that share an edge give the same value and gradient along it once the gradients are rotated by
/// the transition. Vertex data (a value and a gradient per column) live in a per-vertex tangent
/// frame, rotated into each face's chart by the corner's frame rotation.
///
/// Ordinate slots of a face (side k is the edge opposite corner k, from P = corner k+1 to
/// Q = corner k+2; R_k = lam_k P + (1 - lam_k) Q is its split point):
///   A_k = 0 + k        at corner k
///   C_k = 3 + k        at (V_k + Z) / 2
///   D_k = 6 + k        at R_k
///   E_k = 9 + k        at (R_k + Z) / 2
///   BP_k = 12 + k      at (P + R_k) / 2
///   BQ_k = 15 + k      at (Q + R_k) / 2
///   F = 18             at Z
/// Pieces: 2k = (P, R_k, Z) and 2k + 1 = (R_k, Q, Z), both counter-clockwise.

#include <array>
#include <complex>
#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/topology.hpp"

namespace ricci {

/// Bezier ordinates per face.
inline constexpr int kPowellSabinOrdinates = 19;
/// Quadratic pieces per face.
inline constexpr int kPowellSabinPieces = 6;

/// The split of a flat metric's faces, with charts and vertex frames: what the spline space needs.
struct SplineDomain {
  int num_vertices = 0;
  Triangles triangles;  ///< #F by 3 vertex indices of the mesh (not of the cut mesh)
  /// #F by 6: corner positions u0 v0 u1 v1 u2 v2 in the face's chart.
  Eigen::Matrix<double, Eigen::Dynamic, 6> corner_uv;
  Eigen::Matrix<double, Eigen::Dynamic, 2> split_point;    ///< #F: Z, the incenter
  Eigen::Matrix<double, Eigen::Dynamic, 3> split_weights;  ///< #F: barycentric coordinates of Z
  /// #F by 3: lam_k of side k; twin sides hold lam and 1 - lam exactly; 1/2 on the boundary.
  Eigen::Matrix<double, Eigen::Dynamic, 3> edge_split;
  /// 3#F: per corner, the unit complex number taking the vertex's frame into the face's chart
  /// (gradient in the chart = frame rotation * gradient in the vertex frame).
  std::vector<std::complex<double>> corner_frame;
  /// 3#F: per halfedge h, the rigid motion z -> rotation z + translation taking the chart of the
  /// twin's face onto h's face's chart (identity across uncut edges and on the boundary).
  std::vector<std::complex<double>> halfedge_rotation;
  std::vector<std::complex<double>> halfedge_translation;
  std::vector<int> halfedge_twin;  ///< 3#F, -1 on the boundary
  std::vector<int> halfedge_edge;  ///< 3#F, edge index
  int num_edges = 0;
  std::vector<char> fixed_gradient;  ///< #V: 1 where the gradient is held at 0 (cones)
  std::vector<char> referenced;      ///< #V: 1 for vertices of some face
  double mean_edge_length = 0;       ///< in the charts
  /// Largest rotation mismatch (radians) where the walk around an interior vertex that is not a
  /// cone closes: the residual curvature of the metric (rounding level expected).
  double frame_closure_error = 0;
};

/// Builds the domain from a flat metric laid out in charts.
/// \param topology the mesh's connectivity (e.g. MeshFlowResult::intrinsic.topology())
/// \param chart_triangles #F by 3 indices into uv, same faces and corner order (CutMesh::triangles)
/// \param uv chart positions (Layout::uv): every face's corners in one chart; faces across an edge
///        whose ends have the same chart indices share the chart, otherwise the two charts differ
///        by the rigid motion that maps the edge's ends onto each other
/// \param fixed_gradient_vertices vertices whose gradient is held at 0 (the cones)
/// \throw InvalidInput when sizes disagree, a face has no positive area in its chart, a vertex is
///        out of range, or an unfolded neighbour's incenter lands on the wrong side of an edge
SplineDomain spline_domain(const Topology& topology, const Triangles& chart_triangles,
                           const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv,
                           const std::vector<int>& fixed_gradient_vertices = {});

/// A planar mesh as its own single chart (triangles counter-clockwise in uv).
/// \throw InvalidInput, TopologyError as build_topology and spline_domain
SplineDomain planar_spline_domain(const Triangles& triangles,
                                  const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv);

/// Values and gradients at the vertices, k columns of data.
struct SplineVertexData {
  Eigen::MatrixXd values;     ///< #V by k
  Eigen::MatrixXd gradients;  ///< #V by 2k: columns 2c, 2c + 1 = gradient of column c, vertex frame
};

/// The linear map (19 by 9) from a face's corner data (a_0 a_1 a_2, then the vertex-frame
/// gradients g_0x g_0y g_1x g_1y g_2x g_2y) to its 19 ordinates.
Eigen::Matrix<double, kPowellSabinOrdinates, 9> face_ordinate_map(const SplineDomain& domain,
                                                                  int face);

/// The corners of piece p of a face in its chart.
std::array<Eigen::Vector2d, 3> piece_triangle(const SplineDomain& domain, int face, int piece);

/// Ordinate slots of piece p in the order b200 b020 b002 b110 b101 b011 (b200 at its first
/// corner, b110 at the midpoint of its first two corners...).
std::array<int, 6> piece_slots(int piece);

/// The constant Hessian (Hxx, Hxy, Hyy) of piece p as a linear map of the face's ordinates.
Eigen::Matrix<double, 3, kPowellSabinOrdinates> piece_hessian_map(const SplineDomain& domain,
                                                                  int face, int piece);

/// All ordinates: 19 #F by k, row 19 f + slot.
/// \throw InvalidInput when the data do not have #V rows (and 2k gradient columns)
Eigen::MatrixXd face_ordinates(const SplineDomain& domain, const SplineVertexData& data);

/// Value (1 by k) and gradient (2 by k, in the face's chart) at a point of a face.
struct SplineSample {
  Eigen::RowVectorXd value;
  Eigen::Matrix<double, 2, Eigen::Dynamic> gradient;
  int piece = -1;  ///< the piece evaluated
};

/// Evaluates the spline at the point of `face` with these barycentric coordinates (w.r.t. its
/// corners 0, 1, 2), from the piece that contains it.
/// \param ordinates face_ordinates' result (19 #F by k)
SplineSample evaluate_spline(const SplineDomain& domain, const Eigen::MatrixXd& ordinates, int face,
                             const Eigen::Vector3d& barycentric);

/// Value and gradient jumps across every interior edge (cut or not).
struct ContinuityReport {
  int edges_checked = 0;
  int samples = 0;                    ///< sample points (each evaluated from both faces)
  double max_value_jump = 0;          ///< largest |s_f - s_g| over columns
  double max_gradient_jump = 0;       ///< largest |grad s_f - rotation grad s_g| over columns
  double value_scale = 0;             ///< largest spread (max - min) of a column's ordinates
  double gradient_scale = 0;          ///< largest gradient norm met at the sample points
  double relative_value_jump = 0;     ///< max_value_jump / value_scale
  double relative_gradient_jump = 0;  ///< max_gradient_jump / gradient_scale
  int worst_edge = -1;                ///< edge of the largest relative jump
};

/// Samples every interior edge at `samples_per_edge` interior points (t = i / (n + 1)), evaluates
/// the spline from both faces and compares values and gradients (the neighbour's gradient rotated
/// into this face's chart by the halfedge's transition).
ContinuityReport measure_continuity(const SplineDomain& domain, const Eigen::MatrixXd& ordinates,
                                    int samples_per_edge = 5);

}  // namespace ricci
