#include "ricci/intrinsic/delaunay_flips.hpp"

#include <cmath>
#include <complex>
#include <numbers>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/LU>

#include "ricci/errors.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/hyperbolic.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/numerics/complex.hpp"
#include "support/hard_meshes.hpp"
#include "support/test_meshes.hpp"

namespace ricci {
namespace {

/// Every array of a flipped topology agrees with the others, and (for a simplicial complex) with
/// build_topology run on its triangles.
void expect_consistent(const Topology& t, bool simplicial = true) {
  const int nh = 3 * t.num_faces;
  std::vector<int> degree(t.num_vertices, 0);
  for (int h = 0; h < nh; ++h) {
    const int e = t.halfedge_edge[h];
    ASSERT_EQ(t.face_edges(h / 3, h % 3), e) << "halfedge " << h;
    EXPECT_TRUE(t.edge_halfedges(e, 0) == h || t.edge_halfedges(e, 1) == h) << "halfedge " << h;
    EXPECT_EQ(std::min(t.tail(h), t.head(h)), t.edge_vertices(e, 0));
    EXPECT_EQ(std::max(t.tail(h), t.head(h)), t.edge_vertices(e, 1));
    const int g = t.halfedge_twin[h];
    if (g >= 0) {
      EXPECT_EQ(t.halfedge_twin[g], h);
      EXPECT_EQ(t.tail(g), t.head(h));
      EXPECT_EQ(t.halfedge_edge[g], e);
    }
  }
  for (int e = 0; e < t.num_edges; ++e) {
    ++degree[t.edge_vertices(e, 0)];
    ++degree[t.edge_vertices(e, 1)];
  }
  for (int v = 0; v < t.num_vertices; ++v) EXPECT_EQ(t.vertex_degree[v], degree[v]) << v;
  EXPECT_EQ(is_simplicial(t), simplicial);
  if (!simplicial) return;
  const Topology rebuilt = build_topology(t.triangles, t.num_vertices);  // throws if broken
  EXPECT_EQ(rebuilt.num_edges, t.num_edges);
  EXPECT_EQ(rebuilt.euler_characteristic(), t.euler_characteristic());
  EXPECT_EQ(rebuilt.boundary_loops.size(), t.boundary_loops.size());
}

/// Vertex scaling of the mesh's own lengths; in the hyperbolic background the input lengths are
/// first scaled to area 2 pi |chi|.
ConformalStructure vertex_scaling(const Mesh& mesh, const Topology& t,
                                  Geometry geometry = Geometry::Euclidean) {
  StructureOptions options;
  options.scheme = Scheme::VertexScaling;
  options.geometry = geometry;
  return make_conformal_structure(t, input_edge_lengths(mesh, t), options).structure;
}

/// Log scale factors drawn uniformly from [-bound, bound], the same on every run for a seed.
Eigen::VectorXd random_u(int num_vertices, unsigned seed, double bound) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-bound, bound);
  Eigen::VectorXd u(num_vertices);
  for (int v = 0; v < u.size(); ++v) u[v] = uniform(random);
  return u;
}

/// A closed surface under vertex scaling and its lengths at random u.
struct ScaledSurface {
  Topology t;
  ConformalStructure s;
  Eigen::VectorXd u, l;
  int invalid_edges = 0;  ///< among the lengths at u
};

/// make_closed_surface(genus, 8) in `geometry`, u drawn from [-bound, bound].
ScaledSurface scaled_closed_surface(int genus, Geometry geometry, double bound) {
  const Mesh mesh = make_closed_surface(genus, 8);
  ScaledSurface x;
  x.t = build_topology(mesh.triangles, mesh.num_vertices());
  x.s = vertex_scaling(mesh, x.t, geometry);
  x.u = random_u(mesh.num_vertices(), 5, bound);
  x.invalid_edges = edge_lengths(x.t, x.s, x.u, x.l).invalid_edges;
  return x;
}

