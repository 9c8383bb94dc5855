#include "ricci/mesh/generate.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "ricci/errors.hpp"
#include "ricci/mesh/topology.hpp"

namespace ricci {
namespace {

using Point = Eigen::Vector3d;

constexpr double kDegree = std::numbers::pi / 180.0;

Point corner(const Mesh& mesh, int f, int k) {
  return mesh.positions.row(mesh.triangles(f, k)).transpose();
}

/// Area-weighted normal (twice the area, counter-clockwise orientation) of face f.
Point face_normal(const Mesh& mesh, int f) {
  return (corner(mesh, f, 1) - corner(mesh, f, 0)).cross(corner(mesh, f, 2) - corner(mesh, f, 0));
}

/// Smallest corner angle of the mesh, in radians, measured with atan2 (accurate near 0 and pi).
double min_corner_angle(const Mesh& mesh) {
  double smallest = std::numbers::pi;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Point u = corner(mesh, f, (k + 1) % 3) - corner(mesh, f, k);
      const Point v = corner(mesh, f, (k + 2) % 3) - corner(mesh, f, k);
      smallest = std::min(smallest, std::atan2(u.cross(v).norm(), u.dot(v)));
    }
  }
  return smallest;
}

/// Signed volume by the divergence theorem: sum over faces of p0 . (p1 x p2) / 6. Positive for a
/// closed surface whose faces are counter-clockwise seen from outside.
double signed_volume(const Mesh& mesh) {
  double volume = 0.0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    volume += corner(mesh, f, 0).dot(corner(mesh, f, 1).cross(corner(mesh, f, 2))) / 6.0;
  }
  return volume;
}

double total_area(const Mesh& mesh) {
  double area = 0.0;
  for (int f = 0; f < mesh.num_faces(); ++f) area += 0.5 * face_normal(mesh, f).norm();
  return area;
}

/// Smallest face area over the mean face area: catches degenerate and collapsed faces, which a
/// smallest angle alone would miss only for tiny well-shaped faces.
double min_area_ratio(const Mesh& mesh) {
  double smallest = INFINITY;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    smallest = std::min(smallest, 0.5 * face_normal(mesh, f).norm());
  }
  return smallest / (total_area(mesh) / mesh.num_faces());
}

/// Builds the topology (which throws on non-manifold or inconsistently oriented input) and checks
/// the counts that a generator promises.
Topology expect_topology(const Mesh& mesh, int euler_characteristic, int genus,
                         int boundary_loops) {
  Topology topology = build_topology(mesh.triangles, mesh.num_vertices());
  EXPECT_EQ(topology.num_referenced_vertices(), mesh.num_vertices()) << "unreferenced vertices";
  EXPECT_EQ(topology.components.size(), 1u);
  EXPECT_EQ(topology.euler_characteristic(), euler_characteristic);
  EXPECT_EQ(topology.num_boundary_loops(), boundary_loops);
  if (!topology.components.empty()) {
    EXPECT_EQ(topology.components[0].genus, genus);
  }
  return topology;
}

/// Runs `make`, expects InvalidInput, and checks that the message names the function and the
/// offending value.
template <typename Make>
void expect_invalid(Make make, const std::string& function, const std::string& value) {
  try {
    make();
    ADD_FAILURE() << function << " accepted " << value;
  } catch (const InvalidInput& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(function + ":"), std::string::npos) << message;
    EXPECT_NE(message.find(value), std::string::npos) << message;
  }
}

