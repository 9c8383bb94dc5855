#include "ricci/param/atlas/atlas.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ricci/errors.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/metric/scheme.hpp"
#include "ricci/param/cut/cut_graph.hpp"
#include "ricci/param/layout/layout.hpp"
#include "support/flat_layout.hpp"
#include "support/test_meshes.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;
using testing::uv_of;

/// A flattening with the affine atlas of its layout.
struct FlattenedWithAtlas : testing::Flattened {
  AffineAtlas atlas;
};

/// Flat metric of vertex scaling with cones (Newton to 1e-12, so that what the 1e-9 bounds
/// measure is the layout's rounding, not the metric's residual curvature), cut, slice, layout,
/// atlas.
FlattenedWithAtlas flatten_with_atlas(const Mesh& mesh, const std::vector<Cone>& cones = {}) {
  FlattenedWithAtlas f{testing::flatten(mesh, BoundaryMode::Free, cones, Scheme::VertexScaling),
                       {}};
  f.atlas = affine_atlas(f.flow.intrinsic.topology(), f.cut, f.cut_mesh, f.layout);
  return f;
}

Complex corner(const BoundaryChart& chart, std::size_t i, int k) {
  return {chart.corner_uv(static_cast<Eigen::Index>(i), 2 * k),
          chart.corner_uv(static_cast<Eigen::Index>(i), 2 * k + 1)};
}

/// Checks every chart of an atlas; `expect_unflipped` where no cone lies inside a chart.
void expect_valid_atlas(const FlattenedWithAtlas& f, bool expect_unflipped,
                        const std::string& what) {
  SCOPED_TRACE(what);
  const Topology& topology = f.flow.intrinsic.topology();
  const AffineAtlas& atlas = f.atlas;
  ASSERT_FALSE(f.cut.segments.empty());
  ASSERT_EQ(atlas.boundary_charts.size(), f.cut.segments.size());
  int one_rings_checked = 0;
  EXPECT_LE(atlas.max_transition_error, 1e-9);
  std::vector<char> is_node(topology.num_vertices, 0);
  for (int v : f.cut.nodes) is_node[v] = 1;

  for (std::size_t s = 0; s < atlas.boundary_charts.size(); ++s) {
    const BoundaryChart& chart = atlas.boundary_charts[s];
    const std::vector<int>& path = f.cut.segments[s];
    EXPECT_EQ(chart.segment, static_cast<int>(s));
    ASSERT_EQ(chart.side.size(), chart.faces.size());
    ASSERT_EQ(chart.corner_uv.rows(), static_cast<Eigen::Index>(chart.faces.size()));
    EXPECT_EQ(chart.rotation, f.layout.segment_transitions[s].rotation);
    EXPECT_LE(chart.max_gap, 1e-9);
    std::vector<int> index_of(topology.num_faces, -1);
    for (std::size_t i = 0; i < chart.faces.size(); ++i)
      index_of[chart.faces[i]] = static_cast<int>(i);

    for (std::size_t i = 0; i < chart.faces.size(); ++i) {
      const int face = chart.faces[i];
      for (int k = 0; k < 3; ++k) {
        // The chart's edges have the metric's lengths.
        const double l = f.flow.lengths[topology.face_edges(face, k)];
        EXPECT_NEAR(std::abs(corner(chart, i, (k + 1) % 3) - corner(chart, i, (k + 2) % 3)), l,
                    1e-9 * l)
            << "segment " << s << ", face " << face;
        // Side A is the central chart; side B is the central chart moved by the transition.
        Complex central = uv_of(f.layout, f.cut_mesh.triangles(face, k));
        if (chart.side[i]) central = chart.rotation * central + chart.translation;
        EXPECT_EQ(corner(chart, i, k), central);
      }
      if (expect_unflipped) {
        const Complex a = corner(chart, i, 0), b = corner(chart, i, 1), c = corner(chart, i, 2);
        EXPECT_GT(std::imag(std::conj(b - a) * (c - a)), 0.0)
            << "segment " << s << ", face " << face;
      }
    }

    // The two sides of every segment edge meet: the faces on either side are both in the chart,
    // on different sides, and put the edge's ends at the same points.
    for (std::size_t j = 0; j + 1 < path.size(); ++j) {
      int sides[2] = {-1, -1};  // chart index of the face holding v -> w, and w -> v
      for (int h = 0; h < 3 * topology.num_faces; ++h) {
        if (topology.tail(h) == path[j] && topology.head(h) == path[j + 1]) sides[0] = h;
        if (topology.tail(h) == path[j + 1] && topology.head(h) == path[j]) sides[1] = h;
      }
      ASSERT_GE(sides[0], 0);
      ASSERT_GE(sides[1], 0);
      const int i0 = index_of[sides[0] / 3], i1 = index_of[sides[1] / 3];
      ASSERT_GE(i0, 0) << "segment " << s << ": a face beside its edge is not in the chart";
      ASSERT_GE(i1, 0) << "segment " << s << ": a face beside its edge is not in the chart";
      EXPECT_NE(chart.side[i0], chart.side[i1]);
      const double l = f.flow.lengths[topology.halfedge_edge[sides[0]]];
      for (int v : {path[j], path[j + 1]}) {
        Complex p[2];
        for (int side = 0; side < 2; ++side) {
          const int face = sides[side] / 3, i = side ? i1 : i0;
          for (int k = 0; k < 3; ++k) {
            if (topology.triangles(face, k) == v)
              p[side] = corner(chart, static_cast<std::size_t>(i), k);
          }
        }
        EXPECT_LE(std::abs(p[0] - p[1]), 1e-9 * l) << "segment " << s << ", vertex " << v;
      }
    }

    // Around each vertex of the segment that is not a node, the chart holds the whole one-ring,
    // closed up in the plane: one point for the vertex, angles summing to 2 pi (no cone there).
    const bool closed = path.front() == path.back();
    for (std::size_t j = 0; j < path.size(); ++j) {
      const int v = path[j];
      if (is_node[v] || ((j == 0 || j + 1 == path.size()) && !closed)) continue;
      double angle_sum = 0;
      Complex first{0};
      bool have_first = false;
      int faces_around = 0;
      for (int face = 0; face < topology.num_faces; ++face) {
        for (int k = 0; k < 3; ++k) {
          if (topology.triangles(face, k) != v) continue;
          ++faces_around;
          const int i = index_of[face];
          ASSERT_GE(i, 0) << "segment " << s << ": face " << face << " around vertex " << v
                          << " is missing";
          const std::size_t ii = static_cast<std::size_t>(i);
          const Complex p = corner(chart, ii, k), q = corner(chart, ii, (k + 1) % 3),
                        r = corner(chart, ii, (k + 2) % 3);
          angle_sum += std::arg((r - p) / (q - p));
          if (!have_first) {
            first = p;
            have_first = true;
          }
          EXPECT_LE(std::abs(p - first), 1e-9) << "segment " << s << ", vertex " << v;
        }
      }
      ++one_rings_checked;
      EXPECT_EQ(faces_around, topology.vertex_degree[v]);
      EXPECT_NEAR(angle_sum, 2 * std::numbers::pi, 1e-8) << "segment " << s << ", vertex " << v;
    }
  }
  EXPECT_GT(one_rings_checked, 0);
}