/// Flips every seventh flippable edge of a genus-2 surface under vertex scaling in `geometry`
/// twice, with the lengths at random u and at u = 0, and expects the new edge to get the same eta
/// either way (to `eta_tolerance`): Ptolemy's relation commutes with vertex scaling, so a flip
/// never changes the conformal class. The flip at random u must also leave a structure that
/// reproduces the new length to 1e-14.
void expect_flips_keep_the_conformal_class(Geometry geometry, double eta_tolerance) {
  const Mesh mesh = make_closed_surface(2, 8);
  const Topology t0 = build_topology(mesh.triangles, mesh.num_vertices());
  const ConformalStructure s0 = vertex_scaling(mesh, t0, geometry);
  const Eigen::VectorXd u = random_u(t0.num_vertices, 3, 0.7);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(u.size());
  int tested = 0;
  for (int e = 0; e < t0.num_edges; e += 7) {
    if (!can_flip_edge(t0, e)) continue;
    Topology ta = t0, tb = t0;
    ConformalStructure sa = s0, sb = s0;
    Eigen::VectorXd la, lb;
    ASSERT_EQ(edge_lengths(ta, sa, u, la).invalid_edges, 0);
    ASSERT_EQ(edge_lengths(tb, sb, zero, lb).invalid_edges, 0);
    const double cd = ptolemy_flip(ta, sa, u, la, e);
    ptolemy_flip(tb, sb, zero, lb, e);
    EXPECT_NEAR(sa.eta[e] / sb.eta[e], 1.0, eta_tolerance) << "edge " << e;
    Eigen::VectorXd check;
    edge_lengths(ta, sa, u, check);
    EXPECT_NEAR(check[e] / cd, 1.0, 1e-14);
    ++tested;
  }
  EXPECT_GT(tested, 50);
}

TEST(DelaunayMargin, IsTwiceTheCosineSumOfTheOppositeAngles) {
  // Triangles (ab, ca, cb) = (1, 0.8, 0.7) and (1, 0.9, 0.6).
  const double gamma = angle_from_lengths(1.0, 0.8, 0.7);
  const double delta = angle_from_lengths(1.0, 0.9, 0.6);
  EXPECT_NEAR(delaunay_margin(1.0, 0.8, 0.7, 0.9, 0.6), 2 * (std::cos(gamma) + std::cos(delta)),
              1e-14);
  // Scale invariant, and defined where a triangle inequality fails (3 > 1 + 1).
  EXPECT_NEAR(delaunay_margin(1e200, 0.8e200, 0.7e200, 0.9e200, 0.6e200),
              delaunay_margin(1.0, 0.8, 0.7, 0.9, 0.6), 1e-13);
  EXPECT_LT(delaunay_margin(3.0, 1.0, 1.0, 2.0, 2.0), -4.0);
  EXPECT_TRUE(std::isfinite(delaunay_margin(3.0, 1.0, 1.0, 2.0, 2.0)));
}

TEST(FlipEdge, KeepsEveryArrayConsistentThroughRandomFlips) {
  for (const Mesh& mesh :
       {make_icosphere(2), make_disk(5, 0.3), make_torus(12, 8), make_closed_surface(2, 8)}) {
    Topology t = build_topology(mesh.triangles, mesh.num_vertices());
    std::mt19937 random(7);
    int flipped = 0;
    for (int trial = 0; trial < 400; ++trial) {
      const int e = static_cast<int>(random() % t.num_edges);
      if (!can_flip_edge(t, e, /*keep_simplicial=*/true)) continue;
      const int c = t.triangles(t.edge_halfedges(e, 0) / 3, t.edge_halfedges(e, 0) % 3);
      const int d = t.triangles(t.edge_halfedges(e, 1) / 3, t.edge_halfedges(e, 1) % 3);
      flip_edge(t, e);
      ++flipped;
      EXPECT_EQ(t.edge_vertices(e, 0), std::min(c, d));
      EXPECT_EQ(t.edge_vertices(e, 1), std::max(c, d));
    }
    EXPECT_GT(flipped, 100);
    expect_consistent(t);
  }
}

