// The angle polish: what it may move, what it must keep bit for bit, and that it lowers the
// face-mean sigma ratio, measured independently (an SVD per face).

#include "ricci/param/layout/polish.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "ricci/errors.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/param/parameterize.hpp"
#include "support/scoped_threads.hpp"

namespace ricci {
namespace {

using UV = Eigen::Matrix<double, Eigen::Dynamic, 2>;

struct Figures {
  double mean_ratio = 0;  // unweighted over the faces with positive layout area
  int flipped = 0;        // layout signed area <= 0
};

/// sigma_max / sigma_min of each face's map from its 3D triangle (in a frame of its plane) to
/// its layout, by a 2 by 2 SVD: independent of the complex-number formula the polish uses.
Figures measure(const Mesh& mesh, const Triangles& uv_triangles, const UV& uv) {
  Figures fig;
  int counted = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d p0 = mesh.positions.row(mesh.triangles(f, 0));
    const Eigen::Vector3d e1 = Eigen::Vector3d(mesh.positions.row(mesh.triangles(f, 1))) - p0;
    const Eigen::Vector3d e2 = Eigen::Vector3d(mesh.positions.row(mesh.triangles(f, 2))) - p0;
    const Eigen::Vector3d x = e1.normalized();
    const Eigen::Vector3d y = e1.cross(e2).cross(e1).normalized();
    Eigen::Matrix2d X, U;
    X << e1.dot(x), e2.dot(x), e1.dot(y), e2.dot(y);
    const Eigen::Vector2d q0 = uv.row(uv_triangles(f, 0)).transpose();
    U.col(0) = uv.row(uv_triangles(f, 1)).transpose() - q0;
    U.col(1) = uv.row(uv_triangles(f, 2)).transpose() - q0;
    if (!(U.determinant() > 0)) {
      ++fig.flipped;
      continue;
    }
    const Eigen::Vector2d s = Eigen::JacobiSVD<Eigen::Matrix2d>(U * X.inverse()).singularValues();
    fig.mean_ratio += s[0] / s[1];
    ++counted;
  }
  fig.mean_ratio /= counted;
  return fig;
}

/// uv vertices on an edge of one face (the layout's boundary: seams and the mesh boundary).
std::set<int> boundary_of(const Triangles& uv_triangles) {
  std::multiset<std::pair<int, int>> edges;
  for (int f = 0; f < uv_triangles.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int i = uv_triangles(f, k), j = uv_triangles(f, (k + 1) % 3);
      edges.insert({std::min(i, j), std::max(i, j)});
    }
  }
  std::set<int> out;
  for (const auto& e : edges) {
    if (edges.count(e) == 1) out.insert({e.first, e.second});
  }
  return out;
}

TEST(PolishAngles, AConformalLayoutIsLeftAsItIs) {
  const Mesh grid = make_grid(8, 8);
  const UV uv = grid.positions.leftCols<2>();
  const PolishResult r = polish_angles(grid, grid.triangles, uv);
  EXPECT_EQ(r.uv, uv);
  EXPECT_EQ(r.moved_vertices, 0);
  EXPECT_EQ(r.free_vertices, 7 * 7);
  EXPECT_NEAR(r.angle_distortion_before, 1.0, 1e-14);
  EXPECT_NEAR(r.angle_distortion_after, 1.0, 1e-14);
}

