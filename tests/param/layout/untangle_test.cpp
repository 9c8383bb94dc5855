// Untangling a layout's flipped faces: the faces come out positive, seams stay congruent (the
// copies of a seam vertex move by the seam's rigid motion), cones, fixed vertices and the
// boundary keep their positions bit for bit, and nothing gets worse. Folds are made on purpose
// in layouts of generated meshes; every figure is measured here, independently of the untangler.

#include "ricci/param/layout/untangle.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/param/parameterize.hpp"
#include "support/uv_checks.hpp"

namespace ricci {
namespace {

using UV = Eigen::Matrix<double, Eigen::Dynamic, 2>;

double signed_area(const UV& uv, const Triangles& t, int f) {
  const Eigen::Vector2d a = uv.row(t(f, 0)).transpose();
  const Eigen::Vector2d b = uv.row(t(f, 1)).transpose() - a;
  const Eigen::Vector2d c = uv.row(t(f, 2)).transpose() - a;
  return b.x() * c.y() - b.y() * c.x();
}

using testing::count_flipped;

/// Largest relative difference between the two layout copies of an edge (over edges of two
/// faces): 0 inside a chart, the seam mismatch across a cut.
double seam_mismatch(const Mesh& mesh, const Triangles& t, const UV& uv) {
  std::map<std::pair<int, int>, std::vector<double>> lengths;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles(f, k), b = mesh.triangles(f, (k + 1) % 3);
      const double l = (uv.row(t(f, k)) - uv.row(t(f, (k + 1) % 3))).norm();
      lengths[{std::min(a, b), std::max(a, b)}].push_back(l);
    }
  }
  double worst = 0;
  for (const auto& [edge, l] : lengths) {
    if (l.size() == 2) worst = std::max(worst, std::abs(l[0] - l[1]) / std::max(l[0], l[1]));
  }
  return worst;
}

/// The layout vertices of each mesh vertex.
std::vector<std::set<int>> copies_of(const Mesh& mesh, const Triangles& t) {
  std::vector<std::set<int>> copies(mesh.num_vertices());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) copies[mesh.triangles(f, k)].insert(t(f, k));
  }
  return copies;
}

/// The flat metric's own layout (no polish), the seams' rigid motions exact.
MeshParamResult flat_layout(const Mesh& mesh, ConeMode cones = ConeMode::Needed) {
  ParamOptions options;
  options.cone_mode = cones;
  options.polish.enabled = false;
  MeshParamResult p = parameterize(mesh, options);
  EXPECT_TRUE(p.converged) << p.message;
  EXPECT_EQ(count_flipped(p.layout.uv, p.cut_mesh.triangles), 0);
  return p;
}

TEST(Untangle, AFoldedInteriorIsUntangledAndNothingElseMoves) {
  const Mesh grid = make_grid(12, 12);
  const MeshParamResult p = flat_layout(grid);
  UV uv = p.layout.uv;
  const Triangles& t = p.cut_mesh.triangles;
  // Vertex 6 * 13 + 6 (the grid's centre) pushed across three of its neighbours: its fan folds.
  const int centre = 6 * 13 + 6;
  const double h = 1.0 / 12;
  uv.row(centre) += Eigen::RowVector2d(2.6 * h, 1.7 * h);
  const int folded = count_flipped(uv, t);
  ASSERT_GE(folded, 2);
  const UntangleResult r = untangle_layout(p.mesh, t, uv);
  EXPECT_EQ(r.flipped_before, folded);
  EXPECT_EQ(r.flipped_after, 0);
  EXPECT_EQ(count_flipped(r.uv, t), 0);
  EXPECT_GT(r.moved_vertices, 0);
  // Only vertices within a few rings of the fold move; the boundary stays bit for bit.
  const Topology topology = build_topology(grid.triangles, grid.num_vertices());
  for (int v = 0; v < grid.num_vertices(); ++v) {
    const int ring = std::max(std::abs(v % 13 - 6), std::abs(v / 13 - 6));
    if (topology.is_boundary_vertex[v] || ring > 6) {
      EXPECT_EQ(r.uv(v, 0), uv(v, 0)) << v;
      EXPECT_EQ(r.uv(v, 1), uv(v, 1)) << v;
    }
  }
}

