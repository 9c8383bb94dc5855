// Labelled normal coordinates through flips (ricci/intrinsic/edge_overlay.hpp): the input's edges
// tracked over its intrinsic Delaunay triangulation cross exactly the edges that straight lines
// cross, in the same order; transposing twice gives the overlay back; a flip undone leaves
// nothing.
#include <algorithm>
#include <cmath>
#include <complex>

#include <gtest/gtest.h>

#include "isometric_flips_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/intrinsic/edge_overlay.hpp"
#include "ricci/intrinsic/intrinsic_triangulation.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/metric/scheme.hpp"
#include "ricci/numerics/complex.hpp"
#include "support/hard_meshes.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;

struct Tracked {
  Topology input, host;
  Eigen::VectorXd input_lengths, lengths;
  std::vector<int> flips;
  EdgeOverlay overlay;
};

/// Flips the mesh's metric isometrically to Delaunay, then replays the flips with the overlay.
Tracked track(const Mesh& mesh) {
  const testing::Flipped f = testing::flip_isometrically(mesh);
  Tracked r;
  r.input = f.input;
  r.input_lengths = f.input_lengths;
  r.lengths = f.lengths;
  r.flips = f.flips.flipped_edges;
  r.host = r.input;
  r.overlay = identity_overlay(r.host);
  for (int e : r.flips) flip_edge_with_overlay(r.host, r.overlay, e);
  EXPECT_EQ(r.host.triangles, f.flipped.triangles);
  EXPECT_EQ(r.host.face_edges, f.flipped.face_edges);
  return r;
}

/// Develops every traced curve along its faces and checks that the straight segment between
/// its developed ends crosses the recorded sides, in the recorded order, and has the curve's
/// length; and that the crossings along every host edge come in the recorded order.
void expect_straight_lines(const Tracked& r) {
  const FaceShapes shapes = face_shapes_from_lengths(r.host, r.lengths);
  const std::vector<CurvePath> paths = trace_curves(r.host, r.overlay);
  ASSERT_EQ(static_cast<int>(paths.size()), r.input.num_edges);
  // Parameter of each crossing along its host edge, from the tail of its halfedge 0.
  std::vector<std::vector<double>> along(static_cast<std::size_t>(r.host.num_edges));
  for (int e = 0; e < r.host.num_edges; ++e) along[e].assign(r.overlay.crossings[e].size(), -1);
  int crossings = 0;
  double worst_length = 0;
  for (int c = 0; c < r.input.num_edges; ++c) {
    const CurvePath& p = paths[c];
    const int h = r.input.edge_halfedges(c, 0);
    if (p.coincident_halfedge >= 0) {
      EXPECT_EQ(r.host.tail(p.coincident_halfedge), r.input.tail(h));
      EXPECT_EQ(r.host.head(p.coincident_halfedge), r.input.head(h));
      continue;
    }
    EXPECT_EQ(r.host.triangles(p.start_face, p.start_corner), r.input.tail(h));
    EXPECT_EQ(r.host.triangles(p.end_face, p.end_corner), r.input.head(h));
    // Develop: each face placed by the rigid motion that glues it to the previous one.
    std::array<Complex, 3> face = shapes[p.start_face];
    int current = p.start_face;
    const Complex start = face[p.start_corner];
    std::vector<std::pair<Complex, Complex>> sides;
    for (const CurveCrossing& x : p.crossings) {
      const int k = x.halfedge % 3;
      ASSERT_EQ(x.halfedge / 3, current);
      const Complex a = face[(k + 1) % 3], b = face[(k + 2) % 3];
      sides.emplace_back(a, b);
      const int twin = r.host.halfedge_twin[x.halfedge], f2 = twin / 3, k2 = twin % 3;
      const auto& s2 = shapes[f2];
      // twin runs b -> a in f2.
      const Complex b2 = s2[(k2 + 1) % 3], a2 = s2[(k2 + 2) % 3];
      Complex rot = (b - a) / (b2 - a2);
      rot /= std::abs(rot);
      for (int j = 0; j < 3; ++j) face[j] = a + rot * (s2[j] - a2);
      current = f2;
    }
    ASSERT_EQ(current, p.end_face);
    const Complex end = face[p.end_corner];
    worst_length = std::max(
        worst_length, std::abs(std::abs(end - start) - r.input_lengths[c]) / r.input_lengths[c]);
    double previous = 0;
    for (std::size_t i = 0; i < sides.size(); ++i) {
      const auto [a, b] = sides[i];
      const double s = cross(start - a, end - start) / cross(b - a, end - start);
      const double t = cross(a - start, b - a) / cross(end - start, b - a);
      EXPECT_GT(s, -1e-9) << "curve " << c;
      EXPECT_LT(s, 1 + 1e-9) << "curve " << c;
      EXPECT_GE(t, previous - 1e-9) << "curve " << c;
      previous = t;
      const CurveCrossing& x = p.crossings[i];
      const bool forward = x.halfedge == r.host.edge_halfedges(x.edge, 0);
      along[x.edge][x.index] = forward ? s : 1 - s;
      ++crossings;
    }
  }
  EXPECT_LT(worst_length, 1e-10);
  EXPECT_GT(crossings, 0);
  for (int e = 0; e < r.host.num_edges; ++e) {
    for (std::size_t j = 0; j < along[e].size(); ++j) {
      EXPECT_GE(along[e][j], 0) << "crossing not visited";
      if (j > 0) {
        EXPECT_GE(along[e][j], along[e][j - 1] - 1e-9) << "edge " << e;
      }
    }
  }
}