// A grid whose interior vertices were pushed about: the best layout with this boundary is the
// grid itself, and the polish gets most of the way back to it.
TEST(PolishAngles, ShakenInteriorIsDrawnBackAndTheBoundaryKept) {
  const Mesh grid = make_grid(10, 10);
  UV uv = grid.positions.leftCols<2>();
  const std::set<int> boundary = boundary_of(grid.triangles);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> shake(-0.02, 0.02);  // a fifth of the spacing 0.1
  for (int v = 0; v < uv.rows(); ++v) {
    if (!boundary.count(v)) uv.row(v) += Eigen::RowVector2d(shake(random), shake(random));
  }
  const Figures before = measure(grid, grid.triangles, uv);
  ASSERT_EQ(before.flipped, 0);
  ASSERT_GT(before.mean_ratio, 1.2);
  const PolishResult r = polish_angles(grid, grid.triangles, uv);
  const Figures after = measure(grid, grid.triangles, r.uv);
  EXPECT_EQ(after.flipped, 0);
  // Its own figures are the SVD's (1e-12: sums of a hundred ratios near 1).
  EXPECT_NEAR(r.angle_distortion_before, before.mean_ratio, 1e-12);
  EXPECT_NEAR(r.angle_distortion_after, after.mean_ratio, 1e-12);
  EXPECT_LT(after.mean_ratio - 1, 0.05 * (before.mean_ratio - 1));
  EXPECT_EQ(r.free_vertices, 9 * 9);
  EXPECT_EQ(r.moved_vertices, 9 * 9);
  EXPECT_GE(r.sweeps, 2);
  for (int v : boundary) EXPECT_EQ(r.uv.row(v), uv.row(v)) << "boundary vertex " << v;

  PolishOptions off;
  off.enabled = false;
  const PolishResult none = polish_angles(grid, grid.triangles, uv, off);
  EXPECT_EQ(none.uv, uv);
  EXPECT_EQ(none.sweeps, 0);
  EXPECT_NEAR(none.angle_distortion_after, before.mean_ratio, 1e-12);
}

// The sweeps relax classes of vertices that share no face in parallel: 1, 2 and 3 threads give
// the same bits (a 120 x 120 grid: several threads' worth of free vertices in every class).
TEST(PolishAngles, SameBitsWhateverTheThreadCount) {
  const Mesh grid = make_grid(120, 120);
  UV uv = grid.positions.leftCols<2>();
  const std::set<int> boundary = boundary_of(grid.triangles);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> shake(-0.002, 0.002);  // a quarter of the spacing
  for (int v = 0; v < uv.rows(); ++v) {
    if (!boundary.count(v)) uv.row(v) += Eigen::RowVector2d(shake(random), shake(random));
  }
  std::vector<PolishResult> results;
  for (const char* threads : {"1", "2", "3"}) {
    const testing::ScopedThreads scoped(threads);
    results.push_back(polish_angles(grid, grid.triangles, uv));
  }
  EXPECT_LT(results[0].angle_distortion_after - 1, 0.1 * (results[0].angle_distortion_before - 1));
  EXPECT_EQ(results[0].moved_vertices, 119 * 119);
  for (std::size_t k = 1; k < results.size(); ++k) {
    EXPECT_TRUE((results[k].uv.array() == results[0].uv.array()).all()) << k + 1 << " threads";
    EXPECT_EQ(results[k].sweeps, results[0].sweeps);
    EXPECT_EQ(results[k].angle_distortion_after, results[0].angle_distortion_after);
  }
}

// A face drawn flipped with a vertex free to move is unflipped first: the vertex goes where all
// of its faces are positive, and the sweeps then smooth it.
TEST(PolishAngles, AFlippedFaceWithAFreeVertexIsUnflipped) {
  const Mesh grid = make_grid(6, 6);
  UV uv = grid.positions.leftCols<2>();
  const int v = 2 * 7 + 2;                      // interior: (2, 2)
  uv.row(v) += Eigen::RowVector2d(0.25, 0.02);  // past its right-hand neighbour at spacing 1/6
  const Figures before = measure(grid, grid.triangles, uv);
  ASSERT_GT(before.flipped, 0);
  const PolishResult r = polish_angles(grid, grid.triangles, uv);
  const Figures after = measure(grid, grid.triangles, r.uv);
  EXPECT_EQ(after.flipped, 0);
  EXPECT_EQ(r.untangled_faces, before.flipped);
  EXPECT_LT(after.mean_ratio, 1.01);  // the grid again, nearly
  EXPECT_NEAR(r.angle_distortion_after, after.mean_ratio, 1e-12);
  // Off: nothing moves, not even to unflip.
  PolishOptions off;
  off.enabled = false;
  const PolishResult none = polish_angles(grid, grid.triangles, uv, off);
  EXPECT_EQ(none.uv, uv);
  EXPECT_EQ(none.untangled_faces, 0);
}

