#include "ricci/flow/target.hpp"

#include <cmath>
#include <fstream>
#include <functional>
#include <numbers>

#include <gtest/gtest.h>

#include "ricci/errors.hpp"
#include "ricci/mesh/generate.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

struct Fixture {
  Mesh mesh;
  Topology t;
  ConformalStructure s;
  Eigen::VectorXd lbar;
  explicit Fixture(Mesh m) : mesh(std::move(m)) {
    t = build_topology(mesh.triangles, mesh.num_vertices());
    lbar = input_edge_lengths(mesh, t);
    s = make_conformal_structure(t, lbar).structure;
  }
};

TEST(Target, FlatWithConesOnAClosedSurface) {
  Fixture f(make_icosphere(1));
  const Target target = flat_target(f.t, {{0, std::numbers::pi},
                                          {7, std::numbers::pi},
                                          {9, std::numbers::pi},
                                          {11, std::numbers::pi}});
  EXPECT_EQ(target.curvature.sum(), 4 * std::numbers::pi);
  EXPECT_FALSE(target.has_fixed_vertices());
  EXPECT_NO_THROW(check_admissible(f.t, f.s, target));
  EXPECT_EQ(target.description, "flat with 4 cones");
}

TEST(Target, FreeBoundaryFixesTheBoundary) {
  Fixture f(make_disk(4));
  const Target target = flat_target(f.t, {});
  for (int v = 0; v < f.t.num_vertices; ++v) {
    EXPECT_EQ(target.fixed[v], f.t.is_boundary_vertex[v]);
    EXPECT_EQ(target.curvature[v], 0.0);
  }
  // No Gauss-Bonnet condition where u is fixed somewhere.
  EXPECT_NO_THROW(check_admissible(f.t, f.s, target));
}

TEST(Target, DiskBoundaryUniformAndProportionalToLength) {
  Fixture f(make_disk(4, 0.5));
  const Target uniform = flat_target(f.t, {}, BoundaryMode::DiskUniform);
  const auto& loop = f.t.boundary_loops[0];
  const double m = static_cast<double>(loop.size());
  for (int v : loop) EXPECT_NEAR(uniform.curvature[v], 2 * std::numbers::pi / m, 1e-15);
  EXPECT_NO_THROW(check_admissible(f.t, f.s, uniform));

  // Make one boundary edge longer: its ends get more curvature.
  Eigen::VectorXd lengths = f.lbar;
  double perimeter = 0;
  for (int e = 0; e < f.t.num_edges; ++e) {
    if (f.t.is_boundary_edge[e]) perimeter += lengths[e];
  }
  const Target by_length = flat_target(f.t, {}, BoundaryMode::DiskLength, lengths);
  double total = 0;
  for (int v : loop) total += by_length.curvature[v];
  EXPECT_NEAR(total, 2 * std::numbers::pi, 1e-13);
  for (int e = 0; e < f.t.num_edges; ++e) {
    if (!f.t.is_boundary_edge[e]) continue;
    // Each boundary edge hands half its share of 2 pi to each end.
    const int a = f.t.edge_vertices(e, 0);
    double around = 0;
    for (int g = 0; g < f.t.num_edges; ++g) {
      if (f.t.is_boundary_edge[g] && (f.t.edge_vertices(g, 0) == a || f.t.edge_vertices(g, 1) == a))
        around += 0.5 * lengths[g];
    }
    EXPECT_NEAR(by_length.curvature[a], 2 * std::numbers::pi * around / perimeter, 1e-14);
  }
  EXPECT_THROW(flat_target(f.t, {}, BoundaryMode::DiskLength), InvalidInput);
}

TEST(Target, UniformSumsToTwoPiChi) {
  Fixture f(make_closed_surface(2, 6));
  const Target target = uniform_target(f.t);
  EXPECT_NEAR(target.curvature.sum(), 2 * std::numbers::pi * -2, 1e-11);
  EXPECT_NEAR(target.curvature[0], 2 * std::numbers::pi * -2 / f.t.num_vertices, 1e-15);
  EXPECT_NO_THROW(check_admissible(f.t, f.s, target));
}