TEST(EdgeOverlay, InputEdgesOverTheDelaunayTriangulationOfACadFanAreStraight) {
  const Tracked r = track(testing::cad_strip(40, 0.01));
  EXPECT_GT(r.flips.size(), 40u);
  expect_straight_lines(r);
}

TEST(EdgeOverlay, InputEdgesOverTheDelaunayTriangulationOfAValence3SphereAreStraight) {
  const Tracked r = track(testing::icosphere_split_near_corners(1, 0.05));
  EXPECT_GT(r.flips.size(), 20u);
  expect_straight_lines(r);
}

TEST(EdgeOverlay, NormalCoordinatesCountTheCrossings) {
  const Tracked r = track(testing::cad_strip(20, 0.02));
  long total = 0;
  for (int e = 0; e < r.host.num_edges; ++e) {
    const int n = r.overlay.normal_coordinate(e);
    EXPECT_GE(n, -1);
    if (n < 0) {
      EXPECT_NE(r.overlay.coincident[e], 0);
    }
    total += std::max(n, 0);
  }
  // Every flip removes a curve or adds crossings; the strip's fans all end up crossed.
  EXPECT_GT(total, 20);
  for (int f = 0; f < r.host.num_faces; ++f) EXPECT_NO_THROW(face_arcs(r.host, r.overlay, f));
}

TEST(EdgeOverlay, TransposingTwiceGivesTheOverlayBack) {
  const Tracked r = track(testing::icosphere_split_near_corners(1, 0.1));
  const std::vector<CurvePath> paths = trace_curves(r.host, r.overlay);
  const EdgeOverlay t = transpose_overlay(r.host, r.overlay, paths, r.input);
  // The host's edges as curves over the input are straight there too; trace them.
  const std::vector<CurvePath> back_paths = trace_curves(r.input, t);
  const EdgeOverlay back = transpose_overlay(r.input, t, back_paths, r.host);
  EXPECT_EQ(back.crossings, r.overlay.crossings);
  EXPECT_EQ(back.coincident, r.overlay.coincident);
  // Entry j of the transposed list of curve c is the crossing paths[c].crossings[j].
  for (int c = 0; c < r.input.num_edges; ++c) {
    for (std::size_t j = 0; j < paths[c].crossings.size(); ++j) {
      EXPECT_EQ(std::abs(t.crossings[c][j]) - 1, paths[c].crossings[j].edge);
    }
  }
}

TEST(EdgeOverlay, AFlipUndoneLeavesEveryEdgeItsOwnCurve) {
  const Mesh sphere = make_icosphere(1);
  Topology host = build_topology(sphere.triangles, sphere.num_vertices());
  EdgeOverlay o = identity_overlay(host);
  flip_edge_with_overlay(host, o, 7);
  EXPECT_EQ(o.coincident[7], 0);
  EXPECT_EQ(o.crossings[7].size(), 1u);  // the new diagonal crosses the old one
  flip_edge_with_overlay(host, o, 7);
  for (int e = 0; e < host.num_edges; ++e) {
    EXPECT_EQ(std::abs(o.coincident[e]), e + 1);
    EXPECT_TRUE(o.crossings[e].empty());
  }
  EXPECT_THROW(flip_edge_with_overlay(host, o, host.num_edges), InvalidInput);
}

}  // namespace
}  // namespace ricci
