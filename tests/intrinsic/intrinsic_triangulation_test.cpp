// The correspondence between the input triangulation and the flipped one
// (ricci/intrinsic/intrinsic_triangulation.hpp): replaying the flips reproduces the triangulation,
// and undoing isometric flips gives back every input face with its own edge lengths, on ordinary
// meshes and on needle fans whose intrinsic Delaunay triangulation is a Delta-complex.
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "isometric_flips_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/intrinsic/intrinsic_triangulation.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/hyperbolic.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/metric/scheme.hpp"
#include "support/hard_meshes.hpp"
#include "support/topology_checks.hpp"

namespace ricci {
namespace {

using testing::flip_isometrically;
using testing::Flipped;

void expect_input_faces_recovered(const Mesh& mesh) {
  const Flipped f = flip_isometrically(mesh);
  ASSERT_GT(f.flips.flips, 0);
  EXPECT_EQ(count_non_delaunay_edges(f.flipped, f.lengths), 0);
  // Replay reproduces the flipped triangulation array for array.
  const Topology replayed = replay_flips(f.input, f.flips.flipped_edges);
  EXPECT_EQ(replayed.triangles, f.flipped.triangles);
  EXPECT_EQ(replayed.face_edges, f.flipped.face_edges);
  EXPECT_EQ(replayed.halfedge_twin, f.flipped.halfedge_twin);
  EXPECT_EQ(replayed.edge_vertices, f.flipped.edge_vertices);
  EXPECT_EQ(replayed.edge_halfedges, f.flipped.edge_halfedges);

  // Undoing isometric flips gives every input face back with its own lengths and orientation.
  const Development d = develop_input_faces(f.input, f.flips.flipped_edges, f.lengths);
  EXPECT_EQ(d.flipped_faces, 0);
  EXPECT_LT(d.max_length_mismatch, 1e-12);
  double worst = 0;
  for (int e = 0; e < f.input.num_edges; ++e) {
    worst = std::max(worst, std::abs(d.lengths[e] - f.input_lengths[e]) / f.input_lengths[e]);
  }
  EXPECT_LT(worst, 1e-11);
}

TEST(IntrinsicTriangulation, UndoingIsometricFlipsRecoversTheInputFacesOfAValence3Sphere) {
  expect_input_faces_recovered(testing::icosphere_split_near_corners(2, 0.05));
}

TEST(IntrinsicTriangulation, UndoingIsometricFlipsRecoversACadFan) {
  // Angles down to 0.006 degrees: the intrinsic Delaunay triangulation is the strip's zig-zag,
  // many flips away from the fans.
  const Mesh strip = testing::cad_strip(100, 0.01);
  expect_input_faces_recovered(strip);
  EXPECT_GT(flip_isometrically(strip).flips.flips, 100);
}

TEST(IntrinsicTriangulation, WithoutFlipsTheDevelopmentIsTheFacesThemselves) {
  const Mesh torus = make_torus(12, 6);
  const Topology t = build_topology(torus.triangles, torus.num_vertices());
  const Eigen::VectorXd l = input_edge_lengths(torus, t);
  const Development d = develop_input_faces(t, {}, l);
  const FaceShapes shapes = face_shapes_from_lengths(t, l);
  for (int f = 0; f < t.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(d.shapes[f][k], shapes[f][k]);
  }
  EXPECT_LT(d.max_length_mismatch, 1e-15);
}

TEST(IntrinsicTriangulation, ReplayRefusesAFlipItCannotMake) {
  const Mesh disk = make_disk(3);
  const Topology t = build_topology(disk.triangles, disk.num_vertices());
  int boundary_edge = -1;
  for (int e = 0; e < t.num_edges && boundary_edge < 0; ++e) {
    if (t.is_boundary_edge[e]) boundary_edge = e;
  }
  EXPECT_THROW(replay_flips(t, {boundary_edge}), InvalidInput);
  EXPECT_THROW(replay_flips(t, {t.num_edges}), InvalidInput);
}

TEST(IntrinsicTriangulation, EuclideanDiagonalOfASquareAndOfAKite) {
  // Unit square a(0,0) b(1,1) diagonal, c above, d below: the other diagonal has length sqrt 2.
  EXPECT_NEAR(euclidean_diagonal(std::sqrt(2.0), 1, 1, 1, 1), std::sqrt(2.0), 1e-15);
  // Kite a(0,0), b(2,0), c(1,3), d(1,-1): cd = 4.
  EXPECT_NEAR(
      euclidean_diagonal(2, std::sqrt(10.0), std::sqrt(10.0), std::sqrt(2.0), std::sqrt(2.0)), 4.0,
      1e-14);
}

// The common refinement's replay (replay_flips_with_overlay) and the flips share one kernel:
// replaying a flip log gives the flips' own topology and, bit for bit, their own lengths.
TEST(ReplayFlipsWithOverlay, ReproducesTheIsometricFlipsBitForBit) {
  const Mesh mesh = testing::icosphere_split_near_corners(1, 0.05);
  const Flipped f = flip_isometrically(mesh);
  ASSERT_GT(f.flips.flips, 0);
  const OverlaidReplay r = replay_flips_with_overlay(f.input, f.input_lengths,
                                                     f.flips.flipped_edges, FlipLength::Isometric);
  EXPECT_EQ(r.topology.triangles, f.flipped.triangles);
  EXPECT_EQ(r.topology.halfedge_twin, f.flipped.halfedge_twin);
  EXPECT_EQ(r.topology.edge_halfedges, f.flipped.edge_halfedges);
  EXPECT_EQ(r.lengths, f.lengths);
  // The input's edges over the result: an edge never flipped is its own curve; the curves of
  // the flipped ones cross the new edges.
  std::vector<char> flipped(static_cast<std::size_t>(f.input.num_edges), 0);
  for (int e : f.flips.flipped_edges) flipped[e] = 1;
  std::size_t crossings = 0;
  for (int e = 0; e < f.input.num_edges; ++e) {
    if (!flipped[e]) {
      EXPECT_NE(r.overlay.coincident[e], 0) << e;
    }
    crossings += r.overlay.crossings[e].size();
  }
  EXPECT_GT(crossings, 0u);
}

TEST(ReplayFlipsWithOverlay, ReproducesThePtolemyFlipsBitForBit) {
  const Mesh mesh = testing::icosphere_split_near_corners(1, 0.05);
  const Topology input = build_topology(mesh.triangles, mesh.num_vertices());
  const Eigen::VectorXd input_lengths = input_edge_lengths(mesh, input);
  StructureOptions vertex_scaling;
  vertex_scaling.scheme = Scheme::VertexScaling;
  ConformalStructure s = make_conformal_structure(input, input_lengths, vertex_scaling).structure;
  Topology t = input;
  Eigen::VectorXd l = input_lengths;
  const DelaunayFlipResult flips = flip_to_delaunay(t, s, s.initial_u, l);
  ASSERT_GT(flips.flips, 0);
  const OverlaidReplay r =
      replay_flips_with_overlay(input, input_lengths, flips.flipped_edges, FlipLength::Ptolemy);
  EXPECT_EQ(r.topology.triangles, t.triangles);
  EXPECT_EQ(r.lengths, l);
}

TEST(ReplayFlipsWithOverlay, RefusesAFlipItCannotMake) {
  const Mesh disk = make_disk(3);
  const Topology t = build_topology(disk.triangles, disk.num_vertices());
  const Eigen::VectorXd l = input_edge_lengths(disk, t);
  int boundary_edge = -1;
  for (int e = 0; e < t.num_edges && boundary_edge < 0; ++e) {
    if (t.is_boundary_edge[e]) boundary_edge = e;
  }
  EXPECT_THROW(replay_flips_with_overlay(t, l, {boundary_edge}, FlipLength::Isometric),
               InvalidInput);
  EXPECT_THROW(replay_flips_with_overlay(t, l, {t.num_edges}, FlipLength::Ptolemy), InvalidInput);
}

// ---- Hyperbolic metrics: the development in the Poincare disk ----

using WideComplex = std::complex<long double>;

/// Hyperbolic distance of two disk points, and the signed angle at p from q to r.
long double wide_disk_distance(WideComplex p, WideComplex q) {
  return 2 * std::atanh(std::abs((q - p) / (1.0L - std::conj(p) * q)));
}
long double disk_angle(WideComplex p, WideComplex q, WideComplex r) {
  const auto frame = [&](WideComplex z) { return (z - p) / (1.0L - std::conj(p) * z); };
  return std::arg(frame(r) / frame(q));
}

/// Vertex scaling in the hyperbolic background.
ConformalStructure hyperbolic_vertex_scaling(const Mesh& mesh, const Topology& t) {
  StructureOptions options;
  options.scheme = Scheme::VertexScaling;
  options.geometry = Geometry::Hyperbolic;
  return make_conformal_structure(t, input_edge_lengths(mesh, t), options).structure;
}

/// Undoes isometric hyperbolic flips: every input face comes back with its own hyperbolic
/// lengths (the scaled input lengths the structure reproduces) and orientation.
void expect_hyperbolic_input_faces_recovered(const Mesh& mesh, int min_flips) {
  const Topology input = build_topology(mesh.triangles, mesh.num_vertices());
  Topology t = input;
  ConformalStructure s = hyperbolic_vertex_scaling(mesh, t);
  Eigen::VectorXd input_lengths, l;
  ASSERT_EQ(edge_lengths(t, s, s.initial_u, input_lengths).invalid_edges, 0);
  l = input_lengths;
  DelaunayFlipOptions isometric;
  isometric.isometric = true;
  const DelaunayFlipResult r = flip_to_delaunay(t, s, s.initial_u, l, isometric);
  ASSERT_GE(r.flips, min_flips);
  EXPECT_EQ(count_non_delaunay_edges(t, l, 1e-12, Geometry::Hyperbolic), 0);
  const HyperbolicDevelopment d =
      develop_input_faces_hyperbolic(input, r.flipped_edges, l.cast<long double>());
  EXPECT_EQ(d.flipped_faces, 0);
  EXPECT_EQ(d.degenerate_faces, 0);
  EXPECT_LT(d.max_length_mismatch, 1e-12);
  double worst = 0;
  for (int e = 0; e < input.num_edges; ++e) {
    worst = std::max(
        worst, static_cast<double>(std::abs(d.lengths[e] - input_lengths[e]) / input_lengths[e]));
  }
  // The flipped lengths carry the rounding of double: relative 1e-15 per flip near the face.
  EXPECT_LT(worst, 1e-11);
}

TEST(IntrinsicTriangulation, UndoingHyperbolicIsometricFlipsRecoversTheInputFaces) {
  expect_hyperbolic_input_faces_recovered(testing::icosphere_split_near_corners(2, 0.05), 100);
  expect_hyperbolic_input_faces_recovered(testing::cad_strip(100, 0.01), 100);
}

TEST(IntrinsicTriangulation, HyperbolicDevelopmentAfterPtolemyFlipsKeepsTheVertexAngles) {
  // Ptolemy flips at smooth scale factors change the metric; the input faces developed in the
  // final one tile the same surface: around every vertex their angles add up to the final
  // triangulation's angle sum, and their areas to its area.
  const Mesh mesh = testing::icosphere_split_near_corners(2, 0.1);
  const Topology input = build_topology(mesh.triangles, mesh.num_vertices());
  Topology t = input;
  ConformalStructure s = hyperbolic_vertex_scaling(mesh, t);
  Eigen::VectorXd u(mesh.num_vertices()), l;
  for (int v = 0; v < u.size(); ++v) u[v] = 0.3 * std::sin(3 * mesh.positions(v, 0));
  ASSERT_EQ(edge_lengths(t, s, u, l).invalid_edges, 0);
  const DelaunayFlipResult r = flip_to_delaunay(t, s, u, l);
  ASSERT_GT(r.flips, 100);
  CornerAngles angles;
  ASSERT_EQ(corner_angles(t, l, angles, Geometry::Hyperbolic).first_bad_face, -1);
  const Eigen::VectorXd angle_sum = 2 * std::numbers::pi - vertex_curvature(t, angles).array();
  const HyperbolicDevelopment d =
      develop_input_faces_hyperbolic(input, r.flipped_edges, l.cast<long double>());
  EXPECT_LT(d.max_length_mismatch, 1e-12);
  Eigen::VectorXd developed_sum = Eigen::VectorXd::Zero(input.num_vertices);
  long double area = 0;
  for (int f = 0; f < input.num_faces; ++f) {
    const auto& p = d.shapes[f];
    long double face_angles = 0;
    for (int k = 0; k < 3; ++k) {
      const long double a = disk_angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
      developed_sum[input.triangles(f, k)] += static_cast<double>(a);
      face_angles += a;
    }
    area += std::numbers::pi_v<long double> - face_angles;
  }
  EXPECT_EQ(d.flipped_faces, 0);
  EXPECT_LT((developed_sum - angle_sum).cwiseAbs().maxCoeff(), 1e-12);
  const double final_area = hyperbolic_total_area(angles);
  EXPECT_NEAR(static_cast<double>(area), final_area, 1e-12 * final_area);
  // Each developed edge is a geodesic between the developed corners: its length from the shape.
  for (int e = 0; e < input.num_edges; e += 11) {
    const int h = input.edge_halfedges(e, 0);
    const auto& p = d.shapes[h / 3];
    EXPECT_NEAR(static_cast<double>(wide_disk_distance(p[(h % 3 + 1) % 3], p[(h % 3 + 2) % 3])),
                static_cast<double>(d.lengths[e]), 1e-15);
  }
}

TEST(IntrinsicTriangulation, WithoutFlipsTheHyperbolicDevelopmentIsTheFacesThemselves) {
  const Mesh mesh = make_closed_surface(2, 6);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  const ConformalStructure s = hyperbolic_vertex_scaling(mesh, t);
  Eigen::VectorXd l;
  ASSERT_EQ(edge_lengths(t, s, s.initial_u, l).invalid_edges, 0);
  const WideVector wide = l.cast<long double>();
  const HyperbolicDevelopment d = develop_input_faces_hyperbolic(t, {}, wide);
  const WideFaceShapes shapes = hyperbolic_face_shapes_from_lengths(t, wide);
  for (int f = 0; f < t.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(d.shapes[f][k], shapes[f][k]);
  }
  for (int e = 0; e < t.num_edges; ++e) {
    EXPECT_NEAR(static_cast<double>(d.lengths[e] / wide[e]), 1.0, 1e-15);
  }
  EXPECT_THROW(develop_input_faces_hyperbolic(t, {}, wide.head(3)), InvalidInput);
}

// The IntrinsicTriangulation type: copy-on-write, its log, the gathering of components, and
// the developments through it.

/// The input triangulation of a mesh with its vertex-scaling structure, as a type.
struct Input {
  Topology topology;
  ConformalStructure structure;
  Eigen::VectorXd lengths;
};

Input input_of(const Mesh& mesh) {
  Input in;
  in.topology = build_topology(mesh.triangles, mesh.num_vertices());
  in.lengths = input_edge_lengths(mesh, in.topology);
  StructureOptions vertex_scaling;
  vertex_scaling.scheme = Scheme::VertexScaling;
  in.structure = make_conformal_structure(in.topology, in.lengths, vertex_scaling).structure;
  return in;
}

using testing::expect_same_connectivity;

TEST(IntrinsicTriangulationType, CopiesTheInputOnlyAtTheFirstFlip) {
  DelaunayFlipOptions isometric;
  isometric.isometric = true;
  // Already Delaunay: the input object itself, throughout.
  const Input sphere = input_of(make_icosphere(2));
  IntrinsicTriangulation delaunay(sphere.topology, sphere.structure);
  EXPECT_EQ(&delaunay.topology(), &sphere.topology);
  Eigen::VectorXd l = sphere.lengths;
  EXPECT_EQ(delaunay.flip_to_delaunay(sphere.structure.initial_u, l, isometric).flips, 0);
  EXPECT_EQ(&delaunay.topology(), &sphere.topology);
  EXPECT_FALSE(delaunay.owns_topology());
  EXPECT_EQ(delaunay.flips(), 0);

  // Not Delaunay: its own copy once it flips; the input stays as it was.
  const Mesh mesh = testing::icosphere_split_near_corners(2, 0.05);
  const Input in = input_of(mesh);
  IntrinsicTriangulation t(in.topology, in.structure);
  EXPECT_EQ(&t.topology(), &in.topology);
  l = in.lengths;
  const DelaunayFlipResult r = t.flip_to_delaunay(in.structure.initial_u, l, isometric);
  ASSERT_GT(r.flips, 0);
  EXPECT_NE(&t.topology(), &in.topology);
  EXPECT_EQ(&t.input(), &in.topology);
  expect_same_connectivity(in.topology, build_topology(mesh.triangles, mesh.num_vertices()));
  EXPECT_EQ(t.flips(), r.flips);
  EXPECT_EQ(t.isometric_flips(), r.flips);

  // A copy shares the flipped connectivity until it flips itself.
  IntrinsicTriangulation copy = t;
  EXPECT_EQ(&copy.topology(), &t.topology());
  Eigen::VectorXd u(mesh.num_vertices()), lu;
  for (int v = 0; v < u.size(); ++v) u[v] = 3 * mesh.positions(v, 0);  // strong: flips again
  ASSERT_EQ(edge_lengths(copy.topology(), copy.structure(), u, lu).invalid_edges, 0);
  ASSERT_GT(copy.flip_to_delaunay(u, lu).flips, 0);
  EXPECT_NE(&copy.topology(), &t.topology());
  expect_same_connectivity(t.topology(), t.replayed());
  expect_same_connectivity(copy.topology(), copy.replayed());
  EXPECT_EQ(copy.isometric_flips(), t.flips());
  EXPECT_GT(copy.flips(), t.flips());
}

TEST(IntrinsicTriangulationType, FlipsAsTheFreeFunctionAndItsLogReplaysToItsTopology) {
  const Input in = input_of(testing::cad_strip(100, 0.01));
  DelaunayFlipOptions isometric;
  isometric.isometric = true;
  Topology flipped = in.topology;
  ConformalStructure s = in.structure;
  Eigen::VectorXd l_free = in.lengths;
  const DelaunayFlipResult free = flip_to_delaunay(flipped, s, s.initial_u, l_free, isometric);
  IntrinsicTriangulation t(std::make_shared<const Topology>(in.topology), in.structure);
  Eigen::VectorXd l = in.lengths;
  const DelaunayFlipResult r = t.flip_to_delaunay(in.structure.initial_u, l, isometric);
  ASSERT_GT(r.flips, 100);
  EXPECT_EQ(r.flipped_edges, free.flipped_edges);
  EXPECT_EQ(t.flipped_edges(), free.flipped_edges);
  EXPECT_EQ(t.blocked_flips(), free.blocked);
  EXPECT_EQ(l, l_free);
  EXPECT_EQ(t.eta(), s.eta);
  expect_same_connectivity(t.topology(), flipped);
  expect_same_connectivity(t.replayed(), flipped);
  EXPECT_EQ(t.is_simplicial(), is_simplicial(flipped));
}

TEST(IntrinsicTriangulationType, DevelopsTheInputFacesAsTheFreeFunctions) {
  const Mesh mesh = testing::icosphere_split_near_corners(2, 0.05);
  const Input in = input_of(mesh);
  IntrinsicTriangulation t(in.topology, in.structure);
  Eigen::VectorXd u(mesh.num_vertices()), l;
  for (int v = 0; v < u.size(); ++v) u[v] = 0.3 * std::sin(3 * mesh.positions(v, 0));
  ASSERT_EQ(edge_lengths(in.topology, in.structure, u, l).invalid_edges, 0);
  ASSERT_GT(t.flip_to_delaunay(u, l).flips, 0);
  const Development a = t.develop_input_faces(l);
  const Development b = develop_input_faces(in.topology, t.flipped_edges(), l);
  EXPECT_EQ(a.shapes, b.shapes);
  EXPECT_EQ(a.lengths, b.lengths);
  EXPECT_EQ(a.max_length_mismatch, b.max_length_mismatch);
  EXPECT_EQ(a.flipped_faces, b.flipped_faces);

  const WideVector wide = l.cast<long double>();
  const HyperbolicDevelopment ha = t.develop_input_faces_hyperbolic(wide * 0.01L);
  const HyperbolicDevelopment hb =
      develop_input_faces_hyperbolic(in.topology, t.flipped_edges(), wide * 0.01L);
  EXPECT_EQ(ha.shapes, hb.shapes);
  EXPECT_EQ(ha.lengths, hb.lengths);
}

TEST(IntrinsicTriangulationType, GatheredComponentsEqualTheirFlipsReplayedOnTheWholeMesh) {
  // Two copies of a mesh far from Delaunay, each flipped on its own topology (at different
  // scale factors), gathered into the whole mesh's triangulation.
  const Mesh one = testing::icosphere_split_near_corners(2, 0.05);
  Mesh two;
  two.positions.resize(2 * one.num_vertices(), 3);
  two.positions << one.positions, one.positions.array() + 3.0;
  two.triangles.resize(2 * one.num_faces(), 3);
  two.triangles << one.triangles, one.triangles.array() + one.num_vertices();
  const Input whole = input_of(two);
  ASSERT_EQ(whole.topology.components.size(), 2u);
  IntrinsicTriangulation gathered(whole.topology, whole.structure);
  std::vector<int> expected_log;
  for (int c = 0; c < 2; ++c) {
    const Component& comp = whole.topology.components[c];
    const Input part = input_of(one);
    // Faces keep their corner order: local halfedge 3 f + k is whole halfedge
    // 3 faces[f] + k, which gives the edge map; both meshes' edges start at the same halfedge.
    std::vector<int> edge_map(part.topology.num_edges);
    for (int e = 0; e < part.topology.num_edges; ++e) {
      const int h = part.topology.edge_halfedges(e, 0);
      const int hw = 3 * comp.faces[h / 3] + h % 3;
      edge_map[e] = whole.topology.halfedge_edge[hw];
      ASSERT_EQ(whole.topology.edge_halfedges(edge_map[e], 0), hw);
    }
    IntrinsicTriangulation t(part.topology, part.structure);
    Eigen::VectorXd u(one.num_vertices()), l;
    for (int v = 0; v < u.size(); ++v) u[v] = 0.2 * (c + 1) * std::cos(2 * one.positions(v, 1));
    ASSERT_EQ(edge_lengths(part.topology, part.structure, u, l).invalid_edges, 0);
    ASSERT_GT(t.flip_to_delaunay(u, l).flips, 0);
    for (int e : t.flipped_edges()) expected_log.push_back(edge_map[e]);
    gathered.gather_component(t, comp.faces, comp.vertices, edge_map);
  }
  EXPECT_EQ(gathered.flipped_edges(), expected_log);
  EXPECT_EQ(gathered.flips(), static_cast<int>(expected_log.size()));
  expect_same_connectivity(gathered.topology(), replay_flips(whole.topology, expected_log));
  // The whole input is untouched.
  expect_same_connectivity(whole.topology, build_topology(two.triangles, two.num_vertices()));
}

}  // namespace
}  // namespace ricci