TEST(Untangle, ALayoutWithoutFoldsComesBackBitForBit) {
  const MeshParamResult p = flat_layout(make_torus(24, 12));
  const UntangleResult r = untangle_layout(p.mesh, p.cut_mesh.triangles, p.layout.uv);
  EXPECT_EQ(r.flipped_before, 0);
  EXPECT_EQ(r.rounds, 0);
  EXPECT_EQ(r.moved_vertices, 0);
  EXPECT_TRUE((r.uv.array() == p.layout.uv.array()).all());
}

TEST(Untangle, SeamVerticesMoveWithTheirCopiesAndTheSeamsStayCongruent) {
  // A flat torus: its copies across the two seams differ by translations (the lattice).
  const MeshParamResult p = flat_layout(make_torus(24, 12));
  const Triangles& t = p.cut_mesh.triangles;
  const std::vector<std::set<int>> copies = copies_of(p.mesh, t);
  UV uv = p.layout.uv;
  // A seam vertex with two copies (not a node): every copy pushed by the same offset, so the
  // seams stay congruent while the faces on both sides fold.
  int seam_vertex = -1;
  for (int v = 0; v < p.mesh.num_vertices() && seam_vertex < 0; ++v) {
    if (copies[v].size() == 2) seam_vertex = v;
  }
  ASSERT_GE(seam_vertex, 0);
  double shortest = INFINITY;
  for (int f = 0; f < t.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      shortest = std::min(shortest, (uv.row(t(f, k)) - uv.row(t(f, (k + 1) % 3))).norm());
    }
  }
  for (int c : copies[seam_vertex]) uv.row(c) += Eigen::RowVector2d(1.8, 1.1) * shortest;
  const double mismatch_before = seam_mismatch(p.mesh, t, uv);
  ASSERT_LT(mismatch_before, 1e-12);
  const int folded = count_flipped(uv, t);
  ASSERT_GE(folded, 1);
  UntangleOptions options;
  const UntangleResult r = untangle_layout(p.mesh, t, uv, options);
  EXPECT_EQ(r.flipped_after, 0);
  EXPECT_EQ(count_flipped(r.uv, t), 0);
  EXPECT_LT(seam_mismatch(p.mesh, t, r.uv), 1e-12);
  // The seam vertex itself had to move (its own faces folded around it).
  bool moved = false;
  for (int c : copies[seam_vertex]) moved = moved || (r.uv.row(c) - uv.row(c)).norm() > 0;
  EXPECT_TRUE(moved);
}

