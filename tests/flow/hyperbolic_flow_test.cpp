// The Ricci flow in the hyperbolic background (THEORY.md section 9): Hessians against finite
// differences, positive definiteness, convergence to the uniformization metric of genus >= 2
// surfaces (zero vertex curvature), geodesic boundaries, and Gauss-Bonnet with the area term.

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "../support/shared_meshes.hpp"
#include "flow_test_util.hpp"
#include "ricci/errors.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/flow/ricci_flow.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/hessian.hpp"
#include "ricci/metric/hyperbolic.hpp"
#include "ricci/metric/lengths.hpp"

namespace ricci {
namespace {

constexpr double kPi = std::numbers::pi;

struct Metric {
  Eigen::VectorXd lengths, curvature;
  CornerAngles angles;
};

Metric evaluate(const Topology& t, const ConformalStructure& s, const Eigen::VectorXd& u) {
  Metric m;
  EXPECT_EQ(edge_lengths(t, s, u, m.lengths), 0);
  EXPECT_EQ(corner_angles(t, m.lengths, m.angles, s.geometry), -1);
  vertex_curvature(t, m.angles, m.curvature);
  return m;
}

/// The dense Hessian dK/du the flow assembles (hyperbolic_hessian_terms).
Eigen::MatrixXd assembled_hessian(const Topology& t, const ConformalStructure& s,
                                  const Eigen::VectorXd& u) {
  const Metric m = evaluate(t, s, u);
  Eigen::VectorXd w, diag, ew;
  hyperbolic_hessian_terms(t, s, u, m.lengths, m.angles, w, diag);
  edge_weights(t, w, ew);
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(t.num_vertices, t.num_vertices);
  for (int e = 0; e < t.num_edges; ++e) {
    const int i = t.edge_vertices(e, 0), j = t.edge_vertices(e, 1);
    h(i, j) -= ew[e];
    h(j, i) -= ew[e];
    h(i, i) += ew[e];
    h(j, j) += ew[e];
  }
  for (int f = 0; f < t.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) h(t.triangles(f, k), t.triangles(f, k)) += diag[3 * f + k];
  }
  return h;
}

Eigen::MatrixXd finite_difference_hessian(const Topology& t, const ConformalStructure& s,
                                          const Eigen::VectorXd& u, double step) {
  Eigen::MatrixXd h(t.num_vertices, t.num_vertices);
  for (int v = 0; v < t.num_vertices; ++v) {
    Eigen::VectorXd up = u, down = u;
    up[v] += step;
    down[v] -= step;
    h.col(v) = (evaluate(t, s, up).curvature - evaluate(t, s, down).curvature) / (2 * step);
  }
  return h;
}

const Scheme kAllSchemes[] = {Scheme::Thurston, Scheme::Tangential, Scheme::InversiveDistance,
                              Scheme::VertexScaling};

StructureResult hyperbolic_structure(const Topology& t, const Mesh& mesh, Scheme scheme) {
  StructureOptions o;
  o.scheme = scheme;
  o.geometry = Geometry::Hyperbolic;
  return make_conformal_structure(t, input_edge_lengths(mesh, t), o);
}

TEST(HyperbolicHessian, MatchesFiniteDifferencesAndIsPositiveDefiniteForEveryScheme) {
  const Mesh mesh = make_closed_surface(2, 6);
  const Topology t = build_topology(mesh.triangles, static_cast<int>(mesh.positions.rows()));
  std::mt19937 random(11);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  for (Scheme scheme : kAllSchemes) {
    SCOPED_TRACE(scheme_name(scheme));
    const ConformalStructure s = hyperbolic_structure(t, mesh, scheme).structure;
    Eigen::VectorXd u = s.initial_u;
    for (int v = 0; v < t.num_vertices; ++v) u[v] += jitter(random);
    const Eigen::MatrixXd h = assembled_hessian(t, s, u);
    const Eigen::MatrixXd fd = finite_difference_hessian(t, s, u, 1e-6);
    const double scale = h.cwiseAbs().maxCoeff();
    EXPECT_LT((h - fd).cwiseAbs().maxCoeff(), 1e-7 * scale);
    // Symmetric before symmetrisation: the per-face Jacobians themselves.
    const Metric m = evaluate(t, s, u);
    double asymmetry = 0, size = 0;
    for (int f = 0; f < t.num_faces; ++f) {
      const Eigen::Matrix3d j = hyperbolic_face_jacobian(t, s, u, m.lengths, m.angles, f);
      asymmetry = std::max(asymmetry, (j - j.transpose()).cwiseAbs().maxCoeff());
      size = std::max(size, j.cwiseAbs().maxCoeff());
    }
    EXPECT_LT(asymmetry, 1e-12 * size);
    // Positive definite: no gauge direction (K changes when every u grows).
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(h);
    EXPECT_GT(eig.eigenvalues().minCoeff(), 1e-8 * eig.eigenvalues().maxCoeff());
  }
}

TEST(HyperbolicStructure, ReproducesTheScaledInputLengths) {
  const Mesh mesh = make_closed_surface(2, 6);
  const Topology t = build_topology(mesh.triangles, static_cast<int>(mesh.positions.rows()));
  for (Scheme scheme : {Scheme::InversiveDistance, Scheme::VertexScaling}) {
    const StructureResult r = hyperbolic_structure(t, mesh, scheme);
    EXPECT_LT(r.fit_max_relative_error, 1e-12) << scheme_name(scheme);
    EXPECT_GT(r.structure.length_scale, 0);
  }
  // The automatic scale gives the input the area 2 pi |chi| = 4 pi of the hyperbolic metric.
  const StructureResult r = hyperbolic_structure(t, mesh, Scheme::VertexScaling);
  Eigen::VectorXd l;
  CornerAngles a;
  edge_lengths(t, r.structure, r.structure.initial_u, l);
  corner_angles(t, l, a, Geometry::Hyperbolic);
  EXPECT_NEAR(hyperbolic_total_area(a), 4 * kPi, 0.2 * 4 * kPi);
}

/// Runs the default hyperbolic job (zero curvature, geodesic boundary) on a mesh.
MeshFlowResult uniformize(const Mesh& mesh, Scheme scheme = Scheme::Thurston) {
  MeshFlowOptions o;
  o.structure.scheme = scheme;
  o.structure.geometry = Geometry::Hyperbolic;
  o.target.boundary = BoundaryMode::Geodesic;
  return flow_mesh(mesh, o);
}

void expect_uniformized(const MeshFlowResult& r, int chi) {
  ASSERT_TRUE(r.converged) << r.components[0].flow.message;
  EXPECT_LE(r.max_error, 1e-10);
  const FlowResult& f = r.components[0].flow;
  // Gauss-Bonnet in curvature -1: sum K - area = 2 pi chi; with K = 0 the area is -2 pi chi.
  // |area + 2 pi chi| = |sum K| <= #V max |K|.
  EXPECT_NEAR(f.total_area, -2 * kPi * chi, f.curvature.size() * f.max_error + 1e-12);
  EXPECT_LT(f.gauss_bonnet_relative_error, 1e-12);
  EXPECT_LT(f.iterations, 30);
}

TEST(HyperbolicFlow, UniformizesGeneratedGenus2And3WithEveryScheme) {
  for (int genus : {2, 3}) {
    const Mesh mesh = make_closed_surface(genus, 8);
    for (Scheme scheme : kAllSchemes) {
      SCOPED_TRACE(std::string(scheme_name(scheme)) + ", genus " + std::to_string(genus));
      const MeshFlowResult r = uniformize(mesh, scheme);
      expect_uniformized(r, 2 - 2 * genus);
      testing::expect_quadratic_convergence(r.components[0].flow);
    }
  }
}

TEST(HyperbolicFlow, GivesSurfacesWithBoundaryAGeodesicBoundary) {
  // Genus 1 with two holes (chi = -2) and genus 0 with three holes (a pair of pants, chi = -1).
  for (auto [genus, holes] : {std::pair{1, 2}, std::pair{0, 3}}) {
    const Mesh mesh = make_surface_with_holes(genus, holes, 10);
    const MeshFlowResult r = uniformize(mesh);
    expect_uniformized(r, 2 - 2 * genus - holes);
    // Boundary vertices reach zero geodesic curvature (pi - angle sum) like the others.
    const Topology& t = r.topology;
    for (int v = 0; v < t.num_vertices; ++v) {
      if (t.is_boundary_vertex[v]) {
        EXPECT_NEAR(r.curvature[v], 0, 1e-10);
      }
    }
  }
}

TEST(HyperbolicFlow, RefusesTargetsWithNoPositiveArea) {
  // A torus has chi = 0: zero curvature would need zero area.
  const Mesh torus = make_torus(12, 8);
  EXPECT_THROW(uniformize(torus), InvalidInput);
  // Gauss-Bonnet's Euclidean equality is not required: a uniform target below zero works.
  const Mesh mesh = make_closed_surface(2, 8);
  MeshFlowOptions o;
  o.structure.geometry = Geometry::Hyperbolic;
  o.target.kind = TargetKind::Values;
  o.target.values = Eigen::VectorXd::Constant(mesh.positions.rows(), -0.001);
  const MeshFlowResult r = flow_mesh(mesh, o);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.components[0].flow.total_area,
              -0.001 * static_cast<double>(mesh.positions.rows()) + 4 * kPi, 1e-8);
}

