#include "ricci/metric/hessian.hpp"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "ricci/mesh/generate.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/lengths.hpp"
#include "support/metric_helpers.hpp"
#include "support/test_meshes.hpp"

namespace ricci {
namespace {

using testing::curvature_at;
using testing::kAllSchemes;
using testing::structure_of;

Eigen::MatrixXd hessian_at(const Topology& t, const ConformalStructure& s,
                           const Eigen::VectorXd& u) {
  Eigen::VectorXd l, hw, ew;
  CornerAngles a;
  edge_lengths(t, s, u, l);
  corner_angles(t, l, a);
  halfedge_weights(t, s, u, l, a, hw);
  edge_weights(t, hw, ew);
  return Eigen::MatrixXd(curvature_hessian(t, ew));
}

// dK/du from the closed form against central differences of K(u); the step 1e-5 leaves a
// truncation error of order 1e-10 and a rounding error of order 1e-11, far below 1e-6.
TEST(Hessian, AssemblySumsAsTripletsDoBitForBit) {
  // Edges as an intrinsic triangulation may have them: several between two vertices, and loops
  // at one vertex. The compressed columns built directly hold what setFromTriplets made of the
  // four triplets per edge, to the last bit.
  std::mt19937 random(7);
  std::uniform_int_distribution<int> vertex(0, 39);
  std::uniform_real_distribution<double> weight(-1.0, 3.0);
  Topology t;
  t.num_vertices = 40;
  t.num_edges = 400;
  t.edge_vertices.resize(t.num_edges, 2);
  Eigen::VectorXd w(t.num_edges);
  std::vector<Eigen::Triplet<double>> triplets;
  for (int e = 0; e < t.num_edges; ++e) {
    const int a = vertex(random), b = e % 50 == 0 ? a : vertex(random);
    t.edge_vertices(e, 0) = std::min(a, b);
    t.edge_vertices(e, 1) = std::max(a, b);
    w[e] = weight(random);
    const int i = t.edge_vertices(e, 0), j = t.edge_vertices(e, 1);
    triplets.emplace_back(i, j, -w[e]);
    triplets.emplace_back(j, i, -w[e]);
    triplets.emplace_back(i, i, w[e]);
    triplets.emplace_back(j, j, w[e]);
  }
  Eigen::SparseMatrix<double> expected(t.num_vertices, t.num_vertices);
  expected.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::SparseMatrix<double> built = curvature_hessian(t, w);
  ASSERT_EQ(built.nonZeros(), expected.nonZeros());
  for (int c = 0; c < t.num_vertices; ++c) {
    Eigen::SparseMatrix<double>::InnerIterator a(built, c), b(expected, c);
    for (; b; ++a, ++b) {
      ASSERT_TRUE(a);
      EXPECT_EQ(a.row(), b.row());
      EXPECT_EQ(a.value(), b.value()) << "entry (" << b.row() << ", " << c << ")";
    }
    EXPECT_FALSE(a);
  }
}

TEST(Hessian, MatchesFiniteDifferencesForEveryScheme) {
  std::mt19937 rng(11);
  const std::vector<testing::NamedMesh> meshes = {
      {"icosphere", make_icosphere(1)},
      {"curved_disk", make_disk(3, 0.5)},
      {"torus", make_torus(10, 6)},
      {"genus2", make_closed_surface(2, 6)},
  };
  testing::for_every_mesh_and_scheme(meshes, [&](const std::string& name, const Topology& t,
                                                 const ConformalStructure& s, Scheme scheme) {
    std::uniform_real_distribution<double> noise = testing::u_noise(scheme, 0.5, 0.03);
    Eigen::VectorXd u = s.initial_u;
    for (int v = 0; v < t.num_vertices; ++v) u[v] += noise(rng);
    ASSERT_GT(curvature_at(t, s, u).size(), 0) << name << " " << scheme_name(scheme);

    const Eigen::MatrixXd L = hessian_at(t, s, u);
    const double h = 1e-5;
    Eigen::MatrixXd fd(t.num_vertices, t.num_vertices);
    for (int j = 0; j < t.num_vertices; ++j) {
      Eigen::VectorXd up = u, down = u;
      up[j] += h;
      down[j] -= h;
      fd.col(j) = (curvature_at(t, s, up) - curvature_at(t, s, down)) / (2 * h);
    }
    const double scale = L.cwiseAbs().maxCoeff();
    EXPECT_LT((fd - L).cwiseAbs().maxCoeff() / scale, 1e-6) << name << " " << scheme_name(scheme);
    EXPECT_LT((L - L.transpose()).cwiseAbs().maxCoeff() / scale, 1e-14);
    EXPECT_LT(L.rowwise().sum().cwiseAbs().maxCoeff() / scale, 1e-13);
  });
}

// Thurston packings with Phi in [0, pi/2] have a positive semi-definite Hessian whose kernel on
// a closed mesh is exactly the constants (THEORY.md section 4).
TEST(Hessian, ThurstonHessianIsPositiveSemidefiniteWithConstantKernel) {
  const Mesh mesh = make_closed_surface(2, 6);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  const ConformalStructure s = structure_of(mesh, t, Scheme::Thurston);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> noise(-1.0, 1.0);
  Eigen::VectorXd u = s.initial_u;
  for (int v = 0; v < t.num_vertices; ++v) u[v] += noise(rng);
  const Eigen::MatrixXd L = hessian_at(t, s, u);
  const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(L).eigenvalues();
  const double scale = eig.cwiseAbs().maxCoeff();
  EXPECT_NEAR(eig[0] / scale, 0.0, 1e-12);
  EXPECT_GT(eig[1] / scale, 1e-8);
}

// For vertex scaling the power centre is the circumcentre: h / l is half the cotangent.
TEST(Hessian, VertexScalingWeightsAreHalfCotangents) {
  const Mesh mesh = make_disk(3, 0.4);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  const ConformalStructure s = structure_of(mesh, t, Scheme::VertexScaling);
  Eigen::VectorXd l, hw;
  CornerAngles a;
  edge_lengths(t, s, s.initial_u, l);
  corner_angles(t, l, a);
  halfedge_weights(t, s, s.initial_u, l, a, hw);
  for (int f = 0; f < t.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(hw[3 * f + k], 0.5 / std::tan(a(f, k)), 1e-13);
    }
  }
}

}  // namespace
}  // namespace ricci