TEST(GenerateTetrahedron, AllEdgesEqualAndOutward) {
  for (double edge : {1.0, 2.5, 1e-3}) {
    const Mesh mesh = make_tetrahedron(edge);
    ASSERT_EQ(mesh.num_vertices(), 4);
    ASSERT_EQ(mesh.num_faces(), 4);
    expect_topology(mesh, 2, 0, 0);
    // Every coordinate is +-s, so the six lengths agree to the rounding of one square root.
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) {
        EXPECT_NEAR((mesh.positions.row(a) - mesh.positions.row(b)).norm(), edge, 1e-14 * edge);
      }
    }
    // Regular tetrahedron: V = e^3 / (6 sqrt 2); a few roundings in a sum of four terms.
    EXPECT_NEAR(signed_volume(mesh), edge * edge * edge / (6.0 * std::numbers::sqrt2),
                1e-14 * edge * edge * edge);
    EXPECT_NEAR(mesh.positions.colwise().sum().norm(), 0.0, 1e-15 * edge);  // centred
    EXPECT_NEAR(min_corner_angle(mesh), std::numbers::pi / 3, 1e-12);
  }
}

TEST(GenerateIcosphere, CountsSphereAndOrientation) {
  const double radius = 2.5;
  for (int s = 0; s <= 4; ++s) {
    const Mesh mesh = make_icosphere(s, radius);
    const int power = 1 << (2 * s);
    ASSERT_EQ(mesh.num_vertices(), 10 * power + 2);
    ASSERT_EQ(mesh.num_faces(), 20 * power);
    const Topology topology = expect_topology(mesh, 2, 0, 0);
    // Every vertex is normalised then scaled: relative error a few ulps.
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      EXPECT_NEAR(mesh.positions.row(v).norm(), radius, 1e-14 * radius) << "vertex " << v;
    }
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const Point centroid = (corner(mesh, f, 0) + corner(mesh, f, 1) + corner(mesh, f, 2)) / 3;
      EXPECT_GT(face_normal(mesh, f).dot(centroid), 0.0) << "face " << f << " points inwards";
    }
    // Measured: 60 degrees for s = 0, then 55.6, 54.4, 54.1, 54.0 (the limit of midpoint
    // subdivision with projection is just under 54).
    EXPECT_GT(min_corner_angle(mesh), 53.9 * kDegree) << "s = " << s;
    // The inscribed polyhedron has less volume than the ball; the gap shrinks like h^2 and is
    // 0.22% at s = 4.
    const double ball = 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
    EXPECT_LT(signed_volume(mesh), ball);
    if (s == 4) {
      EXPECT_NEAR(signed_volume(mesh) / ball, 1.0, 3e-3);
    }
    // Valences: the 12 icosahedron vertices keep degree 5, every other vertex has degree 6.
    const auto fives = std::count(topology.vertex_degree.begin(), topology.vertex_degree.end(), 5);
    const auto sixes = std::count(topology.vertex_degree.begin(), topology.vertex_degree.end(), 6);
    EXPECT_EQ(fives, 12);
    EXPECT_EQ(fives + sixes, mesh.num_vertices());
  }
}

TEST(GenerateDisk, CountsBoundaryAndCap) {
  for (int rings : {1, 2, 5, 20}) {
    for (double bulge : {0.0, 0.5, -1.0}) {
      const Mesh mesh = make_disk(rings, bulge);
      ASSERT_EQ(mesh.num_vertices(), 1 + 3 * rings * (rings + 1));
      ASSERT_EQ(mesh.num_faces(), 6 * rings * rings);
      const Topology topology = expect_topology(mesh, 1, 0, 1);
      ASSERT_EQ(topology.boundary_loops[0].size(), static_cast<std::size_t>(6 * rings));
      for (int v : topology.boundary_loops[0]) {
        const double r = mesh.positions.row(v).head<2>().norm();
        EXPECT_NEAR(r, 1.0, 1e-15);
        EXPECT_NEAR(mesh.positions(v, 2), 0.0, 1e-15);  // the cap meets z = 0 on the rim
      }
      for (int v = 0; v < mesh.num_vertices(); ++v) {
        const double r2 = mesh.positions.row(v).head<2>().squaredNorm();
        EXPECT_NEAR(mesh.positions(v, 2), bulge * (1.0 - r2), 1e-15);
      }
      // Counter-clockwise seen from +z: every normal has a positive z component, whatever the
      // sign of the bulge (the cap is a graph over the disk).
      for (int f = 0; f < mesh.num_faces(); ++f) EXPECT_GT(face_normal(mesh, f)(2), 0.0);
      // Measured: 44 degrees or more flat (60 for one ring), 25.2 or more for |bulge| <= 1,
      // where the steep rim of the cap stretches the radial edges.
      EXPECT_GT(min_corner_angle(mesh), (bulge == 0.0 ? 43.5 : 25.0) * kDegree)
          << "rings = " << rings << ", bulge = " << bulge;
      // Hexagonal lattice: every interior vertex, the centre included, has degree 6.
      for (int v = 0; v < mesh.num_vertices(); ++v) {
        if (!topology.is_boundary_vertex[v]) {
          EXPECT_EQ(topology.vertex_degree[v], 6);
        }
      }
    }
  }
  // Flat, the triangles tile the regular 6 rings-gon inscribed in the unit circle without
  // overlap, so their areas add up to the polygon's, (n / 2) sin(2 pi / n), up to rounding.
  for (int rings : {1, 3, 20}) {
    const int n = 6 * rings;
    EXPECT_NEAR(total_area(make_disk(rings)), 0.5 * n * std::sin(2.0 * std::numbers::pi / n),
                1e-13);
  }
}

