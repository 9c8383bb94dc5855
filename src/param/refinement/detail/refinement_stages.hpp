#pragma once
/// \file
/// The stages of common_refinement (internal), in the order it runs them over one Context
/// (param/refinement/detail/refinement_support.hpp); declared here so that each is tested on its
/// own (tests/param/refinement/refinement_stages_test.cpp). Stage n fills what stage n + 1 reads;
/// common_refinement.cpp says what each one does.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "param/refinement/detail/refinement_support.hpp"
#include "ricci/intrinsic/edge_overlay.hpp"
#include "ricci/param/refinement/common_refinement.hpp"

namespace ricci::refinement_support {

/// The flow the refinement replays: the mesh parameterized with the whole-mesh flip log, or,
/// when the flow ran on the mesh glued to its mirror image (ComponentFlow::doubled), that
/// doubled surface with its own log; its first front_faces faces are the mesh's.
struct FlowInput {
  Mesh mesh;
  Topology base_topology;  // the mesh's connectivity before any flip
  std::vector<int> flipped_edges;
  std::vector<char> flip_is_isometric;
  Topology final_topology;
  Eigen::VectorXd final_lengths, u;
  int front_faces = 0;
  bool doubled = false;
};

/// The flow of a one-component result (see FlowInput).
/// \throw InvalidInput when a component flowed on its double in a mesh of several components
FlowInput flow_input(const Parameterization& param);

/// 1. The flip log split: the isometric flips (T0 -> T1) and the Ptolemy flips (T1 -> T'), each
/// in log order.
struct FlipLogSplit {
  std::vector<int> isometric, ptolemy;
};
/// \throw InvalidInput when a flip names no edge of t0, or an isometric flip comes after a
///        Ptolemy flip of its component
FlipLogSplit split_flip_log(const Topology& t0, const std::vector<int>& flipped_edges,
                            const std::vector<char>& flip_is_isometric);

/// 2. Replays the log with labelled normal coordinates (replay_flips_with_overlay): sets c.t1,
/// c.l1 and c.o01 (T0 over T1), c.tp and c.final_shapes, and result.max_metric_mismatch.
/// \return T1's edges over T' (to be traced and transposed by trace_overlays)
/// \throw InvalidInput when the log does not reproduce final_topology
EdgeOverlay replay_flip_log(Context& c, const FlipLogSplit& log, const Topology& final_topology,
                            const Eigen::VectorXd& final_lengths, CommonRefinement& result);

/// The paths the crossings are placed along.
struct RefinementPaths {
  std::vector<CurvePath> input;  ///< #E of T0: the input edges over T1
  std::vector<CurvePath> final;  ///< #E of T': the final edges over T1
};

/// 2 (continued). Traces the input edges over T1 and the final edges over T1 (c.oT, the
/// transpose of delaunay_over_final).
/// \throw SolverError when the two overlays disagree
RefinementPaths trace_overlays(Context& c, const EdgeOverlay& delaunay_over_final);

/// 3. Where each input edge and each final edge crosses each Delaunay edge (c.a_s, c.a_tau,
/// c.b_s, c.b_final; result.max_development_error), every list then repaired into the order the
/// combinatorics fix (result.order_repairs).
void place_crossings(Context& c, const RefinementPaths& paths, CommonRefinement& result);

/// 4. Where the final edges leave each vertex, per Delaunay corner (c.b_arcs, c.departures).
void find_departures(Context& c);

/// 5. The points on the Delaunay edges, in order along each (c.ports, c.segment_offset): their
/// refinement vertices, rows over the input and places in the final triangulation.
void place_edge_points(Context& c);

/// 6. Every Delaunay face sliced (slice_delaunay_face); of a doubled surface the pieces of the
/// front half kept.
struct SlicedFaces {
  std::vector<Piece> pieces;
  /// Per final edge, the refinement edges along it among all pieces, before the back half's
  /// are dropped (measure_refinement compares them with those kept).
  std::vector<int> on_final_all;
};
SlicedFaces slice_faces(Context& c, int front_faces, CommonRefinement& result);

/// 7. Numbers the refinement's vertices (the mesh's, then the points the pieces use, in the order
/// they were made), renames the pieces' corners and counts the points by kind.
/// \return per output vertex, its index in the Context (raw index)
std::vector<int> number_vertices(const Context& c, std::vector<Piece>& pieces,
                                 CommonRefinement& result);

/// 7 (continued). Positions from the rows, the interpolation matrix (when asked for) and the
/// triangles with their input, Delaunay and final faces and barycentric coordinates.
void write_vertices_and_pieces(const Context& c, const std::vector<int>& raw_of,
                               const std::vector<Piece>& pieces,
                               const CommonRefinementOptions& options, CommonRefinement& result);

/// 8. Each input face's pieces laid out in the final metric and fitted onto the face's corners
/// in `exact_uv` (result.max_corner_mismatch).
/// \return per piece, its corners in the layout's plane
std::vector<std::array<Complex, 3>> lay_out_pieces(
    const Context& c, const std::vector<Piece>& pieces, int front_faces,
    const Eigen::Matrix<double, Eigen::Dynamic, 2>& exact_uv, CommonRefinement& result);

/// 8 (continued). result.uv, uv_triangles and projective_uv: the input vertices' copies are
/// the layout's (exact_uv, in ParamResult::uv's square); points on a cut input edge get one copy
/// per side; others one.
void write_texture_coordinates(const Context& c, const std::vector<Piece>& pieces,
                               const std::vector<int>& raw_of,
                               const std::vector<std::array<Complex, 3>>& corner_uv,
                               int front_faces, bool polished,
                               const Eigen::Matrix<double, Eigen::Dynamic, 2>& exact_uv,
                               CommonRefinement& result);

/// 9. The figures of the output: degenerate and inverted triangles, and how well the uv
/// distances along each final edge add up to its final length.
void measure_refinement(const Context& c, const std::vector<Piece>& pieces,
                        const std::vector<int>& on_final_all, const Eigen::VectorXd& final_lengths,
                        CommonRefinement& result);

}  // namespace ricci::refinement_support