TEST(FlipEdge, MakesDeltaComplexesWhenAllowed) {
  // Random flips with no restriction: double edges, loops and faces using a vertex twice appear,
  // and every array stays consistent.
  const Mesh mesh = make_icosphere(1);
  Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  std::mt19937 random(11);
  int flipped = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const int e = static_cast<int>(random() % t.num_edges);
    if (!can_flip_edge(t, e)) continue;
    flip_edge(t, e);
    ++flipped;
  }
  EXPECT_GT(flipped, 1000);
  expect_consistent(t, /*simplicial=*/false);
  EXPECT_EQ(t.euler_characteristic(), 2);
}

TEST(FlipEdge, RefusesBoundaryEdgesAndDuplicateEdges) {
  // A tetrahedron: flipping any edge would join two vertices already joined (a Delta-complex
  // allows it).
  const Mesh tet = testing::tetrahedron();
  const Topology t = build_topology(tet.triangles, tet.num_vertices());
  for (int e = 0; e < t.num_edges; ++e) {
    EXPECT_FALSE(can_flip_edge(t, e, /*keep_simplicial=*/true));
    EXPECT_TRUE(can_flip_edge(t, e));
  }
  const Mesh disk = make_disk(3);
  const Topology d = build_topology(disk.triangles, disk.num_vertices());
  for (int e = 0; e < d.num_edges; ++e) {
    if (d.is_boundary_edge[e]) {
      EXPECT_FALSE(can_flip_edge(d, e));
    }
  }
}

TEST(QuadLengths, ReadFromEitherHalfedgeSwapTheRolesOfTheApexes) {
  const Mesh mesh = make_closed_surface(2, 8);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  const Eigen::VectorXd l = input_edge_lengths(mesh, t);
  for (int e = 0; e < t.num_edges; ++e) {
    const QuadLengths q0 = quad_lengths(t, l, t.edge_halfedges(e, 0));
    const QuadLengths q1 = quad_lengths(t, l, t.edge_halfedges(e, 1));
    // From b -> a the apex c is d, and a and b trade places.
    EXPECT_EQ(q0.ab, l[e]);
    EXPECT_EQ(q1.ab, q0.ab);
    EXPECT_EQ(q1.ca, q0.db);
    EXPECT_EQ(q1.cb, q0.da);
    EXPECT_EQ(q1.da, q0.cb);
    EXPECT_EQ(q1.db, q0.ca);
  }
}

TEST(QuadDiagonals, PtolemyOnTheLambdaLengthsAndTheIsometricDiagonal) {
  // Unit square with diagonal ab: both flips give the other diagonal, sqrt 2.
  const QuadLengths square{std::sqrt(2.0), 1, 1, 1, 1};
  EXPECT_NEAR(ptolemy_diagonal(square, Geometry::Euclidean), std::sqrt(2.0), 1e-15);
  EXPECT_EQ(isometric_diagonal(square, Geometry::Euclidean),
            euclidean_diagonal(std::sqrt(2.0), 1, 1, 1, 1));
  // In the hyperbolic background Ptolemy holds for sinh(l / 2).
  const QuadLengths q{0.9, 0.5, 0.6, 0.7, 0.4};
  const auto s = [](double x) { return std::sinh(0.5 * x); };
  EXPECT_NEAR(ptolemy_diagonal(q, Geometry::Hyperbolic),
              2 * std::asinh((s(q.ca) * s(q.db) + s(q.da) * s(q.cb)) / s(q.ab)), 1e-15);
  EXPECT_EQ(isometric_diagonal(q, Geometry::Hyperbolic),
            hyperbolic_diagonal(q.ab, q.ca, q.cb, q.da, q.db));
}