TEST(GenerateTorus, CountsOrientationAndShape) {
  const double big = 1.5, small = 0.5;
  for (auto [major, minor] : {std::pair{3, 3}, {8, 4}, {24, 12}, {40, 17}}) {
    const Mesh mesh = make_torus(major, minor, big, small);
    ASSERT_EQ(mesh.num_vertices(), major * minor);
    ASSERT_EQ(mesh.num_faces(), 2 * major * minor);
    const Topology topology = expect_topology(mesh, 0, 1, 0);
    for (int v = 0; v < mesh.num_vertices(); ++v) EXPECT_EQ(topology.vertex_degree[v], 6);
    // Outward: the normal points away from the core circle of radius R. (Only from 8 x 4 on:
    // the faces of the 3 x 3 torus are chords so long that their centroids leave the torus.)
    for (int f = 0; f < mesh.num_faces() && major >= 8; ++f) {
      const Point centroid = (corner(mesh, f, 0) + corner(mesh, f, 1) + corner(mesh, f, 2)) / 3;
      Point core(centroid(0), centroid(1), 0.0);
      core *= big / core.norm();
      EXPECT_GT(face_normal(mesh, f).dot(centroid - core), 0.0) << "face " << f;
    }
    // Vertices on the torus: (sqrt(x^2 + y^2) - R)^2 + z^2 = r^2.
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const double ring = mesh.positions.row(v).head<2>().norm() - big;
      EXPECT_NEAR(std::hypot(ring, mesh.positions(v, 2)), small, 1e-14);  // a few ulps of R
    }
    EXPECT_GT(signed_volume(mesh), 0.0);
    EXPECT_GT(min_area_ratio(mesh), 0.2);
  }
  // At 40 x 17 the volume is within 2.5% of 2 pi^2 R r^2 (the deficit of an inscribed polygon
  // of n sides is about (2 pi / n)^2 / 6 in each direction: 0.4% + 2.3%; measured 2.66%).
  const double exact = 2.0 * std::numbers::pi * std::numbers::pi * big * small * small;
  EXPECT_NEAR(signed_volume(make_torus(40, 17, big, small)) / exact, 1.0, 0.03);
  // Quality: right triangles with legs (R +- r) 2 pi / major and r 2 pi / minor; for the default
  // radii and major = 2 minor that is atan(0.4 / 1.4 * 2) = 29.7 degrees at the outer equator.
  EXPECT_GT(min_corner_angle(make_torus(24, 12)), 29.7 * kDegree);
  EXPECT_GT(min_corner_angle(make_torus(200, 100)), 29.7 * kDegree);
}

TEST(GenerateTorus, ScalesToLargeGrids) {
  // 200 x 100 is 40000 faces; the 1000 x 500 benchmark mesh uses the same loops.
  const Mesh mesh = make_torus(200, 100);
  EXPECT_EQ(mesh.num_faces(), 40000);
  expect_topology(mesh, 0, 1, 0);
}

