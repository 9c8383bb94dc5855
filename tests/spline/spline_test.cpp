// Powell-Sabin manifold splines: polynomial reproduction, C1 continuity across every chart
// transition, convergence under refinement, and the tutorial's three topologies on real meshes.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "ricci/errors.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/spline/manifold_spline.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

Eigen::Matrix<double, Eigen::Dynamic, 2> xy(const Mesh& mesh) {
  return mesh.positions.leftCols<2>();
}

/// Chart position of a tessellation point.
Eigen::Vector2d chart_point(const SplineDomain& d, int f, const Eigen::Vector3d& b) {
  Eigen::Vector2d x = Eigen::Vector2d::Zero();
  for (int k = 0; k < 3; ++k)
    x += b[k] * Eigen::Vector2d(d.corner_uv(f, 2 * k), d.corner_uv(f, 2 * k + 1));
  return x;
}

// A plane given as an affine image of the disk's own coordinates is fitted exactly, whatever the
// smoothness weight: the smoothness energy vanishes on it and the data term is zero.
TEST(Spline, PlaneIsFittedExactlyOnPlanarDomain) {
  const Mesh disk = make_disk(6, 0.0);
  const SplineDomain d = planar_spline_domain(disk.triangles, xy(disk));
  Eigen::Matrix<double, 3, 2> a;
  a << 0.7, -1.3, 0.2, 0.9, 1.1, 0.4;
  const Eigen::Vector3d c(0.3, -2.0, 5.0);
  Eigen::MatrixXd data(disk.num_vertices(), 3);
  for (int v = 0; v < disk.num_vertices(); ++v) {
    data.row(v) = (a * xy(disk).row(v).transpose() + c).transpose();
  }
  for (double w : {1e-8, 1e-4, 1e-2, 1.0}) {
    SplineFitOptions options;
    options.smoothness = w;
    const SplineFit fit = fit_spline(d, data, options);
    const SplineTessellation s = tessellate_spline(d, fit.ordinates, 3);
    double worst = 0;
    for (int q = 0; q < s.values.rows(); ++q) {
      const Eigen::Vector2d x = chart_point(d, s.face[q], s.barycentric.row(q).transpose());
      worst = std::max(worst, (s.values.row(q).transpose() - (a * x + c)).norm());
    }
    EXPECT_LT(worst / 2.0, 1e-12) << "smoothness " << w;  // the disk's diameter is 2
    EXPECT_FALSE(fit.regularized);
  }
}

// End to end: a planar disk in 3D under vertex scaling (which reproduces the input lengths
// exactly, so the flat metric is the disk itself up to a rigid motion; no flips): the spline
// surface is the plane, parametric error at rounding level.
TEST(Spline, PlaneIsFittedExactlyEndToEnd) {
  Mesh disk = make_disk(5, 0.0);
  Eigen::Matrix3d a;
  a << 0.6, -0.8, 0, 0.8, 0.6, 0, 0.3, 0.5, 1;  // a rotation in xy, then tilted into 3D
  disk.positions = (disk.positions * a.transpose()).eval();
  disk.positions.col(0).array() += 2.0;
  SplineOptions options;
  options.param.structure.scheme = Scheme::VertexScaling;
  // Ptolemy flips would change the metric (they keep the conformal class, not the plane).
  options.param.flow.flips = EdgeFlips::Off;
  for (double w : {1e-6, 1e-2}) {
    options.smoothness = w;
    const SplineResult r = fit_manifold_spline(disk, options);
    ASSERT_TRUE(r.converged) << r.message;
    EXPECT_LT(r.error.max_parametric, 1e-12) << "smoothness " << w;
    EXPECT_LT(r.error.max_distance, 1e-12);
    EXPECT_LT(r.continuity.relative_value_jump, 1e-12);
    EXPECT_LT(r.continuity.relative_gradient_jump, 1e-12);
  }
}