TEST(FlipToDelaunay, PtolemyGivesTheTrueDiagonalOfACyclicQuad) {
  // Four points on the unit circle, triangulated by the diagonal 0-2 that is not Delaunay for a
  // slightly moved point: on the circle every diagonal is allowed and Ptolemy is exact.
  const double angles[4] = {0.0, 0.3, 2.9, 4.0};
  Mesh quad;
  quad.positions.resize(4, 3);
  for (int i = 0; i < 4; ++i) quad.positions.row(i) << std::cos(angles[i]), std::sin(angles[i]), 0;
  quad.triangles.resize(2, 3);
  quad.triangles << 0, 1, 2, 0, 2, 3;
  Topology t = build_topology(quad.triangles, 4);
  ConformalStructure s = vertex_scaling(quad, t);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(4), l;
  edge_lengths(t, s, u, l);
  int diagonal = -1;
  for (int e = 0; e < t.num_edges; ++e) {
    if (!t.is_boundary_edge[e]) diagonal = e;
  }
  ASSERT_TRUE(can_flip_edge(t, diagonal, true));
  flip_edge(t, diagonal);
  // Ptolemy by hand: the new diagonal 1-3.
  const double expected = (quad.positions.row(1) - quad.positions.row(3)).norm();
  flip_edge(t, diagonal);  // back to 0-2
  Topology t2 = t;
  ConformalStructure s2 = s;
  Eigen::VectorXd l2 = l;
  // Force the flip with a large tolerance of the opposite sign: flip if margin < +inf.
  DelaunayFlipOptions always;
  always.tolerance = -10.0;
  always.max_flips = 1;
  const DelaunayFlipResult r = flip_to_delaunay(t2, s2, u, l2, always);
  EXPECT_EQ(r.flips, 1);
  EXPECT_NEAR(l2[diagonal], expected, 1e-15);
  // The flipped edge's constant reproduces the length at these u.
  Eigen::VectorXd again;
  edge_lengths(t2, s2, u, again);
  EXPECT_NEAR(again[diagonal], expected, 1e-15);
}

TEST(PtolemyFlip, KeepsTheConformalClassWhateverTheScaleFactors) {
  // Flipping an edge at random u or at u = 0 gives the new edge the same constant eta: Ptolemy's
  // relation commutes with vertex scaling, so a flip never changes the conformal class.
  expect_flips_keep_the_conformal_class(Geometry::Euclidean, 1e-14);
}

TEST(FlipToDelaunay, EndsDelaunayWithValidTrianglesOnAClosedSurface) {
  auto [t, s, u, l, invalid_edges] = scaled_closed_surface(2, Geometry::Euclidean, 1.0);
  ASSERT_EQ(invalid_edges, 0);
  const DelaunayFlipResult r = flip_to_delaunay(t, s, u, l);
  ASSERT_GT(r.flips, 10);
  EXPECT_TRUE(r.complete);
  expect_consistent(t, is_simplicial(t));
  EXPECT_EQ(r.blocked, 0);
  EXPECT_EQ(count_non_delaunay_edges(t, l), 0);
  // Lengths at u follow from the flipped constants.
  Eigen::VectorXd check;
  edge_lengths(t, s, u, check);
  EXPECT_LT(((check - l).array() / l.array()).abs().maxCoeff(), 1e-14);
  // Every triangle of a Delaunay triangulation of a closed surface satisfies the triangle
  // inequality: a broken triangle's long edge would need a broken neighbour with a longer one.
  CornerAngles angles;
  EXPECT_EQ(corner_angles(t, l, angles).first_bad_face, -1);
}

TEST(FlipToDelaunay, RepairsBrokenTrianglesOfAStrongScaling) {
  // Scale one vertex of an icosphere far down: its link' triangles break, flips repair them.
  const Mesh mesh = make_icosphere(2);
  Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  ConformalStructure s = vertex_scaling(mesh, t);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(mesh.num_vertices());
  u[0] = -3.0;
  Eigen::VectorXd l;
  ASSERT_EQ(edge_lengths(t, s, u, l).invalid_edges, 0);
  CornerAngles angles;
  ASSERT_GE(corner_angles(t, l, angles).first_bad_face, 0)
      << "the test needs broken triangles to start with";
  const DelaunayFlipResult r = flip_to_delaunay(t, s, u, l);
  EXPECT_GT(r.flips, 0);
  EXPECT_EQ(r.blocked, 0);
  EXPECT_EQ(count_non_delaunay_edges(t, l), 0);
  EXPECT_EQ(corner_angles(t, l, angles).first_bad_face, -1);
  expect_consistent(t, is_simplicial(t));
}