// A flipped face whose vertices are all on the boundary is not the polish's to mend: they stay,
// and no other face flips.
TEST(PolishAngles, AFlippedFaceOnTheBoundaryStays) {
  const Mesh strip = make_grid(4, 1);  // every vertex on the boundary
  UV uv = strip.positions.leftCols<2>();
  uv.row(1) += Eigen::RowVector2d(0.0, 1.5);  // (1, 0) above the top row: its faces flip
  const Figures before = measure(strip, strip.triangles, uv);
  ASSERT_GT(before.flipped, 0);
  const PolishResult r = polish_angles(strip, strip.triangles, uv);
  EXPECT_EQ(r.uv, uv);
  EXPECT_EQ(r.free_vertices, 0);
  EXPECT_EQ(r.untangled_faces, 0);
  EXPECT_EQ(measure(strip, strip.triangles, r.uv).flipped, before.flipped);
}

TEST(PolishAngles, RefusesMismatchedArraysAndBadOptions) {
  const Mesh grid = make_grid(3, 3);
  const UV uv = grid.positions.leftCols<2>();
  EXPECT_THROW(polish_angles(grid, grid.triangles.topRows(2), uv), InvalidInput);
  EXPECT_THROW(polish_angles(grid, grid.triangles, uv.topRows(3)), InvalidInput);
  PolishOptions bad;
  bad.max_sweeps = -1;
  EXPECT_THROW(polish_angles(grid, grid.triangles, uv, bad), InvalidInput);
  bad = {};
  bad.tolerance = std::nan("");
  EXPECT_THROW(polish_angles(grid, grid.triangles, uv, bad), InvalidInput);
}

// In the pipeline: a sphere with four cones. The polish moves only the interior of the cut
// disk; every seam vertex (and so every cone, every seam length and transition) is bit for bit
// the flat metric's, and the face-mean ratio falls.
TEST(PolishAngles, InParameterizeTheSeamsAreTheFlatMetricsBitForBit) {
  const Mesh sphere = make_icosphere(3);
  ParamOptions options;
  options.cone_mode = ConeMode::User;
  for (int v = 0; v < 4; ++v) options.cones.push_back({7 * v, std::numbers::pi});
  const MeshParamResult polished = parameterize(sphere, options);
  options.polish.enabled = false;
  const MeshParamResult exact = parameterize(sphere, options);
  ASSERT_TRUE(polished.converged) << polished.message;
  ASSERT_TRUE(exact.converged) << exact.message;
  ASSERT_EQ(polished.cut_mesh.triangles, exact.cut_mesh.triangles);
  EXPECT_EQ(polished.polish.uv, exact.layout.uv);  // the positions from before the polish
  EXPECT_TRUE(exact.polish.uv.size() == 0);
  const std::set<int> seams = boundary_of(exact.cut_mesh.triangles);
  ASSERT_FALSE(seams.empty());
  for (int v : seams) EXPECT_EQ(polished.layout.uv.row(v), exact.layout.uv.row(v));
  EXPECT_EQ(polished.polish.free_vertices + static_cast<int>(seams.size()),
            static_cast<int>(exact.layout.uv.rows()));
  EXPECT_GT(polished.polish.moved_vertices, 0);
  const Figures a = measure(polished.mesh, polished.cut_mesh.triangles, polished.layout.uv);
  const Figures b = measure(exact.mesh, exact.cut_mesh.triangles, exact.layout.uv);
  EXPECT_EQ(a.flipped, 0);
  EXPECT_EQ(b.flipped, 0);
  EXPECT_LT(a.mean_ratio, b.mean_ratio);
  EXPECT_NEAR(polished.polish.angle_distortion_before, b.mean_ratio, 1e-12);
  EXPECT_NEAR(polished.polish.angle_distortion_after, a.mean_ratio, 1e-12);
  // The distortion figures are those of the polished layout; the area changes little.
  EXPECT_NEAR(polished.distortion.area_distortion_energy, exact.distortion.area_distortion_energy,
              0.05 * exact.distortion.area_distortion_energy);
  EXPECT_EQ(polished.layout.transitions.size(), exact.layout.transitions.size());
  EXPECT_GT(polished.timings.polish, 0.0);
  EXPECT_EQ(exact.timings.polish, 0.0);
}

}  // namespace
}  // namespace ricci
