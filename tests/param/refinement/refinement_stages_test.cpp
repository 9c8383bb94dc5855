// The stages of common_refinement one by one (param/refinement/detail/refinement_stages.hpp),
// each against its own contract, on a valence-3 sphere with strong cones whose flow flips both
// ways (isometric flips to its Delaunay triangulation, Ptolemy flips during the flow): the flip
// log split, the replay, the crossings placed, the departures, the points on the Delaunay edges,
// the pieces, the vertices numbered, the layout and the figures.
#include "param/refinement/detail/refinement_stages.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include <gtest/gtest.h>
#include <Eigen/LU>

#include "ricci/errors.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/metric/lengths.hpp"
#include "support/hard_meshes.hpp"

namespace ricci::refinement_support {
namespace {

/// Every stage run in order, with what each one handed on (the Context refers to the mesh, the
/// result and u held here, so the object stays where it was made).
struct Stages {
  MeshParamResult param;
  FlowInput flow;
  std::unique_ptr<Context> c;
  CommonRefinement result;
  FlipLogSplit log;
  EdgeOverlay delaunay_over_final;
  RefinementPaths paths;
  std::size_t edge_points = 0;  // refinement vertices after place_edge_points
  SlicedFaces sliced;
  std::vector<Piece> all_pieces;  // before number_vertices renames the corners
  std::vector<int> raw_of;
  Eigen::Matrix<double, Eigen::Dynamic, 2> exact_uv;
  std::vector<std::array<Complex, 3>> corner_uv;
};

const Stages& stages() {
  static const std::unique_ptr<Stages> made = [] {
    auto s = std::make_unique<Stages>();
    ParamOptions options;
    options.structure.scheme = Scheme::VertexScaling;
    options.cone_mode = ConeMode::User;
    options.cones = {
        {0, 1.5 * std::numbers::pi}, {5, 1.5 * std::numbers::pi}, {20, std::numbers::pi}};
    options.flow.tolerance = 1e-12;
    s->param = parameterize(testing::icosphere_split_near_corners(1, 0.05), options);
    s->flow = flow_input(s->param);
    s->c = std::make_unique<Context>(s->flow.mesh, s->param, s->flow.u);
    Context& c = *s->c;
    c.t0 = s->flow.base_topology;
    c.l0 = input_edge_lengths(s->flow.mesh, c.t0);
    s->log = split_flip_log(c.t0, s->flow.flipped_edges, s->flow.flip_is_isometric);
    s->delaunay_over_final =
        replay_flip_log(c, s->log, s->flow.final_topology, s->flow.final_lengths, s->result);
    s->paths = trace_overlays(c, s->delaunay_over_final);
    place_crossings(c, s->paths, s->result);
    find_departures(c);
    place_edge_points(c);
    s->edge_points = c.rows.size();
    s->sliced = slice_faces(c, s->flow.front_faces, s->result);
    s->all_pieces = s->sliced.pieces;
    s->raw_of = number_vertices(c, s->sliced.pieces, s->result);
    write_vertices_and_pieces(c, s->raw_of, s->sliced.pieces, {}, s->result);
    // As common_refinement: the flat metric's own positions, from before the angle polish.
    const bool polished = s->param.polish.moved_vertices > 0;
    s->exact_uv = polished ? s->param.polish.uv : s->param.layout.uv;
    s->corner_uv = lay_out_pieces(c, s->sliced.pieces, s->flow.front_faces, s->exact_uv, s->result);
    write_texture_coordinates(c, s->sliced.pieces, s->raw_of, s->corner_uv, s->flow.front_faces,
                              polished, s->exact_uv, s->result);
    measure_refinement(c, s->sliced.pieces, s->sliced.on_final_all, s->flow.final_lengths,
                       s->result);
    return s;
  }();
  return *made;
}

TEST(RefinementStages, TheFlowFlipsBothWays) {
  const Stages& s = stages();
  ASSERT_TRUE(s.param.converged) << s.param.message;
  EXPECT_GT(s.log.isometric.size(), 50u);
  EXPECT_GT(s.log.ptolemy.size(), 5u);
}

TEST(RefinementStages, SplitFlipLogKeepsTheLogOrderAndRefusesIsometricFlipsAfterPtolemy) {
  const Mesh mesh = make_icosphere(1);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  const FlipLogSplit log = split_flip_log(t, {4, 7, 2, 9}, {1, 1, 0, 0});
  EXPECT_EQ(log.isometric, (std::vector<int>{4, 7}));
  EXPECT_EQ(log.ptolemy, (std::vector<int>{2, 9}));
  // One component: an isometric flip after a Ptolemy flip breaks T0 -> T1 -> T'.
  EXPECT_THROW(split_flip_log(t, {4, 2, 7}, {1, 0, 1}), InvalidInput);
  EXPECT_THROW(split_flip_log(t, {t.num_edges}, {1}), InvalidInput);
  EXPECT_THROW(split_flip_log(t, {-1}, {0}), InvalidInput);
}

TEST(RefinementStages, ReplayReproducesTheFinalTriangulationAndItsMetric) {
  const Stages& s = stages();
  const Context& c = *s.c;
  EXPECT_EQ(c.tp.triangles, s.flow.final_topology.triangles);
  EXPECT_EQ(c.tp.face_edges, s.flow.final_topology.face_edges);
  // T1 is the input metric retriangulated: its lengths are the isometric flips' own.
  EXPECT_EQ(c.t1.triangles, replay_flips(c.t0, s.log.isometric).triangles);
  EXPECT_EQ(c.l1.size(), c.t0.num_edges);
  // Ptolemy's lengths of T1 scaled by e^{(u_i + u_j) / 2} are the flow's final lengths.
  EXPECT_LT(s.result.max_metric_mismatch, 1e-9);
  EXPECT_EQ(c.final_shapes.size(), static_cast<std::size_t>(c.tp.num_faces));
  // A log that does not lead to the final triangulation is refused.
  Context other(s.flow.mesh, s.param, s.flow.u);
  other.t0 = c.t0;
  other.l0 = c.l0;
  CommonRefinement scratch;
  EXPECT_THROW(replay_flip_log(other, s.log, c.t0, s.flow.final_lengths, scratch), InvalidInput);
}

TEST(RefinementStages, TracedPathsMatchTheOverlays) {
  const Stages& s = stages();
  const Context& c = *s.c;
  ASSERT_EQ(s.paths.input.size(), static_cast<std::size_t>(c.t0.num_edges));
  ASSERT_EQ(s.paths.final.size(), static_cast<std::size_t>(c.tp.num_edges));
  // Each path visits exactly the entries of its curve in the overlay's lists.
  std::size_t input_crossings = 0, final_crossings = 0, listed_a = 0, listed_b = 0;
  for (int e = 0; e < c.t0.num_edges; ++e) {
    for (const CurveCrossing& x : s.paths.input[e].crossings) {
      EXPECT_EQ(std::abs(c.o01.crossings[x.edge][x.index]), e + 1);
      ++input_crossings;
    }
  }
  for (int e = 0; e < c.tp.num_edges; ++e) {
    for (const CurveCrossing& x : s.paths.final[e].crossings) {
      EXPECT_EQ(std::abs(c.oT.crossings[x.edge][x.index]), e + 1);
      ++final_crossings;
    }
  }
  for (int e = 0; e < c.t1.num_edges; ++e) {
    listed_a += c.o01.crossings[e].size();
    listed_b += c.oT.crossings[e].size();
  }
  EXPECT_EQ(input_crossings, listed_a);
  EXPECT_EQ(final_crossings, listed_b);
  EXPECT_GT(final_crossings, 0u);
}

TEST(RefinementStages, CrossingsLieOnTheirEdgesInOrder) {
  const Stages& s = stages();
  const Context& c = *s.c;
  // The input edges developed over T1 keep their 3D lengths (T0 -> T1 is an isometry).
  EXPECT_LT(s.result.max_development_error, 1e-12);
  for (int e = 0; e < c.t1.num_edges; ++e) {
    EXPECT_TRUE(std::is_sorted(c.a_s[e].begin(), c.a_s[e].end())) << e;
    EXPECT_TRUE(std::is_sorted(c.b_s[e].begin(), c.b_s[e].end())) << e;
    for (double x : c.a_s[e]) EXPECT_TRUE(x >= 0 && x <= 1);
    for (double x : c.b_s[e]) EXPECT_TRUE(x >= 0 && x <= 1);
    for (const FinalEdgePoint& p : c.b_final[e]) {
      EXPECT_TRUE(p.s >= 0 && p.s <= 1);
      EXPECT_TRUE(std::isfinite(p.log_w));
    }
  }
  for (const CurvePath& p : s.paths.input) {
    double previous = 0;
    for (const CurveCrossing& x : p.crossings) {
      EXPECT_GE(c.a_tau[x.edge][x.index], previous);
      previous = c.a_tau[x.edge][x.index];
    }
  }
}

TEST(RefinementStages, DeparturesAreFinalCornersAtTheDelaunayCornersVertex) {
  const Stages& s = stages();
  const Context& c = *s.c;
  int departures = 0;
  for (int t = 0; t < c.t1.num_faces; ++t) {
    for (int k = 0; k < 3; ++k) {
      for (const auto& [face, corner] : c.departures[3 * t + k]) {
        EXPECT_EQ(c.tp.triangles(face, corner), c.t1.triangles(t, k));
        ++departures;
      }
    }
  }
  EXPECT_GT(departures, 0);
}

TEST(RefinementStages, EdgePointsHaveRowsOnTheInputAndPlacesInTheFinalTriangulation) {
  const Stages& s = stages();
  const Context& c = *s.c;
  const int nv = c.mesh.num_vertices();
  std::size_t crossings = 0;
  for (int e = 0; e < c.t1.num_edges; ++e) {
    crossings += c.a_s[e].size() + c.b_s[e].size();
    EXPECT_EQ(c.ports[e].size(), c.a_s[e].size() + c.b_s[e].size());
    for (std::size_t j = 0; j < c.a_vertex[e].size(); ++j) {
      const int v = c.a_vertex[e][j] - nv;
      ASSERT_GE(v, 0);
      EXPECT_EQ(c.kind[v], 0);
      // An input-edge crossing leans on the two ends of that input edge.
      const int curve = std::abs(c.o01.crossings[e][j]) - 1;
      EXPECT_EQ(c.on_input_edge[v], curve);
      ASSERT_EQ(c.rows[v].size(), 2u);
      EXPECT_EQ(c.rows[v][0].first, c.t0.tail(c.t0.edge_halfedges(curve, 0)));
      EXPECT_EQ(c.rows[v][1].first, c.t0.head(c.t0.edge_halfedges(curve, 0)));
    }
    for (std::size_t j = 0; j < c.b_vertex[e].size(); ++j) {
      const int v = c.b_vertex[e][j] - nv;
      ASSERT_GE(v, 0);
      EXPECT_EQ(c.kind[v], 1);
      EXPECT_EQ(c.on_final_edge[v].edge, std::abs(c.oT.crossings[e][j]) - 1);
    }
  }
  EXPECT_EQ(s.edge_points, crossings);
  for (std::size_t v = 0; v < s.edge_points; ++v) {
    double sum = 0;
    for (const auto& [u, w] : c.rows[v]) sum += w;
    EXPECT_NEAR(sum, 1, 1e-14);
    // Every point is on a final edge or inside a final face, with finite weight.
    const bool on_edge = c.on_final_edge[v].edge >= 0, in_face = c.in_final_face[v].face >= 0;
    EXPECT_TRUE(on_edge != in_face) << v;
    EXPECT_TRUE(std::isfinite(on_edge ? c.on_final_edge[v].log_w : c.in_final_face[v].log_w));
  }
}

TEST(RefinementStages, PiecesTileEveryDelaunayFace) {
  const Stages& s = stages();
  const Context& c = *s.c;
  // The pieces' areas in barycentric coordinates of their Delaunay face add up to the face.
  std::vector<double> covered(static_cast<std::size_t>(c.t1.num_faces), 0.0);
  for (const Piece& piece : s.all_pieces) {
    Eigen::Matrix3d b;
    for (int k = 0; k < 3; ++k) b.col(k) = piece.delaunay_bary[k];
    covered[piece.delaunay_face] += b.determinant();
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(piece.final_bary[k].sum(), 1, 1e-12);
  }
  for (int t = 0; t < c.t1.num_faces; ++t) EXPECT_NEAR(covered[t], 1, 1e-12) << t;
  // The mesh is closed: nothing is dropped, and every final edge is laid along by pieces.
  EXPECT_EQ(s.sliced.pieces.size(), s.all_pieces.size());
  for (int e = 0; e < c.tp.num_edges; ++e) EXPECT_GT(s.sliced.on_final_all[e], 0);
}

TEST(RefinementStages, VerticesAreTheMeshsThenTheUsedPointsInOrder) {
  const Stages& s = stages();
  const int nv = s.param.mesh.num_vertices();
  ASSERT_GE(s.raw_of.size(), static_cast<std::size_t>(nv));
  for (int v = 0; v < nv; ++v) EXPECT_EQ(s.raw_of[v], v);
  EXPECT_TRUE(std::is_sorted(s.raw_of.begin(), s.raw_of.end()));
  EXPECT_EQ(s.result.input_delaunay_points + s.result.delaunay_intrinsic_points +
                s.result.interior_points,
            static_cast<int>(s.raw_of.size()) - nv);
  for (std::size_t p = 0; p < s.all_pieces.size(); ++p) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(s.raw_of[s.sliced.pieces[p].vertex[k]], s.all_pieces[p].vertex[k]);
    }
  }
}

