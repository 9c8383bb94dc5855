#pragma once
/// \file
/// The exact discrete conformal map of a vertex-scaling parameterization, written on the common
/// refinement of the input triangulation and the intrinsic one (Gillespie, Springborn and Crane,
/// "Discrete conformal equivalence of polyhedral surfaces", SIGGRAPH 2021).
///
/// A flow with flips (ricci/intrinsic/delaunay_flips.hpp) meets three triangulations of the input
/// vertices: T0, the input; T1, the intrinsic Delaunay triangulation of the input metric (the
/// same flat surface, reached by isometric flips); T', the final triangulation (reached from T1
/// by Ptolemy flips, with the final lengths). The map from the input surface to the plane is:
/// the identity from T0 to T1 (one flat surface); from each T1 triangle to the ideal hyperbolic
/// triangle whose Klein model is the triangle in its circumscribed disk; from there into the T'
/// triangle that holds the point, again through the Klein model; and the layout of T' into the
/// plane. In homogeneous coordinates every step is linear: a triangle's corners lifted to the
/// light cone by its decoration (Penner's lambda lengths, lambda = 2 log l) give homogeneous
/// barycentric coordinates equal to the Euclidean ones; across an edge ab with apexes c and d,
/// v_d = (l_bd l_cd / (l_ac l_ab)) v_a + (l_ad l_cd / (l_bc l_ab)) v_b - (l_ad l_bd / (l_ac l_bc))
/// v_c with l_cd Ptolemy's diagonal; and vertex scaling by u multiplies the lift of vertex i by
/// e^{u_i}, so that within one triangle the map is diag(e^{-u_i}) in homogeneous barycentric
/// coordinates (it takes the triangle's circumcircle to the scaled triangle's). The map is
/// therefore projective on every piece where one T1 triangle and one T' triangle overlap, and the
/// refinement is cut along T0, T1 and T' so that each of its triangles lies in one triangle of
/// each: interpolating the homogeneous texture coordinates (w u, w v, w) linearly over a
/// refinement triangle and dividing by w gives the map exactly. (Across a T1 edge the map bends,
/// so T0 and T' alone would not do; CEPS slices T1's triangles the same way.)
///
/// Combinatorics are exact: the flip log is replayed with labelled normal coordinates
/// (ricci/intrinsic/edge_overlay.hpp), once for T0 over T1 (isometric flips: straight lines in the
/// flat metric) and once for T1 over T' (Ptolemy flips: geodesics of the ideal hyperbolic
/// surface); transposed, the second gives the T' edges over T1. Inside each T1 triangle the T0
/// edges and the T' edges are straight chords; whether two chords cross is read from the order of
/// their ends around the triangle, never from coordinates. Geometry then places the points: T0
/// edges developed in the flat metric along the T1 triangles they cross, T' edges developed in
/// the light cone along theirs, chord intersections in barycentric coordinates of the T1
/// triangle. The texture coordinates of each input face come from laying its refinement pieces
/// out in the final metric, fitted to where the default output (ParamResult::uv) puts its
/// corners; seams follow the same cut.

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "ricci/mesh/topology.hpp"
#include "ricci/param/parameterize.hpp"

namespace ricci {

/// Options of common_refinement.
struct CommonRefinementOptions {
  /// Build the interpolation matrix (rows of barycentric weights of the refinement's vertices in
  /// the input triangulation); its rows also give the refinement's positions, which are built
  /// either way.
  bool interpolation_matrix = true;
};

/// The common refinement of the input, its intrinsic Delaunay triangulation and the final
/// intrinsic triangulation, with the exact map to the plane.
struct CommonRefinement {
  /// #R by 3 positions on the input surface. The first #V rows are the input's vertices (the
  /// mesh parameterized, ParamResult::mesh) in their order; then the points where an input edge
  /// crosses a Delaunay edge, where a Delaunay edge crosses a final edge, and where an input edge
  /// crosses a final edge inside a Delaunay triangle.
  Eigen::Matrix<double, Eigen::Dynamic, 3> positions;
  Triangles triangles;             ///< #T by 3, counter-clockwise as the input faces
  std::vector<int> input_face;     ///< #T: the input face (mesh.triangles row) holding it
  std::vector<int> delaunay_face;  ///< #T: the face of delaunay_topology holding it
  /// #T: the face of the final triangulation holding it (ParamResult::flow.topology, or see
  /// `doubled`)
  std::vector<int> intrinsic_face;
  /// #V: the refinement vertex of each input vertex (the identity: they come first)
  std::vector<int> input_vertex;
  /// #R by #V: row r holds the barycentric (or edge) weights of vertex r in the input face (or
  /// edge) it lies on; rows sum to 1 and interpolation * mesh.positions = positions. Multiply
  /// per-vertex data of the input by it to carry them onto the refinement. Empty when
  /// CommonRefinementOptions::interpolation_matrix is false.
  Eigen::SparseMatrix<double, Eigen::RowMajor> interpolation;