TEST(Atlas, FlatTorusChartsAreTranslatedCopiesThatMeet) {
  const FlattenedWithAtlas f = flatten_with_atlas(make_torus(48, 20));
  ASSERT_EQ(f.layout.lattice.size(), 2u);
  expect_valid_atlas(f, true, "torus");
  for (const BoundaryChart& chart : f.atlas.boundary_charts) {
    EXPECT_LE(std::abs(chart.rotation - 1.0), 1e-9);
    EXPECT_NE(std::count(chart.side.begin(), chart.side.end(), 0), 0);
    EXPECT_NE(std::count(chart.side.begin(), chart.side.end(), 1), 0);
  }
}

TEST(Atlas, SphereWithFourAndEightCones) {
  // The cones are the cut tree's nodes (its leaves and branch points), never inside a chart's
  // one-rings; a chart's faces around a cone may overlap, so flips are only checked on the torus.
  const Mesh sphere = make_icosphere(3);
  const std::vector<Cone> four = testing::tetrahedron_cones(sphere);
  const std::vector<Cone> eight = testing::cube_cones(sphere);
  for (const auto& cones : {four, eight}) {
    const FlattenedWithAtlas f = flatten_with_atlas(sphere, cones);
    expect_valid_atlas(f, false, std::to_string(cones.size()) + " cones");
  }
}

TEST(Atlas, RejectsALayoutOfAnotherCut) {
  const FlattenedWithAtlas f = flatten_with_atlas(make_torus(12, 8));
  Layout other = f.layout;
  other.segment_transitions.pop_back();
  EXPECT_THROW(affine_atlas(f.flow.intrinsic.topology(), f.cut, f.cut_mesh, other), InvalidInput);
}

}  // namespace
}  // namespace ricci