TEST(Untangle, ConesKeepTheirPositionsAndAngles) {
  // Genus 2 with its automatic cones: a vertex next to a cone pushed across the cone.
  const MeshParamResult p = flat_layout(make_closed_surface(2, 8));
  const Triangles& t = p.cut_mesh.triangles;
  ASSERT_FALSE(p.cones.empty());
  const std::vector<std::set<int>> copies = copies_of(p.mesh, t);
  const int cone = p.cones.front().vertex;
  // Vertices whose faces' vertices all have a single copy: away from every seam.
  std::vector<char> inside(p.mesh.num_vertices(), 1);
  for (int f = 0; f < t.rows(); ++f) {
    bool seam = false;
    for (int k = 0; k < 3; ++k) seam = seam || copies[p.mesh.triangles(f, k)].size() > 1;
    for (int k = 0; k < 3 && seam; ++k) inside[p.mesh.triangles(f, k)] = 0;
  }
  // Of those, the one nearest the cone (in the layout), pushed across the cone's copy: its fan
  // folds over the cone's.
  int n = -1, cone_copy = -1;
  double nearest = INFINITY;
  for (int f = 0; f < t.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (p.mesh.triangles(f, k) != cone) continue;
      for (int g = 0; g < t.rows(); ++g) {
        for (int j = 0; j < 3; ++j) {
          const int w = p.mesh.triangles(g, j);
          const double d = (p.layout.uv.row(t(g, j)) - p.layout.uv.row(t(f, k))).norm();
          if (inside[w] && d < nearest) nearest = d, n = t(g, j), cone_copy = t(f, k);
        }
      }
    }
  }
  ASSERT_GE(n, 0);
  UV uv = p.layout.uv;
  // Pushed across its neighbour nearest the cone: its fan folds, next to the cone's.
  int towards = -1;
  for (int f = 0; f < t.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (t(f, k) != n) continue;
      for (int j = 1; j < 3; ++j) {
        const int m = t(f, (k + j) % 3);
        if (towards < 0 ||
            (uv.row(m) - uv.row(cone_copy)).norm() < (uv.row(towards) - uv.row(cone_copy)).norm()) {
          towards = m;
        }
      }
    }
  }
  uv.row(n) += 2.5 * (uv.row(towards) - uv.row(n));
  ASSERT_GE(count_flipped(uv, t), 1);
  ASSERT_LT(seam_mismatch(p.mesh, t, p.layout.uv), 1e-10);
  ASSERT_LT(seam_mismatch(p.mesh, t, uv), 1e-10);
  const UntangleResult r = untangle_layout(p.mesh, t, uv);
  EXPECT_EQ(r.flipped_after, 0);
  for (const Cone& c : p.cones) {
    for (int copy : copies[c.vertex]) {
      EXPECT_EQ(r.uv(copy, 0), uv(copy, 0));
      EXPECT_EQ(r.uv(copy, 1), uv(copy, 1));
    }
  }
  EXPECT_LT(seam_mismatch(p.mesh, t, r.uv), 1e-10);
  // The cone angles, summed over every copy's wedge, are the flat metric's: 2 pi - K.
  std::vector<double> angle_sum(p.mesh.num_vertices(), 0);
  for (int f = 0; f < t.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d a = r.uv.row(t(f, k)).transpose();
      const Eigen::Vector2d b = r.uv.row(t(f, (k + 1) % 3)).transpose() - a;
      const Eigen::Vector2d c = r.uv.row(t(f, (k + 2) % 3)).transpose() - a;
      angle_sum[p.mesh.triangles(f, k)] += std::atan2(b.x() * c.y() - b.y() * c.x(), b.dot(c));
    }
  }
  for (const Cone& c : p.cones)
    EXPECT_NEAR(angle_sum[c.vertex], 2 * std::numbers::pi - c.curvature, 1e-9);
  for (int v = 0; v < p.mesh.num_vertices(); ++v) {
    bool is_cone = false;
    for (const Cone& c : p.cones) is_cone = is_cone || c.vertex == v;
    if (!is_cone) {
      EXPECT_NEAR(angle_sum[v], 2 * std::numbers::pi, 1e-9) << v;
    }
  }
}

TEST(Untangle, TheBoundaryStaysUnlessItMayMove) {
  // A grid's interior fold is untangled by interior vertices alone; its boundary stays.
  {
    const Mesh grid = make_grid(8, 8);
    const MeshParamResult p = flat_layout(grid);
    const Triangles& t = p.cut_mesh.triangles;
    UV uv = p.layout.uv;
    const int next_to_corner = 9 + 1;
    uv.row(next_to_corner) = -0.5 * uv.row(next_to_corner) + 1.5 * uv.row(0);
    ASSERT_GE(count_flipped(uv, t), 1);
    const UntangleResult r = untangle_layout(p.mesh, t, uv);
    EXPECT_EQ(r.flipped_after, 0);
    const Topology topology = build_topology(grid.triangles, grid.num_vertices());
    for (int v = 0; v < grid.num_vertices(); ++v) {
      if (!topology.is_boundary_vertex[v]) continue;
      EXPECT_EQ(r.uv(v, 0), uv(v, 0)) << v;
      EXPECT_EQ(r.uv(v, 1), uv(v, 1)) << v;
    }
  }
  // Two triangles, every vertex on the boundary: a corner pushed across the diagonal can only be
  // brought back by moving the boundary.
  const Mesh square = make_grid(1, 1);
  const MeshParamResult p = flat_layout(square);
  const Triangles& t = p.cut_mesh.triangles;
  UV uv = p.layout.uv;
  int opposite = -1;  // the vertex not on the corner's faces' shared diagonal: any face flips
  for (int v = 1; v < 4; ++v) {
    UV trial = p.layout.uv;
    trial.row(0) = 2 * trial.row(v) - trial.row(0);
    if (count_flipped(trial, t) == 1) opposite = v, uv = trial;
  }
  ASSERT_GE(opposite, 0);
  const UntangleResult fixed = untangle_layout(p.mesh, t, uv);
  EXPECT_EQ(fixed.flipped_after, 1);
  EXPECT_EQ(fixed.stuck_faces, 1);
  EXPECT_TRUE((fixed.uv.array() == uv.array()).all());
  UntangleOptions options;
  options.move_boundary = true;
  const UntangleResult moved = untangle_layout(p.mesh, t, uv, options);
  EXPECT_EQ(moved.flipped_after, 0);
}

