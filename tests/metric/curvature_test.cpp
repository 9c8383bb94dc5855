#include "ricci/metric/curvature.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/metric/scheme.hpp"
#include "support/metric_helpers.hpp"
#include "support/shared_meshes.hpp"
#include "support/test_meshes.hpp"

namespace ricci {
namespace {

using testing::curvature_at;
using testing::kAllSchemes;
using testing::structure_of;

// Gauss-Bonnet holds for every metric, not only the input one: perturb u at random.
TEST(Curvature, GaussBonnetOnEveryGeneratedMeshAndScheme) {
  std::mt19937 rng(7);
  testing::for_every_mesh_and_scheme(
      testing::generated_meshes(),
      [&](const std::string& name, const Topology& t, const ConformalStructure& s, Scheme scheme) {
        std::uniform_real_distribution<double> noise = testing::u_noise(scheme, 1.0, 0.02);
        Eigen::VectorXd u = s.initial_u;
        for (int round = 0; round < 2; ++round) {
          const Eigen::VectorXd k = curvature_at(t, s, u);
          ASSERT_EQ(k.size(), t.num_vertices) << name << " " << scheme_name(scheme);
          const double total = accurate_sum(k);
          EXPECT_NEAR(total, 2 * std::numbers::pi * t.euler_characteristic(),
                      1e-12 * 2 * std::numbers::pi * t.num_vertices)
              << name << " " << scheme_name(scheme) << " round " << round;
          EXPECT_LT(gauss_bonnet_relative_error(t, k), 1e-12);
          for (int v = 0; v < t.num_vertices; ++v) u[v] += noise(rng);
        }
      });
}

TEST(Curvature, FlatGridHasZeroInteriorCurvatureAndCornersOfPiOverTwo) {
  const Mesh mesh = make_grid(6, 4, 3.0, 2.0);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  StructureOptions options;
  options.scheme = Scheme::VertexScaling;
  const StructureResult r = make_conformal_structure(t, input_edge_lengths(mesh, t), options);
  const Eigen::VectorXd k = curvature_at(t, r.structure, r.structure.initial_u);
  ASSERT_EQ(k.size(), t.num_vertices);
  int corners = 0;
  for (int v = 0; v < t.num_vertices; ++v) {
    if (!t.is_boundary_vertex[v]) {
      EXPECT_NEAR(k[v], 0.0, 1e-14) << "vertex " << v;
    } else if (std::abs(k[v]) > 1e-12) {
      EXPECT_NEAR(k[v], std::numbers::pi / 2, 1e-14) << "vertex " << v;
      ++corners;
    }
  }
  EXPECT_EQ(corners, 4);
}

TEST(Curvature, GaussBonnetOnEverySharedManifoldMesh) {
  RICCI_REQUIRE_SHARED_MESHES();
  int checked = 0;
  for (const auto& shared : testing::shared_meshes()) {
    if (!shared.manifold || shared.file == "degtri_sliding.off") continue;
    if (shared.faces > 100000) continue;  // the big scans are covered by the flow benchmark
    const ReadResult read = read_mesh(shared.path);
    const Topology t = build_topology(read.mesh.triangles, read.mesh.num_vertices());
    for (Scheme scheme : kAllSchemes) {
      const ConformalStructure s = structure_of(read.mesh, t, scheme);
      Eigen::VectorXd l;
      CornerAngles a;
      ASSERT_EQ(edge_lengths(t, s, s.initial_u, l).invalid_edges, 0) << shared.file;
      ASSERT_EQ(corner_angles(t, l, a).first_bad_face, -1)
          << shared.file << " " << scheme_name(scheme);
      const Eigen::VectorXd k = vertex_curvature(t, a);
      EXPECT_LT(gauss_bonnet_relative_error(t, k), 1e-12)
          << shared.file << " " << scheme_name(scheme);
    }
    ++checked;
  }
  EXPECT_GT(checked, 5);
}

TEST(Curvature, AccurateSumIsExactWhereNaiveSummationIsNot) {
  Eigen::VectorXd x(4);
  x << 1e16, 1.0, -1e16, 1.0;
  EXPECT_EQ(accurate_sum(x), 2.0);
}

}  // namespace
}  // namespace ricci