// Quadratic data on a planar disk are reproduced, values and gradients, to rounding.
TEST(Spline, QuadraticDataAreReproduced) {
  const Mesh disk = make_disk(6, 0.0);
  const SplineDomain d = planar_spline_domain(disk.triangles, xy(disk));
  auto q = [](const Eigen::Vector2d& x) {
    return Eigen::Vector3d(
        1 + 2 * x.x() - x.y() + 3 * x.x() * x.x() - 2 * x.x() * x.y() + 0.5 * x.y() * x.y(),
        -x.x() * x.x() + 4 * x.y() * x.y(), 0.3 * x.x() * x.y() - x.x());
  };
  auto grad = [](const Eigen::Vector2d& x) {
    Eigen::Matrix<double, 2, 3> g;
    g.col(0) << 2 + 6 * x.x() - 2 * x.y(), -1 - 2 * x.x() + x.y();
    g.col(1) << -2 * x.x(), 8 * x.y();
    g.col(2) << 0.3 * x.y() - 1, 0.3 * x.x();
    return g;
  };
  Eigen::MatrixXd data(disk.num_vertices(), 3);
  for (int v = 0; v < disk.num_vertices(); ++v)
    data.row(v) = q(xy(disk).row(v).transpose()).transpose();
  for (double w : {1e-6, 1e-4, 1.0}) {
    SplineFitOptions options;
    options.smoothness = w;
    const SplineFit fit = fit_spline(d, data, options);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    double value_err = 0, grad_err = 0;
    for (int f = 0; f < disk.num_faces(); ++f) {
      for (int s = 0; s < 8; ++s) {
        double b1 = u(rng), b2 = u(rng);
        if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
        const Eigen::Vector3d b(1 - b1 - b2, b1, b2);
        const Eigen::Vector2d x = chart_point(d, f, b);
        const SplineSample e = evaluate_spline(d, fit.ordinates, f, b);
        value_err = std::max(value_err, (e.value.transpose() - q(x)).cwiseAbs().maxCoeff());
        grad_err = std::max(grad_err, (e.gradient - grad(x)).cwiseAbs().maxCoeff());
      }
    }
    // The data are of size ~10 and their gradients ~10 on the unit disk.
    EXPECT_LT(value_err, 1e-11) << "smoothness " << w;
    EXPECT_LT(grad_err, 1e-10) << "smoothness " << w;
  }
}

/// C1 on a manifold: every interior edge, cut or not, 5 samples.
void expect_c1(const SplineResult& r, const std::string& what) {
  ASSERT_TRUE(r.converged) << what << ": " << r.message;
  EXPECT_GT(r.continuity.edges_checked, 0);
  EXPECT_LT(r.continuity.relative_value_jump, 1e-9) << what;
  EXPECT_LT(r.continuity.relative_gradient_jump, 1e-9) << what;
  EXPECT_FALSE(r.fit.regularized) << what;
  // Surface and control net share their points along every edge: same topology as the input.
  const Topology input = build_topology(r.param.mesh.triangles, r.param.mesh.num_vertices());
  for (const Mesh* m : {&r.surface, &r.control_net}) {
    const Topology t = build_topology(m->triangles, m->num_vertices());
    EXPECT_EQ(t.components.size(), 1u) << what;
    EXPECT_EQ(t.euler_characteristic(), input.euler_characteristic()) << what;
    EXPECT_EQ(t.num_boundary_loops(), input.num_boundary_loops()) << what;
  }
  EXPECT_EQ(r.surface.num_faces(), 6 * 4 * r.param.mesh.num_faces()) << what;  // refine 2
}

TEST(Spline, C1AcrossEveryTransitionOnGeneratedSurfaces) {
  const SplineResult torus = fit_manifold_spline(make_torus(24, 12, 1.0, 0.4));
  expect_c1(torus, "torus");
  EXPECT_TRUE(torus.param.cones.empty());
  int cut_edges = 0;
  for (char c : torus.param.cut.is_cut_edge) cut_edges += c;
  EXPECT_GT(cut_edges, 0);

  const SplineResult genus2 = fit_manifold_spline(make_closed_surface(2, 10));
  expect_c1(genus2, "genus 2");
  EXPECT_FALSE(genus2.param.cones.empty());

  const SplineResult holes = fit_manifold_spline(make_surface_with_holes(0, 3, 9));
  expect_c1(holes, "sphere with 3 holes");
  EXPECT_TRUE(holes.param.cones.empty());
  std::printf(
      "C1 relative jumps (value, gradient): torus %.2e %.2e, genus 2 %.2e %.2e, holes "
      "%.2e %.2e\n",
      torus.continuity.relative_value_jump, torus.continuity.relative_gradient_jump,
      genus2.continuity.relative_value_jump, genus2.continuity.relative_gradient_jump,
      holes.continuity.relative_value_jump, holes.continuity.relative_gradient_jump);
}