TEST(RefinementStages, PositionsComeFromTheRows) {
  const Stages& s = stages();
  const CommonRefinement& r = s.result;
  ASSERT_EQ(r.positions.rows(), static_cast<Eigen::Index>(s.raw_of.size()));
  const Eigen::MatrixX3d reproduced = r.interpolation * s.param.mesh.positions;
  EXPECT_LT((reproduced - r.positions).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(r.triangles.rows(), static_cast<Eigen::Index>(s.sliced.pieces.size()));
}

TEST(RefinementStages, PiecesLaidOutFitTheLayoutsCorners) {
  const Stages& s = stages();
  EXPECT_LT(s.result.max_corner_mismatch, 1e-9);
  // The input vertices' copies are the layout's, and the corners of the pieces sit on them.
  const CommonRefinement& r = s.result;
  const Eigen::Matrix<double, Eigen::Dynamic, 2> exact =
      (s.exact_uv.rowwise() - s.param.uv_offset.transpose()) * s.param.uv_scale;
  EXPECT_EQ(r.uv.topRows(s.param.uv.rows()), exact);
  const int nv = s.param.mesh.num_vertices();
  for (std::size_t p = 0; p < s.sliced.pieces.size(); ++p) {
    for (int k = 0; k < 3; ++k) {
      const double w = r.projective_uv(3 * static_cast<Eigen::Index>(p) + k, 2);
      EXPECT_TRUE(w > 0 && w <= 1);
      if (s.sliced.pieces[p].vertex[k] >= nv) continue;
      const Eigen::RowVector2d uv = r.uv.row(r.uv_triangles(static_cast<Eigen::Index>(p), k));
      const Complex z = s.corner_uv[p][k];
      const Eigen::RowVector2d fitted =
          (Eigen::RowVector2d(z.real(), z.imag()) - s.param.uv_offset.transpose()) *
          s.param.uv_scale;
      EXPECT_LT((fitted - uv).norm(), 1e-9);
    }
  }
}

TEST(RefinementStages, FiguresMeasureTheFinalLengthsAndTheOrientation) {
  const Stages& s = stages();
  EXPECT_LT(s.result.max_intrinsic_length_error, 1e-9);
  EXPECT_EQ(s.result.inverted_triangles, 0);
  EXPECT_EQ(s.result.degenerate_triangles, 0);
}

}  // namespace
}  // namespace ricci::refinement_support