  /// Linear texture coordinates in ParamResult::uv's unit square, #UV by 2, indexed per corner by
  /// uv_triangles. The first rows are ParamResult::uv itself (the input vertices' copies, where
  /// the default output puts them); seams follow ParamResult::cut.
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv;
  Triangles uv_triangles;  ///< #T by 3
  /// 3#T by 3: row 3 t + k holds corner k of triangle t in homogeneous coordinates (w u, w v, w),
  /// (u, v) = uv at that corner and w > 0 scaled so that each triangle's largest w is 1.
  /// Interpolated linearly over the triangle in 3D and divided by the third component they give
  /// the exact (projective) map; divided at the corners they give the linear uv.
  Eigen::Matrix<double, Eigen::Dynamic, 3> projective_uv;
  /// 3#T by 3: barycentric coordinates of each corner in its Delaunay face (corners in
  /// delaunay_topology.triangles order) and in its intrinsic face (flow.topology order).
  Eigen::Matrix<double, Eigen::Dynamic, 3> delaunay_barycentric, intrinsic_barycentric;

  /// T1: the input after the isometric flips of the flip log, and its edge lengths.
  Topology delaunay_topology;
  Eigen::VectorXd delaunay_lengths;
  /// The flow ran on the mesh glued to its mirror image along the boundary
  /// (ComponentFlow::doubled): delaunay_topology, delaunay_face and intrinsic_face then refer to
  /// that doubled surface (its final triangulation is the component's flow.intrinsic.topology()),
  /// whose first #F faces are the mesh's; the refinement is that of the mesh's half.
  bool doubled = false;

  // Figures.
  int isometric_flips = 0;            ///< flips from T0 to T1
  int ptolemy_flips = 0;              ///< flips from T1 to T'
  int input_delaunay_points = 0;      ///< input edge x Delaunay edge crossings
  int delaunay_intrinsic_points = 0;  ///< Delaunay edge x final edge crossings
  int interior_points = 0;            ///< input edge x final edge, inside Delaunay triangles
  /// Largest relative difference, over final edges, between the edge's final length and the sum
  /// of the uv distances (divided by ParamResult::uv_scale) between the refinement vertices along
  /// it (of a doubled surface, over the final edges that stay in the mesh's half).
  double max_intrinsic_length_error = 0;
  /// Largest distance, relative to the face's longest uv edge, between an input face's corners
  /// as its refinement pieces develop them and where the default layout puts them (before the
  /// corners are set to the latter).
  double max_corner_mismatch = 0;
  /// Largest relative difference between the final lengths and the Ptolemy flips of the
  /// Delaunay lengths scaled by e^{(u_i + u_j) / 2} (how well MeshFlowResult::lengths and u
  /// agree with the flip log).
  double max_metric_mismatch = 0;
  /// Largest relative difference between an input edge's 3D length and its length developed
  /// over the Delaunay triangles it crosses.
  double max_development_error = 0;
  int degenerate_triangles = 0;  ///< zero 3D area (chords through one point, up to rounding)
  int inverted_triangles = 0;    ///< uv signed area <= 0 among the non-degenerate ones
  /// Crossing parameters moved back into the order the combinatorics fix (rounding near
  /// coincident crossings).
  int order_repairs = 0;
  double seconds = 0;
};

/// The common refinement of a vertex-scaling parameterization (see the file comment).
/// \param param a converged result of parameterize with Scheme::VertexScaling (edge flips or
///        not; without flips the refinement is the input, with projective weights e^{-u}; a flow
///        run on the doubled surface is refined there and cut back to the mesh's half)
/// \throw InvalidInput when the result did not converge, its scheme is not vertex scaling, or its
///        flip log does not reproduce its triangulation; SolverError on an internal
///        inconsistency (a bug)
CommonRefinement common_refinement(const Parameterization& param,
                                   const CommonRefinementOptions& options = {});

/// The same on what parameterize returns.
/// \throw InvalidInput also when it covers several components (take the refinement of each
///        one's own result, components[c].param)
CommonRefinement common_refinement(const MeshParamResult& param,
                                   const CommonRefinementOptions& options = {});

}  // namespace ricci