TEST(FlipToDelaunay, RejectsSchemesWithoutPtolemy) {
  const Mesh mesh = make_icosphere(1);
  Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  StructureOptions thurston;
  thurston.scheme = Scheme::Thurston;
  ConformalStructure s =
      make_conformal_structure(t, input_edge_lengths(mesh, t), thurston).structure;
  Eigen::VectorXd u = s.initial_u, l;
  edge_lengths(t, s, u, l);
  EXPECT_THROW(flip_to_delaunay(t, s, u, l), InvalidInput);
}

// ---- Hyperbolic background: the lambda lengths sinh(l / 2) ----

/// A point of the Poincare disk on the hyperboloid model (x0 > 0, -x0^2 + x1^2 + x2^2 = -1).
Eigen::Vector3d on_hyperboloid(std::complex<double> z) {
  const double r2 = std::norm(z);
  return Eigen::Vector3d(1 + r2, 2 * z.real(), 2 * z.imag()) / (1 - r2);
}

/// Hyperbolic distance of two points of the Poincare disk.
double disk_distance(std::complex<double> p, std::complex<double> q) {
  return 2 * std::atanh(std::abs((q - p) / (1.0 - std::conj(p) * q)));
}

/// The hyperbolic quad of edge ab with c on its left and d on its right, from four disk points.
struct HyperbolicQuad {
  std::complex<double> a, b, c, d;
  double ab() const { return disk_distance(a, b); }
  double ca() const { return disk_distance(c, a); }
  double cb() const { return disk_distance(c, b); }
  double da() const { return disk_distance(d, a); }
  double db() const { return disk_distance(d, b); }
  double margin() const { return hyperbolic_delaunay_margin(ab(), ca(), cb(), da(), db()); }
};

TEST(HyperbolicDelaunayMargin, AgreesWithTheEmptyCircleAndTheAngleConditionOnRandomQuads) {
  // Random quads of the disk, small and large (up to |z| = 0.99: circumcircles, horocycles and
  // hypercycles all occur). The reference tests, computed independently of lambda lengths:
  //  - empty circle: on the hyperboloid, a circle (or horocycle, hypercycle) through a, b, c is
  //    the section by an affine plane n . x = 1 (Euclidean dot product); its inside is the side
  //    of the origin, so the quad is Delaunay exactly when n . d >= 1;
  //  - Leibon's angle condition: theta_c + theta_d <= the other four angles of the two triangles.
  std::mt19937 random(17);
  std::uniform_real_distribution<double> unit(0, 1), turn(0, 2 * std::numbers::pi);
  int delaunay = 0, not_delaunay = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const double reach = 0.3 + 0.69 * unit(random);
    std::complex<double> z[4];
    for (auto& p : z) p = std::polar(reach * std::sqrt(unit(random)), turn(random));
    const HyperbolicQuad q{z[0], z[1], z[2], z[3]};
    // c left of the geodesic from a to b, d right of it: in the frame that moves a to the centre
    // the geodesic is straight.
    const auto frame = [&](std::complex<double> w) {
      return (w - q.a) / (1.0 - std::conj(q.a) * w);
    };
    if (!(cross(frame(q.b), frame(q.c)) > 0 && cross(frame(q.b), frame(q.d)) < 0)) continue;
    const double margin = q.margin();
    if (std::abs(margin) < 1e-8) continue;  // too close to cocircular for the references
    Eigen::Matrix3d points;
    points << on_hyperboloid(q.a).transpose(), on_hyperboloid(q.b).transpose(),
        on_hyperboloid(q.c).transpose();
    const Eigen::Vector3d n = points.fullPivLu().solve(Eigen::Vector3d::Ones());
    const bool empty_circle = n.dot(on_hyperboloid(q.d)) >= 1;
    const double ab = q.ab(), ca = q.ca(), cb = q.cb(), da = q.da(), db = q.db();
    const double theta_c = hyperbolic_angle_from_lengths(ab, ca, cb);
    const double theta_d = hyperbolic_angle_from_lengths(ab, da, db);
    const double others =
        hyperbolic_angle_from_lengths(cb, ca, ab) + hyperbolic_angle_from_lengths(ca, cb, ab) +
        hyperbolic_angle_from_lengths(db, da, ab) + hyperbolic_angle_from_lengths(da, db, ab);
    const bool angles = theta_c + theta_d <= others;
    EXPECT_EQ(margin >= 0, empty_circle) << "trial " << trial << ", margin " << margin;
    EXPECT_EQ(margin >= 0, angles) << "trial " << trial << ", margin " << margin;
    ++(margin >= 0 ? delaunay : not_delaunay);
  }
  EXPECT_GT(delaunay, 1000);
  EXPECT_GT(not_delaunay, 1000);
}