// The C1 check can fail: move one ordinate that carries a vertex gradient (B at P of an interior
// edge, seen by the face on one side only) and the jump shows.
TEST(Spline, ContinuityCheckDetectsAPerturbedGradient) {
  const SplineResult r = fit_manifold_spline(make_torus(16, 8, 1.0, 0.4));
  ASSERT_TRUE(r.converged);
  Eigen::MatrixXd ord = r.fit.ordinates;
  const int f = 10, k = 0;  // side 0 of face 10, BP slot 12
  ASSERT_GE(r.domain.halfedge_twin[3 * f + k], 0);
  ord(kPowellSabinOrdinates * f + 12 + k, 2) += 1e-6;
  const ContinuityReport bad = measure_continuity(r.domain, ord);
  EXPECT_GT(bad.relative_gradient_jump, 1e-7);
  EXPECT_EQ(bad.worst_edge, r.domain.halfedge_edge[3 * f + k]);
  EXPECT_LT(r.continuity.relative_gradient_jump, 1e-9);
}

double torus_distance(const Eigen::Vector3d& p, double big, double small) {
  return std::abs(std::hypot(std::hypot(p.x(), p.y()) - big, p.z()) - small);
}

// Refinement: the spline surface of tori 16x8, 32x16, 64x32 against the analytic torus.
TEST(Spline, ErrorDecreasesUnderRefinementOnTori) {
  double previous = -1;
  for (int n : {16, 32, 64}) {
    const SplineResult r = fit_manifold_spline(make_torus(n, n / 2, 1.0, 0.4));
    ASSERT_TRUE(r.converged) << r.message;
    double worst = 0, pl_worst = 0;
    for (int q = 0; q < r.surface.num_vertices(); ++q) {
      worst = std::max(worst, torus_distance(r.surface.positions.row(q).transpose(), 1.0, 0.4));
    }
    // The input mesh's own error (at the same sample points) for comparison.
    for (int q = 0; q < r.surface_samples.values.rows(); ++q) {
      const int f = r.surface_samples.face[q];
      Eigen::Vector3d pl = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) {
        pl += r.surface_samples.barycentric(q, k) *
              r.param.mesh.positions.row(r.param.mesh.triangles(f, k)).transpose();
      }
      pl_worst = std::max(pl_worst, torus_distance(pl, 1.0, 0.4));
    }
    std::printf(
        "torus %dx%d: spline max distance to the torus %.3e (mesh %.3e), fit rms %.3e, "
        "C1 %.1e %.1e\n",
        n, n / 2, worst, pl_worst, r.error.rms_distance, r.continuity.relative_value_jump,
        r.continuity.relative_gradient_jump);
    EXPECT_LT(worst, pl_worst);
    if (previous > 0) {
      EXPECT_GT(previous / worst, 3.5) << n;
    }
    previous = worst;
  }
}

// The tutorial's three topologies on real meshes.
void shared_mesh_case(const std::string& file, int genus, bool cones_expected) {
  RICCI_REQUIRE_SHARED_MESHES();
  const std::string path = *testing::shared_meshes_dir() + "/" + file;
  const Mesh mesh = read_mesh(path).mesh;
  const SplineResult r = fit_manifold_spline(mesh);
  expect_c1(r, file);
  EXPECT_EQ(!r.param.cones.empty(), cones_expected) << file;
  (void)genus;
  EXPECT_TRUE(std::isfinite(r.error.max_distance));
  EXPECT_LT(r.error.max_distance, 0.05) << file;
  EXPECT_LT(r.error.rms_distance, 0.005) << file;
  std::printf(
      "%s: V %d F %d cones %zu | parametric max %.3e rms %.3e | distance max %.3e rms "
      "%.3e | C1 %.1e %.1e | param %.2f s fit %.2f s evaluate %.2f s error %.2f s\n",
      file.c_str(), r.param.mesh.num_vertices(), r.param.mesh.num_faces(), r.param.cones.size(),
      r.error.max_parametric, r.error.rms_parametric, r.error.max_distance, r.error.rms_distance,
      r.continuity.relative_value_jump, r.continuity.relative_gradient_jump, r.seconds_param,
      r.seconds_fit, r.seconds_evaluate, r.seconds_error);
}

TEST(SplineSharedMeshes, OpenBeetleWith11Boundaries) {
  shared_mesh_case("beetle.obj", 0, false);
}
TEST(SplineSharedMeshes, Genus1Bob) {
  shared_mesh_case("bob_tri.obj", 1, false);
}
TEST(SplineSharedMeshes, Genus2Eight) {
  shared_mesh_case("eight.off", 2, true);
}

}  // namespace
}  // namespace ricci