TEST(HyperbolicStructure, RefusesTheVirtualRadiusScheme) {
  const Mesh mesh = make_closed_surface(2, 6);
  const Topology t = build_topology(mesh.triangles, static_cast<int>(mesh.positions.rows()));
  EXPECT_THROW(hyperbolic_structure(t, mesh, Scheme::VirtualRadius), InvalidInput);
}

TEST(HyperbolicFlow, RefusesDelaunayFlips) {
  const Mesh mesh = make_closed_surface(2, 6);
  MeshFlowOptions o;
  o.structure.scheme = Scheme::VertexScaling;
  o.structure.geometry = Geometry::Hyperbolic;
  o.flow.flips = EdgeFlips::Delaunay;
  EXPECT_THROW(flow_mesh(mesh, o), InvalidInput);
}

TEST(HyperbolicFlow, UniformizesEveryClosedSharedMeshOfGenusAtLeastTwo) {
  RICCI_REQUIRE_SHARED_MESHES();
  int tested = 0;
  for (const auto& m : testing::shared_meshes()) {
    if (!m.manifold || m.genus < 2 || m.boundary_loops != 0) continue;
    SCOPED_TRACE(m.file);
    const Mesh mesh = read_mesh(m.path).mesh;
    const MeshFlowResult r = uniformize(mesh);
    expect_uniformized(r, m.euler_characteristic);
    ++tested;
  }
  EXPECT_GE(tested, 3);  // eight (g2), 3holes (g3), fertility (g4)
}

}  // namespace
}  // namespace ricci