TEST(HyperbolicDelaunayMargin, IsScaleFreeInLambdaAndDefinedForBrokenTriangles) {
  // The Euclidean margin of the lambdas; a triangle with sides 6 > 2 + 2 (broken) is far from
  // Delaunay, and the margin stays finite.
  const auto s = [](double l) { return std::sinh(l / 2); };
  EXPECT_DOUBLE_EQ(hyperbolic_delaunay_margin(1.0, 0.8, 0.7, 0.9, 0.6),
                   delaunay_margin(s(1.0), s(0.8), s(0.7), s(0.9), s(0.6)));
  EXPECT_LT(hyperbolic_delaunay_margin(6.0, 2.0, 2.0, 4.0, 4.0), -2.0);
  EXPECT_TRUE(std::isfinite(hyperbolic_delaunay_margin(6.0, 2.0, 2.0, 4.0, 4.0)));
  EXPECT_DOUBLE_EQ(lambda_length(1.5, Geometry::Euclidean), 1.5);
  EXPECT_NEAR(length_from_lambda(lambda_length(1.5, Geometry::Hyperbolic), Geometry::Hyperbolic),
              1.5, 1e-15);
}

TEST(HyperbolicPtolemy, GivesTheTrueDiagonalOfAConcyclicQuad) {
  // Four points on a hyperbolic circle (a Euclidean circle inside the disk, moved off centre by an
  // isometry): Ptolemy's relation on sinh(l / 2) gives the other diagonal exactly, so a flip of a
  // concyclic quad is isometric. hyperbolic_diagonal gives it for any quad.
  std::mt19937 random(23);
  std::uniform_real_distribution<double> unit(0, 1), turn(0, 2 * std::numbers::pi);
  for (int trial = 0; trial < 200; ++trial) {
    const double radius = std::tanh((0.05 + 3.0 * unit(random)) / 2);  // hyperbolic 0.05 to 3
    const std::complex<double> centre = std::polar(0.6 * unit(random), turn(random));
    double angle[4];
    for (double& t : angle) t = turn(random);
    std::sort(angle, angle + 4);
    std::complex<double> z[4];
    for (int i = 0; i < 4; ++i) {
      const std::complex<double> w = std::polar(radius, angle[i]);
      z[i] = (w + centre) / (1.0 + std::conj(centre) * w);
    }
    // Counter-clockwise on the circle: a, d, b, c (c left of a -> b, d right).
    const HyperbolicQuad q{z[0], z[2], z[3], z[1]};
    const auto s = [](double l) { return std::sinh(l / 2); };
    const double cd = disk_distance(q.c, q.d);
    const double ptolemy =
        2 * std::asinh((s(q.ca()) * s(q.db()) + s(q.da()) * s(q.cb())) / s(q.ab()));
    EXPECT_NEAR(ptolemy / cd, 1.0, 1e-12) << "trial " << trial;
    EXPECT_NEAR(q.margin(), 0.0, 1e-11) << "trial " << trial;
    EXPECT_NEAR(hyperbolic_diagonal(q.ab(), q.ca(), q.cb(), q.da(), q.db()) / cd, 1.0, 1e-12);
  }
  // And a quad that is not concyclic: the developed diagonal, not Ptolemy's.
  const HyperbolicQuad q{{-0.3, 0.05}, {0.4, -0.1}, {0.1, 0.5}, {0.0, -0.2}};
  EXPECT_NEAR(hyperbolic_diagonal(q.ab(), q.ca(), q.cb(), q.da(), q.db()) / disk_distance(q.c, q.d),
              1.0, 1e-13);
}