TEST(Untangle, FixedVerticesStayAndAFaceOfFixedVerticesIsStuck) {
  const Mesh grid = make_grid(10, 10);
  const MeshParamResult p = flat_layout(grid);
  const Triangles& t = p.cut_mesh.triangles;
  UV uv = p.layout.uv;
  const int centre = 5 * 11 + 5;
  uv.row(centre) += 2.5 * (uv.row(centre + 1) - uv.row(centre));
  const int folded = count_flipped(uv, t);
  ASSERT_GE(folded, 2);
  UntangleOptions options;
  options.fixed.assign(grid.num_vertices(), 1);  // nothing may move
  const UntangleResult r = untangle_layout(p.mesh, t, uv, options);
  EXPECT_EQ(r.stuck_faces, folded);
  EXPECT_EQ(r.flipped_after, folded);
  EXPECT_TRUE((r.uv.array() == uv.array()).all());
}

TEST(Untangle, NeverMoreFlippedFacesThanBeforeAndNoGoodFaceFlips) {
  // Heavy random noise over a disk's interior: whatever is left flipped was flipped before.
  const Mesh disk = make_disk(10);
  const MeshParamResult p = flat_layout(disk);
  const Triangles& t = p.cut_mesh.triangles;
  const Topology topology = build_topology(disk.triangles, disk.num_vertices());
  UV uv = p.layout.uv;
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0.0, 0.08);
  for (int v = 0; v < disk.num_vertices(); ++v) {
    if (!topology.is_boundary_vertex[v])
      uv.row(v) += Eigen::RowVector2d(noise(random), noise(random));
  }
  const int folded = count_flipped(uv, t);
  ASSERT_GE(folded, 10);
  const UntangleResult r = untangle_layout(p.mesh, t, uv);
  EXPECT_LE(r.flipped_after, folded);
  for (int f = 0; f < t.rows(); ++f) {
    if (signed_area(uv, t, f) > 0) {
      EXPECT_GT(signed_area(r.uv, t, f), 0) << f;
    }
  }
  EXPECT_EQ(r.flipped_after, count_flipped(r.uv, t));
  EXPECT_EQ(r.flipped_after, 0);  // a disk with a fixed convex boundary: always untangles
}

TEST(Untangle, RefusesArraysThatDisagree) {
  const Mesh grid = make_grid(3, 3);
  const MeshParamResult p = flat_layout(grid);
  EXPECT_THROW(untangle_layout(p.mesh, p.cut_mesh.triangles.topRows(2), p.layout.uv), InvalidInput);
  Triangles bad = p.cut_mesh.triangles;
  bad(0, 0) = static_cast<int>(p.layout.uv.rows());
  EXPECT_THROW(untangle_layout(p.mesh, bad, p.layout.uv), InvalidInput);
  UntangleOptions options;
  options.fixed.assign(3, 0);
  EXPECT_THROW(untangle_layout(p.mesh, p.cut_mesh.triangles, p.layout.uv, options), InvalidInput);
  options = {};
  options.min_det = 0;
  EXPECT_THROW(untangle_layout(p.mesh, p.cut_mesh.triangles, p.layout.uv, options), InvalidInput);
}

}  // namespace
}  // namespace ricci