TEST(Target, GaussBonnetViolationNamesTheComponentAndTheSums) {
  Fixture f(make_icosphere(1));
  const Target target = flat_target(f.t, {{0, std::numbers::pi}});
  const std::string m = message_of([&] { check_admissible(f.t, f.s, target); });
  EXPECT_NE(m.find("Gauss-Bonnet"), std::string::npos) << m;
  EXPECT_NE(m.find("component 0"), std::string::npos) << m;
  EXPECT_NE(m.find("12.566"), std::string::npos) << m;  // 2 pi chi = 4 pi
}

TEST(Target, SingleVertexBoundNamesTheVertexAndTheBound) {
  Fixture f(make_icosphere(1));  // valence 5 or 6
  // Vertex 0 has valence 5: K > 2 pi - 5 pi = -3 pi at best (Phi = 0); ask for -4 pi.
  ASSERT_EQ(f.t.vertex_degree[0], 5);
  const Target target = flat_target(
      f.t, {{0, -4 * std::numbers::pi}, {1, 4 * std::numbers::pi + 2 * std::numbers::pi}});
  const std::string m = message_of([&] { check_admissible(f.t, f.s, target); });
  EXPECT_NE(m.find("vertex 0"), std::string::npos) << m;
  EXPECT_NE(m.find("single-vertex bound"), std::string::npos) << m;
  EXPECT_NE(m.find("valence 5"), std::string::npos) << m;
  // And the upper bound 2 pi.
  const Target above = flat_target(f.t, {{2, 2 * std::numbers::pi}, {1, 2 * std::numbers::pi}});
  const std::string m2 = message_of([&] { check_admissible(f.t, f.s, above); });
  EXPECT_NE(m2.find("vertex 1"), std::string::npos) << m2;
  EXPECT_NE(m2.find("must be below"), std::string::npos) << m2;
}

/// The fixes an InvalidInput carries, or a failure when f does not throw one.
std::vector<OptionFix> fixes_from(const std::function<void()>& f) {
  try {
    f();
  } catch (const InvalidInput& e) {
    return e.fixes();
  }
  ADD_FAILURE() << "no InvalidInput thrown";
  return {};
}

TEST(Target, RefusalsNameTheOptionThatWorks) {
  Fixture f(make_icosphere(1));
  // A flat target with too little curvature: the natural or the uniform target.
  const Target flat = flat_target(f.t, {{0, std::numbers::pi}});
  EXPECT_EQ(fixes_from([&] { check_admissible(f.t, f.s, flat); }),
            (std::vector<OptionFix>{{"target", "natural"}, {"target", "uniform"}}));
  // The single-vertex bound: edge flips lift it for vertex scaling; a circle packing gets
  // vertex scaling, and the tangential scheme only where its wider bound (2 pi - 5 pi at a
  // valence-5 vertex) holds.
  ASSERT_EQ(f.s.scheme, Scheme::VertexScaling);
  const Target deep = flat_target(
      f.t, {{0, -4 * std::numbers::pi}, {1, 4 * std::numbers::pi + 2 * std::numbers::pi}});
  EXPECT_EQ(fixes_from([&] { check_admissible(f.t, f.s, deep); }),
            (std::vector<OptionFix>{{"flips", "auto"}}));
  ConformalStructure packing = f.s;
  packing.scheme = Scheme::Thurston;
  EXPECT_EQ(fixes_from([&] { check_admissible(f.t, packing, deep); }),
            (std::vector<OptionFix>{{"scheme", "vertex-scaling"}}));
  const Target within_tangential = flat_target(
      f.t, {{0, -2.5 * std::numbers::pi}, {1, 2.5 * std::numbers::pi + 2 * std::numbers::pi}});
  EXPECT_EQ(fixes_from([&] { check_admissible(f.t, packing, within_tangential); }),
            (std::vector<OptionFix>{{"scheme", "vertex-scaling"}, {"scheme", "tangential"}}));
  // A sphere in the hyperbolic background: the Euclidean one.
  ConformalStructure hyperbolic = f.s;
  hyperbolic.geometry = Geometry::Hyperbolic;
  const Target zero = flat_target(f.t, {});
  EXPECT_EQ(fixes_from([&] { check_admissible(f.t, hyperbolic, zero); }),
            (std::vector<OptionFix>{{"geometry", "euclidean"}}));
  // A cone on a free boundary: the disk boundary.
  Fixture d(make_disk(3));
  const int boundary_vertex = d.t.boundary_loops[0][0];
  EXPECT_EQ(fixes_from([&] {
              flat_target(d.t, {{boundary_vertex, 1.0}});
            }),
            (std::vector<OptionFix>{{"boundary", "disk"}}));
  // Nothing to suggest for a cone off the mesh.
  EXPECT_TRUE(fixes_from([&] { flat_target(d.t, {{1000, 1.0}}); }).empty());
}