TEST(HyperbolicPtolemyFlip, KeepsTheConformalClassWhateverTheScaleFactors) {
  // sinh(l / 2) scales with exp((u_i + u_j) / 2) and Ptolemy's relation commutes with that: the
  // new edge's eta is the same at any u.
  expect_flips_keep_the_conformal_class(Geometry::Hyperbolic, 1e-13);
}

TEST(HyperbolicFlipToDelaunay, EndsDelaunayWithValidTrianglesOnAClosedSurface) {
  auto [t, s, u, l, invalid_edges] = scaled_closed_surface(3, Geometry::Hyperbolic, 1.5);
  ASSERT_EQ(invalid_edges, 0);
  CornerAngles angles;
  ASSERT_GE(corner_angles(t, l, angles, Geometry::Hyperbolic).first_bad_face, 0)
      << "the test needs broken triangles to start with";
  const int before = count_non_delaunay_edges(t, l, 1e-12, Geometry::Hyperbolic);
  ASSERT_GT(before, 10);
  const DelaunayFlipResult r = flip_to_delaunay(t, s, u, l);
  EXPECT_GE(r.flips, before);
  EXPECT_TRUE(r.complete);
  EXPECT_EQ(r.blocked, 0);
  expect_consistent(t, is_simplicial(t));
  EXPECT_EQ(count_non_delaunay_edges(t, l, 1e-12, Geometry::Hyperbolic), 0);
  Eigen::VectorXd check;
  edge_lengths(t, s, u, check);
  EXPECT_LT(((check - l).array() / l.array()).abs().maxCoeff(), 1e-13);
  // Delaunay in the lambdas: every hyperbolic triangle exists.
  EXPECT_EQ(corner_angles(t, l, angles, Geometry::Hyperbolic).first_bad_face, -1);
}

TEST(HyperbolicFlipToDelaunay, IsometricFlipsKeepTheCurvatureAndTheArea) {
  // An isometric retriangulation of the same hyperbolic surface: every vertex keeps its angle
  // sum, the total area (pi - angle sum over the faces) is unchanged. The input: a genus-2
  // surface whose vertices were moved in their tangent planes (far from Delaunay).
  const Mesh mesh = testing::jitter_tangentially(make_closed_surface(2, 10), 0.45, 9);
  Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  ConformalStructure s = vertex_scaling(mesh, t, Geometry::Hyperbolic);
  const Eigen::VectorXd u = s.initial_u;
  Eigen::VectorXd l;
  ASSERT_EQ(edge_lengths(t, s, u, l).invalid_edges, 0);
  CornerAngles angles;
  ASSERT_EQ(corner_angles(t, l, angles, Geometry::Hyperbolic).first_bad_face, -1);
  const Eigen::VectorXd k_before = vertex_curvature(t, angles);
  const double area_before = hyperbolic_total_area(angles);
  DelaunayFlipOptions isometric;
  isometric.isometric = true;
  const DelaunayFlipResult r = flip_to_delaunay(t, s, u, l, isometric);
  ASSERT_GT(r.flips, 50);
  ASSERT_EQ(corner_angles(t, l, angles, Geometry::Hyperbolic).first_bad_face, -1);
  EXPECT_LT((vertex_curvature(t, angles) - k_before).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(hyperbolic_total_area(angles), area_before, 1e-12 * area_before);
  EXPECT_EQ(count_non_delaunay_edges(t, l, 1e-12, Geometry::Hyperbolic), 0);
  // The structure reproduces the new diagonals.
  Eigen::VectorXd check;
  edge_lengths(t, s, u, check);
  EXPECT_LT(((check - l).array() / l.array()).abs().maxCoeff(), 1e-13);
}

}  // namespace
}  // namespace ricci