TEST(GenerateGrid, CountsFlatnessAndArea) {
  for (auto [nx, ny, w, h] : {std::tuple{1, 1, 1.0, 1.0}, {4, 3, 2.0, 1.0}, {7, 13, 0.5, 3.0}}) {
    const Mesh mesh = make_grid(nx, ny, w, h);
    ASSERT_EQ(mesh.num_vertices(), (nx + 1) * (ny + 1));
    ASSERT_EQ(mesh.num_faces(), 2 * nx * ny);
    const Topology topology = expect_topology(mesh, 1, 0, 1);
    EXPECT_EQ(topology.boundary_loops[0].size(), static_cast<std::size_t>(2 * (nx + ny)));
    for (int v = 0; v < mesh.num_vertices(); ++v) EXPECT_EQ(mesh.positions(v, 2), 0.0);
    EXPECT_EQ(mesh.positions.col(0).minCoeff(), 0.0);
    EXPECT_EQ(mesh.positions.col(0).maxCoeff(), w);
    EXPECT_EQ(mesh.positions.col(1).minCoeff(), 0.0);
    EXPECT_EQ(mesh.positions.col(1).maxCoeff(), h);
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const Point n = face_normal(mesh, f);
      EXPECT_GT(n(2), 0.0);
      EXPECT_EQ(n(0), 0.0);
      EXPECT_EQ(n(1), 0.0);
    }
    EXPECT_NEAR(total_area(mesh), w * h, 1e-14 * w * h);
    // Right triangles with legs w / nx and h / ny.
    const double dx = w / nx, dy = h / ny;
    EXPECT_NEAR(min_corner_angle(mesh), std::atan(std::min(dx, dy) / std::max(dx, dy)), 1e-12);
  }
}

TEST(GenerateClosedSurface, TopologyOrientationAndQuality) {
  for (int genus = 0; genus <= 6; ++genus) {
    for (int resolution : {1, 6, 12, 30}) {
      SCOPED_TRACE("genus " + std::to_string(genus) + ", resolution " + std::to_string(resolution));
      const Mesh mesh = make_closed_surface(genus, resolution);
      // Face count of the solid's boundary in unit squares: genus 0 is a cube of k^3 cells
      // (6 k^2 squares); genus g has 2 (5g + 3) k^2 squares on top and bottom and
      // (2 (2g + 4) + 4g) k^2 on the walls, 2 triangles each. V = F / 2 + chi.
      const int columns = genus == 0 ? 1 : 2 * genus + 1;
      const int k = std::max(1, static_cast<int>(std::lround(double(resolution) / columns)));
      const int faces = genus == 0 ? 12 * k * k : (36 * genus + 28) * k * k;
      const int chi = 2 - 2 * genus;
      EXPECT_EQ(mesh.num_faces(), faces);
      EXPECT_EQ(mesh.num_vertices(), faces / 2 + chi);
      expect_topology(mesh, chi, genus, 0);
      // Consistent orientation (checked by the topology) and one component: a positive volume
      // means every face points outwards. The plate of unit cubes has volume 1 (genus 0) or
      // 5g + 3; smoothing rounds the edges off and Taubin's inflating step puts back a little
      // more: measured ratios 1.000 to 1.016.
      const double solid = genus == 0 ? 1.0 : 5.0 * genus + 3.0;
      EXPECT_NEAR(signed_volume(mesh) / solid, 1.0, 0.05);
      // Measured: 45 degrees at k = 1 (unsmoothed right isosceles triangles), 37.4 to 40.5
      // from k = 2 on, where smoothing bends the squares near the edges.
      EXPECT_GT(min_corner_angle(mesh), 37.0 * kDegree);
      EXPECT_GT(min_area_ratio(mesh), 0.3);
    }
  }
}

TEST(GenerateClosedSurface, HighGenus) {
  const Mesh mesh = make_closed_surface(10, 21);
  expect_topology(mesh, -18, 10, 0);
  EXPECT_GT(signed_volume(mesh), 0.0);
  EXPECT_GT(min_corner_angle(mesh), 37.0 * kDegree);
}