TEST(Target, BadConesAreRejected) {
  Fixture f(make_disk(3));
  EXPECT_THROW(flat_target(f.t, {{1000, 1.0}}), InvalidInput);
  EXPECT_THROW(flat_target(f.t, {{0, 1.0}, {0, 1.0}}), InvalidInput);
  const int boundary_vertex = f.t.boundary_loops[0][0];
  const std::string m = message_of([&] { flat_target(f.t, {{boundary_vertex, 1.0}}); });
  EXPECT_NE(m.find("boundary vertex " + std::to_string(boundary_vertex)), std::string::npos) << m;
  EXPECT_THROW(values_target(f.t, Eigen::VectorXd::Zero(3)), InvalidInput);
}

TEST(Target, ParseCurvatureAcceptsPiForms) {
  EXPECT_EQ(parse_curvature("1.5"), 1.5);
  EXPECT_EQ(parse_curvature("pi"), std::numbers::pi);
  EXPECT_EQ(parse_curvature("-pi/2"), -std::numbers::pi / 2);
  EXPECT_EQ(parse_curvature("0.5pi"), 0.5 * std::numbers::pi);
  EXPECT_EQ(parse_curvature("3*pi/4"), 3 * std::numbers::pi / 4);
  EXPECT_EQ(parse_curvature(" -8pi "), -8 * std::numbers::pi);
  for (const char* bad : {"", "abc", "pi/0", "2pi/x", "nan", "inf", "1.5.2"}) {
    EXPECT_THROW(parse_curvature(bad), InvalidInput) << bad;
  }
  const std::vector<Cone> cones = parse_cone_list("3:pi/2, 17:-1.25");
  ASSERT_EQ(cones.size(), 2u);
  EXPECT_EQ(cones[1].vertex, 17);
  EXPECT_EQ(cones[1].curvature, -1.25);
  EXPECT_THROW(parse_cone_list("3=pi"), InvalidInput);
  EXPECT_THROW(parse_cone_list("-3:pi"), InvalidInput);
}

TEST(Target, ConeAndValueFilesNameTheBadLine) {
  const std::string dir = testing::test_tmp_dir();
  const std::string cones_path = dir + "/cones.txt", values_path = dir + "/values.txt";
  {
    std::ofstream out(cones_path);
    out << "# vertex curvature\n4 pi/2\n\n9 3.1\n12 oops\n";
  }
  std::string m = message_of([&] { read_cone_file(cones_path); });
  EXPECT_NE(m.find("cones.txt:5"), std::string::npos) << m;
  {
    std::ofstream out(cones_path);
    out << "4 pi/2\n9 3.1 # second\n";
  }
  const std::vector<Cone> cones = read_cone_file(cones_path);
  ASSERT_EQ(cones.size(), 2u);
  EXPECT_EQ(cones[0].curvature, std::numbers::pi / 2);
  {
    std::ofstream out(values_path);
    out << "0.1\n0.2\nx\n";
  }
  m = message_of([&] { read_values_file(values_path); });
  EXPECT_NE(m.find("values.txt:3"), std::string::npos) << m;
  EXPECT_THROW(read_values_file(dir + "/missing.txt"), IoError);
}

}  // namespace
}  // namespace ricci
