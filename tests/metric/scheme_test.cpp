#include "ricci/metric/scheme.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "ricci/errors.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/lengths.hpp"
#include "support/test_meshes.hpp"

namespace ricci {
namespace {

/// The tutorial's fig. 5 structure on a tetrahedron: circles of radius 0.5 (epsilon = 1) meeting
/// at Phi = 0 (eta = cos Phi = 1), so that every edge has length 1.
ConformalStructure tangent_circles(const Topology& t, Scheme scheme) {
  ConformalStructure s;
  s.scheme = scheme;
  s.epsilon = Eigen::VectorXd::Ones(t.num_vertices);
  s.eta = Eigen::VectorXd::Ones(t.num_edges);
  s.initial_u = Eigen::VectorXd::Constant(t.num_vertices, std::log(0.5));
  return s;
}

// The tutorial's fig. 5: a tetrahedron with radii 0.5 and Phi = 0 has every edge 1 and K = pi.
TEST(Scheme, TutorialFigure5Tetrahedron) {
  const Mesh mesh = make_tetrahedron(1.0);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  const ConformalStructure s = tangent_circles(t, Scheme::Thurston);
  Eigen::VectorXd lengths;
  ASSERT_EQ(edge_lengths(t, s, s.initial_u, lengths).invalid_edges, 0);
  for (int e = 0; e < t.num_edges; ++e) EXPECT_NEAR(lengths[e], 1.0, 1e-15);
  CornerAngles angles;
  ASSERT_EQ(corner_angles(t, lengths, angles).first_bad_face, -1);
  const Eigen::VectorXd k = vertex_curvature(t, angles);
  for (int v = 0; v < 4; ++v) EXPECT_NEAR(k[v], std::numbers::pi, 1e-14);
  // The Thurston fit of the regular tetrahedron finds an exact packing.
  const StructureResult fit = make_conformal_structure(t, input_edge_lengths(mesh, t));
  EXPECT_LT(fit.fit_rms_relative_error, 1e-14);
}

TEST(Scheme, ExactSchemesReproduceTheInputLengths) {
  for (const auto& [name, mesh] : testing::generated_meshes()) {
    const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
    const Eigen::VectorXd lbar = input_edge_lengths(mesh, t);
    for (Scheme scheme :
         {Scheme::InversiveDistance, Scheme::VertexScaling, Scheme::VirtualRadius}) {
      StructureOptions options;
      options.scheme = scheme;
      const StructureResult r = make_conformal_structure(t, lbar, options);
      Eigen::VectorXd l;
      ASSERT_EQ(edge_lengths(t, r.structure, r.structure.initial_u, l).invalid_edges, 0);
      EXPECT_LT(((l - lbar).array() / lbar.array()).abs().maxCoeff(), 1e-13)
          << name << " " << scheme_name(scheme);
      EXPECT_LT(r.fit_rms_relative_error, 1e-13);
    }
  }
}

// edge_lengths says how many edges have no length and which is the first, in either geometry.
TEST(Scheme, EdgeLengthsReportsTheEdgesWithoutALength) {
  const Mesh mesh = make_tetrahedron(1.0);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  ConformalStructure s = tangent_circles(t, Scheme::InversiveDistance);
  Eigen::VectorXd l;
  const LengthsCheck valid = edge_lengths(t, s, s.initial_u, l);
  EXPECT_TRUE(valid.ok());
  EXPECT_EQ(valid.invalid_edges, 0);
  EXPECT_EQ(valid.first_edge, -1);
  // eta = -2 with equal radii: l^2 = 2 r^2 - 4 r^2 < 0 (and cosh l < 1 in the hyperbolic form).
  s.eta[4] = s.eta[2] = -2.0;
  for (Geometry g : {Geometry::Euclidean, Geometry::Hyperbolic}) {
    s.geometry = g;
    const LengthsCheck bad = edge_lengths(t, s, s.initial_u, l);
    EXPECT_FALSE(bad.ok());
    EXPECT_EQ(bad.invalid_edges, 2);
    EXPECT_EQ(bad.first_edge, 2);
    EXPECT_TRUE(std::isnan(l[2]) && std::isnan(l[4]));
  }
}

TEST(Scheme, ThurstonFitIsBetterThanTangentialAndWithinItsBounds) {
  const Mesh mesh = make_disk(6, 0.7);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  const Eigen::VectorXd lbar = input_edge_lengths(mesh, t);
  StructureOptions options;
  options.scheme = Scheme::Tangential;
  const StructureResult tangential = make_conformal_structure(t, lbar, options);
  options.scheme = Scheme::Thurston;
  const StructureResult thurston = make_conformal_structure(t, lbar, options);
  EXPECT_LE(thurston.fit_rms_relative_error, tangential.fit_rms_relative_error);
  EXPECT_LT(thurston.fit_rms_relative_error, 0.1);
  EXPECT_GT(tangential.fit_rms_relative_error, 0.0);  // touching circles cannot fit this disk
  for (int e = 0; e < t.num_edges; ++e) {
    EXPECT_GE(thurston.structure.eta[e], 0.0);  // Phi in [0, pi/2]
    EXPECT_LE(thurston.structure.eta[e], 1.0);
  }
  // The reported RMS matches the lengths of the fitted metric.
  Eigen::VectorXd l;
  edge_lengths(t, thurston.structure, thurston.structure.initial_u, l);
  EXPECT_NEAR(std::sqrt((l - lbar).squaredNorm() / lbar.squaredNorm()),
              thurston.fit_rms_relative_error, 1e-14);
}

TEST(Scheme, UnitRadiiShortcutGivesEqualEdges) {
  const Mesh mesh = make_icosphere(1);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  StructureOptions options;
  options.scheme = Scheme::Thurston;
  options.packing_init = PackingInit::UnitRadii;
  const StructureResult r = make_conformal_structure(t, input_edge_lengths(mesh, t), options);
  Eigen::VectorXd l;
  edge_lengths(t, r.structure, r.structure.initial_u, l);
  EXPECT_NEAR(l.minCoeff(), 2.0, 1e-15);
  EXPECT_NEAR(l.maxCoeff(), 2.0, 1e-15);
}

TEST(Scheme, NamesRoundTripAndBadNamesAreRejected) {
  for (const SchemeTraits& row : kSchemeTraits) {
    EXPECT_EQ(parse_scheme(scheme_name(row.scheme)), row.scheme);
  }
  EXPECT_EQ(parse_scheme("yamabe"), Scheme::VertexScaling);
  try {
    parse_scheme("circle");
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("'circle'"), std::string::npos);
  }
}

TEST(Scheme, NonPositiveInputLengthIsRejected) {
  const Mesh mesh = make_tetrahedron(1.0);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  Eigen::VectorXd lbar = input_edge_lengths(mesh, t);
  lbar[3] = 0;
  EXPECT_THROW(make_conformal_structure(t, lbar), InvalidInput);
}

}  // namespace
}  // namespace ricci