TEST(GenerateSurfaceWithHoles, TopologyAndPlacement) {
  for (int genus = 0; genus <= 4; ++genus) {
    for (int holes : {0, 1, 2, 4}) {
      for (int resolution : {12, 24}) {
        SCOPED_TRACE("genus " + std::to_string(genus) + ", holes " + std::to_string(holes) +
                     ", resolution " + std::to_string(resolution));
        const Mesh mesh = make_surface_with_holes(genus, holes, resolution);
        const Topology topology = expect_topology(mesh, 2 - 2 * genus - holes, genus, holes);
        // The holes are cut into the top face (z = +0.5 before smoothing, which moves it by
        // less than 0.02 at k = 3 and not at all further from the edges).
        for (const auto& loop : topology.boundary_loops) {
          EXPECT_GE(loop.size(), 4u);
          for (int v : loop) EXPECT_GT(mesh.positions(v, 2), 0.45);
        }
        EXPECT_GT(min_corner_angle(mesh), 37.0 * kDegree);
        EXPECT_GT(min_area_ratio(mesh), 0.3);
      }
    }
  }
  // Without holes it is the closed surface.
  const Mesh closed = make_closed_surface(2, 24);
  const Mesh none = make_surface_with_holes(2, 0, 24);
  EXPECT_EQ(none.triangles, closed.triangles);
  EXPECT_EQ(none.positions, closed.positions);
}

TEST(GenerateSurfaceWithHoles, RefusesMoreHolesThanFit) {
  // A cube at resolution 3 has room for one 1-pixel hole in the middle of its top face only.
  EXPECT_NO_THROW(make_surface_with_holes(0, 1, 3));
  expect_invalid([] { make_surface_with_holes(0, 2, 3); }, "make_surface_with_holes",
                 "got holes = 2");
}

TEST(GenerateErrors, InvalidArgumentsNameFunctionAndValue) {
  expect_invalid([] { make_tetrahedron(0.0); }, "make_tetrahedron", "got 0");
  expect_invalid([] { make_tetrahedron(NAN); }, "make_tetrahedron", "nan");
  expect_invalid([] { make_icosphere(-1); }, "make_icosphere", "got -1");
  expect_invalid([] { make_icosphere(13); }, "make_icosphere", "got 13");
  expect_invalid([] { make_icosphere(1, -2.0); }, "make_icosphere", "got -2");
  expect_invalid([] { make_disk(0); }, "make_disk", "got 0");
  expect_invalid([] { make_disk(3, INFINITY); }, "make_disk", "inf");
  expect_invalid([] { make_torus(2, 8); }, "make_torus", "major_segments must be >= 3, got 2");
  expect_invalid([] { make_torus(8, 1); }, "make_torus", "minor_segments must be >= 3, got 1");
  expect_invalid([] { make_torus(8, 8, 1.0, 1.0); }, "make_torus", "minor_radius");
  expect_invalid([] { make_torus(8, 8, -1.0, 0.5); }, "make_torus", "major_radius");
  expect_invalid([] { make_torus(100000, 100000); }, "make_torus", "int index range");
  expect_invalid([] { make_grid(0, 3); }, "make_grid", "nx must be >= 1, got 0");
  expect_invalid([] { make_grid(3, -4); }, "make_grid", "ny must be >= 1, got -4");
  expect_invalid([] { make_grid(3, 3, 0.0); }, "make_grid", "width");
  expect_invalid([] { make_closed_surface(-1); }, "make_closed_surface", "genus must be >= 0");
  expect_invalid([] { make_closed_surface(1, 0); }, "make_closed_surface",
                 "resolution must be >= 1, got 0");
  expect_invalid([] { make_closed_surface(1, 1000000); }, "make_closed_surface", "int index range");
  expect_invalid([] { make_surface_with_holes(1, -1); }, "make_surface_with_holes",
                 "holes must be >= 0, got -1");
}

}  // namespace
}  // namespace ricci
