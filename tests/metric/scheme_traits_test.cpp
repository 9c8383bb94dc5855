// The scheme table (kSchemeTraits) walked row by row: each row's names parse back to it, and
// each trait agrees with what the scheme does, so that a new row cannot claim what its
// construction does not deliver. A new scheme needs no change here.
#include <cmath>
#include <cstddef>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "ricci/errors.hpp"
#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/metric/background.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/metric/scheme.hpp"
#include "support/metric_helpers.hpp"

namespace ricci {
namespace {

using testing::structure_of;

TEST(SchemeTraits, OneRowPerSchemeInTheOrderOfTheEnum) {
  for (std::size_t i = 0; i < kSchemeTraits.size(); ++i) {
    const SchemeTraits& row = kSchemeTraits[i];
    EXPECT_EQ(static_cast<std::size_t>(row.scheme), i) << row.name;
    EXPECT_EQ(&scheme_traits(row.scheme), &row) << row.name;
  }
  EXPECT_THROW(scheme_traits(static_cast<Scheme>(kSchemeTraits.size())), InvalidInput);
}

TEST(SchemeTraits, NamesParseBackToTheirRow) {
  for (const SchemeTraits& row : kSchemeTraits) {
    EXPECT_STREQ(scheme_name(row.scheme), row.name);
    EXPECT_EQ(parse_scheme(row.name), row.scheme) << row.name;
    if (row.alias) {
      EXPECT_EQ(parse_scheme(row.alias), row.scheme) << row.alias;
    }
    EXPECT_EQ(find_enum<Scheme>(row.identifier), std::nullopt) << "Python names are not parsed";
  }
}

TEST(SchemeTraits, EpsilonPackingAndAnglesAgreeWithTheConstruction) {
  const Mesh mesh = make_icosphere(2);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  for (const SchemeTraits& row : kSchemeTraits) {
    SCOPED_TRACE(row.name);
    const ConformalStructure s = structure_of(mesh, t, row.scheme);
    EXPECT_EQ(s.scheme, row.scheme);
    ASSERT_EQ(s.epsilon.size(), t.num_vertices);
    EXPECT_TRUE((s.epsilon.array() == row.epsilon).all());
    // Packings: eta = cos Phi with Phi in [0, pi/2]; Thurston fits Phi (some edge below 1 on a
    // curved mesh), tangential keeps Phi = 0.
    if (row.circle_packing) {
      EXPECT_GE(s.eta.minCoeff(), 0.0);
      EXPECT_LE(s.eta.maxCoeff(), 1.0);
      EXPECT_EQ(s.eta.minCoeff() < 1.0, row.fitted_intersection_angles);
    } else {
      EXPECT_FALSE(row.fitted_intersection_angles);
    }
    // Every face gives its vertex at least the guaranteed angle of the single-vertex bound, and
    // at most pi.
    for (int e = 0; e < t.num_edges; ++e) {
      const double angle = max_face_angle(row, s.eta[e]);
      EXPECT_GE(angle, row.guaranteed_face_angle) << "edge " << e;
      EXPECT_LE(angle, std::numbers::pi) << "edge " << e;
    }
    EXPECT_EQ(row.guaranteed_face_angle,
              row.circle_packing ? std::numbers::pi / 2 : std::numbers::pi);
  }
}

TEST(SchemeTraits, PtolemyFlipsAreAllowedExactlyWhereTheTableSays) {
  const Mesh mesh = make_icosphere(1);
  for (const SchemeTraits& row : kSchemeTraits) {
    SCOPED_TRACE(row.name);
    Topology t = build_topology(mesh.triangles, mesh.num_vertices());
    ConformalStructure s = structure_of(mesh, t, row.scheme);
    // Ptolemy's relation is that of epsilon = 0.
    EXPECT_EQ(row.ptolemy_flips, row.epsilon == 0.0);
    Eigen::VectorXd u = s.initial_u, l;
    ASSERT_EQ(edge_lengths(t, s, u, l).invalid_edges, 0);
    if (row.ptolemy_flips) {
      EXPECT_NO_THROW(flip_to_delaunay(t, s, u, l));
    } else {
      EXPECT_THROW(flip_to_delaunay(t, s, u, l), InvalidInput);
    }
  }
}

TEST(SchemeTraits, HyperbolicBackgroundIsOfferedExactlyWhereTheTableSays) {
  const Mesh mesh = make_closed_surface(2, 6);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  for (const SchemeTraits& row : kSchemeTraits) {
    SCOPED_TRACE(row.name);
    if (row.hyperbolic) {
      const ConformalStructure s = structure_of(mesh, t, row.scheme, Geometry::Hyperbolic);
      EXPECT_EQ(s.geometry, Geometry::Hyperbolic);
      EXPECT_TRUE((s.epsilon.array() == row.epsilon).all());
    } else {
      EXPECT_THROW(structure_of(mesh, t, row.scheme, Geometry::Hyperbolic), InvalidInput);
    }
  }
}

TEST(GeometryTraits, OneRowPerGeometryWhoseNameParsesBack) {
  for (std::size_t i = 0; i < kGeometryTraits.size(); ++i) {
    const GeometryTraits& row = kGeometryTraits[i];
    EXPECT_EQ(static_cast<std::size_t>(row.geometry), i);
    EXPECT_EQ(&geometry_traits(row.geometry), &row);
    EXPECT_STREQ(geometry_name(row.geometry), row.name);
    EXPECT_EQ(parse_geometry(row.name), row.geometry);
    // The gauge u += c exists exactly where Gauss-Bonnet has no area term.
    EXPECT_NE(row.scale_gauge, row.area_in_gauss_bonnet);
  }
}

}  // namespace
}  // namespace ricci
