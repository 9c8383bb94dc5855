#include "ricci/sphere/sphere.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include "ricci/sphere/spherical.hpp"

#include "ricci/errors.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/hard_cases.hpp"
#include "ricci/mesh/io.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

/// Faces whose chordal triangle on the sphere turns against the outward direction: the normal
/// (b - a) x (c - a) against the centroid a + b + c, in long double from the differences of
/// the double positions (exact for nearby doubles), so that faces of 1e-13 still count right.
int count_inverted(const Mesh& mesh, const Positions& P) {
  int inverted = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    Eigen::Matrix<long double, 3, 1> q[3];
    for (int k = 0; k < 3; ++k) q[k] = P.row(mesh.triangles(f, k)).transpose().cast<long double>();
    const Eigen::Matrix<long double, 3, 1> normal = (q[1] - q[0]).cross(q[2] - q[0]);
    if (!(normal.dot(q[0] + q[1] + q[2]) > 0)) ++inverted;
  }
  return inverted;
}

/// Girard's corner angle at p of the geodesic triangle p q s, from the differences (tangent
/// vectors of tiny triangles keep their digits).
long double girard_corner(const Eigen::Matrix<long double, 3, 1>& p,
                          const Eigen::Matrix<long double, 3, 1>& q,
                          const Eigen::Matrix<long double, 3, 1>& s) {
  const Eigen::Matrix<long double, 3, 1> dq = q - p, ds = s - p;
  const Eigen::Matrix<long double, 3, 1> tq = dq - dq.dot(p) * p, ts = ds - ds.dot(p) * p;
  return std::atan2(tq.cross(ts).norm(), tq.dot(ts));
}

/// ln((spherical area / 4 pi) / (3D area share)) of each face from the output positions alone:
/// the spherical area by Girard's theorem where the excess is large enough to read off the
/// angles, else the chordal triangle's area (the same to O(size^2)).
std::vector<double> log_area_ratios(const Mesh& mesh, const Positions& P) {
  std::vector<double> area_3d(mesh.num_faces()), out(mesh.num_faces());
  double total = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = mesh.positions.row(mesh.triangles(f, 0));
    area_3d[f] = (Eigen::Vector3d(mesh.positions.row(mesh.triangles(f, 1))) - a)
                     .cross(Eigen::Vector3d(mesh.positions.row(mesh.triangles(f, 2))) - a)
                     .norm();
    total += area_3d[f];
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    Eigen::Matrix<long double, 3, 1> q[3];
    for (int k = 0; k < 3; ++k) q[k] = P.row(mesh.triangles(f, k)).transpose().cast<long double>();
    long double area = girard_corner(q[0], q[1], q[2]) + girard_corner(q[1], q[2], q[0]) +
                       girard_corner(q[2], q[0], q[1]) - std::numbers::pi_v<long double>;
    if (area < 1e-6L) area = (q[1] - q[0]).cross(q[2] - q[0]).norm() / 2;
    out[f] = static_cast<double>(
        std::log(area / (4 * std::numbers::pi_v<long double>) / (area_3d[f] / total)));
  }
  return out;
}

/// The invariants of a spherical conformal map (sphere.hpp), recomputed here from the positions
/// alone rather than read from the result's diagnostics, then compared with them.
void expect_sphere_invariants(const Mesh& mesh, const SphereResult& r, const std::string& what) {
  ASSERT_TRUE(r.converged) << what << ": " << r.message;
  ASSERT_TRUE(r.valid) << what << ": " << r.message;
  ASSERT_EQ(r.positions.rows(), mesh.num_vertices()) << what;
  EXPECT_LE(r.flow.max_error, 1e-10) << what;
  double radius_deviation = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    radius_deviation = std::max(radius_deviation, std::abs(r.positions.row(v).norm() - 1));
  }
  EXPECT_LE(radius_deviation, 1e-12) << what;
  EXPECT_NEAR(r.max_radius_deviation, radius_deviation, 1e-16) << what;

  const int inverted = count_inverted(mesh, r.positions);
  double area = 0, area_by_cosine_law = 0, total_3d = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = r.positions.row(mesh.triangles(f, 0));
    const Eigen::Vector3d b = r.positions.row(mesh.triangles(f, 1));
    const Eigen::Vector3d c = r.positions.row(mesh.triangles(f, 2));
    // Girard's theorem: the spherical excess from the three corner angles of the geodesic
    // triangle, a formula independent of the one the library uses.
    const Eigen::Matrix<long double, 3, 1> la = a.cast<long double>(), lb = b.cast<long double>(),
                                           lc = c.cast<long double>();
    area += static_cast<double>(girard_corner(la, lb, lc) + girard_corner(lb, lc, la) +
                                girard_corner(lc, la, lb) - std::numbers::pi_v<long double>);
    // And a third: the angles from the arc lengths by the spherical law of cosines.
    auto arc = [](const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
      return 2 * std::asin(std::min(1.0, 0.5 * (p - q).norm()));
    };
    const double la_ = arc(b, c), lb_ = arc(c, a), lc_ = arc(a, b);
    area_by_cosine_law += spherical_angle_from_lengths(la_, lb_, lc_) +
                          spherical_angle_from_lengths(lb_, lc_, la_) +
                          spherical_angle_from_lengths(lc_, la_, lb_) - std::numbers::pi;
    const Eigen::Vector3d pa = mesh.positions.row(mesh.triangles(f, 0));
    const double w = (Eigen::Vector3d(mesh.positions.row(mesh.triangles(f, 1))) - pa)
                         .cross(Eigen::Vector3d(mesh.positions.row(mesh.triangles(f, 2))) - pa)
                         .norm();
    total_3d += w;
    centre += w * (a + b + c).normalized();
  }
  EXPECT_EQ(inverted, 0) << what;
  EXPECT_EQ(r.inverted_faces, inverted) << what;
  EXPECT_EQ(r.inverted_by_rounding, 0) << what;
  EXPECT_EQ(r.inverted_pole_faces, 0) << what;
  EXPECT_NEAR(area, 4 * std::numbers::pi, 1e-8) << what;
  EXPECT_NEAR(area_by_cosine_law, 4 * std::numbers::pi, 1e-8) << what;
  EXPECT_NEAR(r.spherical_area, 4 * std::numbers::pi, 1e-8) << what;
  EXPECT_LT((centre / total_3d).norm(), 1e-9) << what;
  EXPECT_LT(r.centre_of_mass, 1e-9) << what;
  EXPECT_GE(r.angle_distortion_mean, 1.0) << what;
  EXPECT_LE(r.angle_distortion_mean, r.angle_distortion_p95 * 1.5) << what;
  EXPECT_LE(r.angle_distortion_p95, r.angle_distortion_max) << what;
  EXPECT_GT(r.min_sphere_altitude, 0) << what;
  EXPECT_GT(r.min_plane_altitude, 0) << what;
  for (double x : {r.angle_distortion_mean, r.angle_distortion_max, r.angle_error_max,
                   r.log_area_min, r.log_area_max, r.log_area_stddev, r.layout_length_error}) {
    EXPECT_TRUE(std::isfinite(x)) << what;
  }
}

/// The reach of the log area ratio recomputed from the output positions matches the result's,
/// to `tolerance` (the double positions keep a face of altitude h to about 1e-16 / h).
void expect_log_area_reach(const Mesh& mesh, const SphereResult& r, double tolerance,
                           const std::string& what) {
  const std::vector<double> ratios = log_area_ratios(mesh, r.positions);
  const auto [low, high] = std::minmax_element(ratios.begin(), ratios.end());
  EXPECT_NEAR(*low, r.log_area_min, tolerance) << what;
  EXPECT_NEAR(*high, r.log_area_max, tolerance) << what;
}

TEST(SphereMap, InscribedIcosphereIsARotationWithVertexScaling) {
  // Every vertex of the icosphere lies on the unit sphere, and stereographic projection keeps
  // vertex-scaling (Yamabe) conformal equivalence of inscribed meshes (Bobenko, Pinkall and
  // Springborn 2015): the plane's flat metric is the projection of the input, and the map must be
  // a rotation of the input up to rounding: chordal triangles congruent to the input's.
  // The disk-length boundary is exact when the pole's link projects to a regular polygon: the
  // pole is one of the icosahedron's own vertices (the first 12), whose link is a regular
  // pentagon.
  const Mesh sphere = make_icosphere(3);
  SphereOptions options;
  options.structure.scheme = Scheme::VertexScaling;
  options.pole = 0;
  const SphereResult r = sphere_map(sphere, options);
  expect_sphere_invariants(sphere, r, "icosphere 3, vertex scaling");
  EXPECT_EQ(r.flow.intrinsic.flips(), 0);
  EXPECT_NEAR(r.angle_distortion_max, 1.0, 1e-10);
  EXPECT_LT(r.angle_error_max, 1e-10);
  EXPECT_LT(r.log_area_max - r.log_area_min, 1e-2);  // chordal vs spherical area only
  for (int v = 0; v < sphere.num_vertices(); v += 37) {
    for (int w = v + 11; w < sphere.num_vertices(); w += 53) {
      EXPECT_NEAR(r.positions.row(v).dot(r.positions.row(w)),
                  sphere.positions.row(v).dot(sphere.positions.row(w)), 1e-9)
          << v << " " << w;
    }
  }
}

TEST(SphereMap, IcosphereWithThurstonIsCloseToARotation) {
  // Thurston's packing reproduces the icosphere's lengths exactly (the fit), but its conformal
  // class (fixed intersection angles) is not that of the stereographic projection, so the map is
  // only close to a rotation: measured mean 1.021, max 1.88 (on the faces touching the pole's
  // link, where the disk's boundary turning is pinned), mean corner-angle error 0.0104 rad.
  const Mesh sphere = make_icosphere(3);
  SphereOptions thurston;
  thurston.structure.scheme = Scheme::Thurston;
  const SphereResult r = sphere_map(sphere, thurston);
  expect_sphere_invariants(sphere, r, "icosphere 3, Thurston");
  EXPECT_LT(r.flow.structure.fit_rms_relative_error, 1e-12);
  EXPECT_LT(r.angle_distortion_mean, 1.03);
  EXPECT_LT(r.angle_distortion_p95, 1.1);
  EXPECT_LT(r.angle_distortion_max, 2.0);
  EXPECT_LT(r.angle_error_mean, 0.015);
  EXPECT_LT(r.log_area_stddev, 0.1);
}

TEST(SphereMap, StretchedSphere) {
  // An ellipsoid with axes 3 : 1 : 0.5: still genus 0, now far from round, with triangles of
  // aspect ratio up to 6.
  Mesh ellipsoid = make_icosphere(3);
  for (int v = 0; v < ellipsoid.num_vertices(); ++v) {
    ellipsoid.positions(v, 0) *= 3.0;
    ellipsoid.positions(v, 2) *= 0.5;
  }
  SphereOptions packing;
  packing.structure.scheme = Scheme::Thurston;
  const SphereResult thurston = sphere_map(ellipsoid, packing);
  expect_sphere_invariants(ellipsoid, thurston, "ellipsoid, Thurston");
  SphereOptions exact;
  exact.structure.scheme = Scheme::InversiveDistance;
  const SphereResult inversive = sphere_map(ellipsoid, exact);
  expect_sphere_invariants(ellipsoid, inversive, "ellipsoid, inversive distance");
  // Inversive distance starts from the input's lengths exactly; Thurston's fit (Phi at most 80
  // degrees) misses them by 20 % RMS on the stretched faces and pays for it in angles (measured
  // means 1.25 and 2.40).
  EXPECT_LT(inversive.flow.structure.fit_rms_relative_error, 1e-12);
  EXPECT_GT(thurston.flow.structure.fit_rms_relative_error, 0.1);
  EXPECT_LT(inversive.angle_distortion_mean, 1.3);
  EXPECT_LT(thurston.angle_distortion_mean, 2.5);
  EXPECT_LT(inversive.angle_distortion_mean, thurston.angle_distortion_mean);
  // The long axis ends are pulled in: a map far from uniform in area.
  EXPECT_GT(inversive.log_area_max - inversive.log_area_min, 3.0);
}

TEST(SphereMap, TetrahedronAndEveryPole) {
  // The smallest closed genus-0 mesh: the disk is a single triangle with no interior vertex.
  const Mesh tet = make_tetrahedron(1.0);
  for (int pole = 0; pole < 4; ++pole) {
    SphereOptions options;
    options.pole = pole;
    const SphereResult r = sphere_map(tet, options);
    expect_sphere_invariants(tet, r, "tetrahedron, pole " + std::to_string(pole));
    EXPECT_EQ(r.pole, pole);
    // By symmetry the centred regular tetrahedron is its own spherical map.
    EXPECT_NEAR(r.angle_distortion_max, 1.0, 1e-6);
  }
}

TEST(SphereMap, OtherSchemes) {
  const Mesh sphere = make_icosphere(2);
  for (Scheme scheme : {Scheme::Tangential, Scheme::InversiveDistance, Scheme::VertexScaling}) {
    SphereOptions options;
    options.structure.scheme = scheme;
    const SphereResult r = sphere_map(sphere, options);
    expect_sphere_invariants(sphere, r, scheme_name(scheme));
  }
}

TEST(SphereMap, DefaultPoleLeavesTheLinkTheAnglesTheBoundaryWants) {
  // A bumpy sphere, so that vertices differ. The score of a pole v, recomputed here from the
  // corner angles: the largest |(angle sum of w outside the star of v) - (pi - 2 pi / valence)|
  // over the vertices w of its link, or its own |2 pi - angle sum| if larger, plus pi below
  // valence 5; the chosen pole has the smallest.
  Mesh sphere = make_icosphere(2);
  for (int v = 0; v < sphere.num_vertices(); ++v) {
    sphere.positions.row(v) *= 1 + 0.1 * std::sin(3 * sphere.positions(v, 0) + v);
  }
  const int nv = sphere.num_vertices();
  Eigen::MatrixXd corner(sphere.num_faces(), 3);
  Eigen::VectorXd angle_sum = Eigen::VectorXd::Zero(nv);
  std::vector<int> valence(nv, 0);
  for (int f = 0; f < sphere.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = sphere.positions.row(sphere.triangles(f, k));
      const Eigen::Vector3d a =
          Eigen::Vector3d(sphere.positions.row(sphere.triangles(f, (k + 1) % 3))) - p;
      const Eigen::Vector3d b =
          Eigen::Vector3d(sphere.positions.row(sphere.triangles(f, (k + 2) % 3))) - p;
      corner(f, k) = std::acos(a.normalized().dot(b.normalized()));
      angle_sum[sphere.triangles(f, k)] += corner(f, k);
      ++valence[sphere.triangles(f, k)];  // closed mesh: faces around a vertex = its valence
    }
  }
  auto score = [&](int v) {
    std::map<int, double> outside;
    for (int f = 0; f < sphere.num_faces(); ++f) {
      for (int k = 0; k < 3; ++k) {
        if (sphere.triangles(f, k) != v) continue;
        for (int j = 1; j <= 2; ++j) {
          const int w = sphere.triangles(f, (k + j) % 3);
          if (!outside.count(w)) outside[w] = angle_sum[w];
          outside[w] -= corner(f, (k + j) % 3);
        }
      }
    }
    double s = std::abs(2 * std::numbers::pi - angle_sum[v]);
    for (const auto& [w, angle] : outside) {
      s = std::max(s, std::abs(angle - (std::numbers::pi - 2 * std::numbers::pi / valence[v])));
    }
    return s + (valence[v] < 5 ? std::numbers::pi : 0.0);
  };
  const int pole = choose_pole_vertex(sphere);
  const double best = score(pole);
  for (int v = 0; v < nv; ++v) EXPECT_LE(best, score(v) + 1e-12) << v;
  EXPECT_EQ(sphere_map(sphere).pole, pole);
}

TEST(SphereMap, NeedlesAndValence3VerticesAreUntangled) {
  // ricci generate icosphere --resolution 3 --valence3 --needles 0.998: corner splits lifted off
  // the surface (valence 3, two needles each) and 0.1-degree needles. Vertex scaling's flat
  // metric reverses dozens of them (the exact map left 92 faces inverted before untangling).
  const Mesh mesh = pull_vertices_to_neighbours(
      split_faces_near_corner(make_icosphere(3), 0.05, 0.05, 3), 0.998, 1, 2);
  const SphereResult r = sphere_map(mesh);
  expect_sphere_invariants(mesh, r, "needles and valence 3");
  expect_log_area_reach(mesh, r, 1e-6, "needles and valence 3");
  EXPECT_GT(r.reversed_disk_faces, 50);
  EXPECT_GT(r.untangled_vertices, 50);
  // The moves are of the size of the needles' stars, below the mesh's edges (about 0.12 on
  // the unit sphere; measured 0.072).
  EXPECT_LT(r.max_untangle_move, 0.12);

  // Without untangling the exact map is returned, not valid, and says why.
  SphereOptions exact;
  exact.untangle = false;
  const SphereResult e = sphere_map(mesh, exact);
  EXPECT_TRUE(e.converged);
  EXPECT_FALSE(e.valid);
  EXPECT_EQ(e.untangled_vertices, 0);
  EXPECT_GT(e.inverted_faces, 50);
  EXPECT_EQ(e.inverted_faces, count_inverted(mesh, e.positions));
  EXPECT_EQ(e.inverted_by_rounding, 0);
  EXPECT_NE(e.message.find("reversed in the disk's flat metric"), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("untangling was off"), std::string::npos) << e.message;
}

TEST(SphereMap, LongFingersNeedAWiderArithmetic) {
  // Five fingers, each four times as long as it is round: the map shrinks their tips' area by
  // about e^-4pi*4 = e^-50. The default pole is a fingertip (flat, regular), which squeezes the
  // rest of the plane by as much again: smallest altitude 7e-25 of the unit circle, below what
  // double and long double resolve. The layout then runs in quad, and every face comes out.
  const Mesh mesh = make_ball_with_fingers(5, 4.0, 16);
  const SphereResult r = sphere_map(mesh);
  expect_sphere_invariants(mesh, r, "fingers");
  EXPECT_GT(r.precision_bits, 64);
  EXPECT_LT(r.min_plane_altitude, 1e-20);
  EXPECT_LT(r.log_area_min, -45);
  EXPECT_EQ(r.unresolved_faces, 0);
  EXPECT_LT(r.layout_length_error, 1e-9);  // the tips close up as well as the ball
  // Faces of altitude 1e-12 on the sphere: their double positions give areas to about 1e-4.
  expect_log_area_reach(mesh, r, 1e-2, "fingers");
}

TEST(SphereMap, FingersWithNeedles) {
  // The scan-like case: long limbs and needles together.
  const Mesh mesh = pull_vertices_to_neighbours(make_ball_with_fingers(5, 3.0, 16), 0.998, 1, 2);
  const SphereResult r = sphere_map(mesh);
  expect_sphere_invariants(mesh, r, "fingers with needles");
  EXPECT_LT(r.log_area_min, -33);
  expect_log_area_reach(mesh, r, 1e-2, "fingers with needles");
}

TEST(SphereMap, FingersBeyondDoubleFailHonestly) {
  // Fingers six times as long as they are round: tip faces of altitude 1e-18 on the unit
  // sphere, below what a double position resolves. The default pole (a fingertip) would need
  // a plane of altitude 1e-35, beyond quad: a second pole, the widest star of that first map,
  // gives a plane quad resolves. The map is then right before rounding, and its rounding to
  // double inverts faces: not valid, and the message says so.
  const Mesh mesh = make_ball_with_fingers(5, 6.0, 16);
  const SphereResult r = sphere_map(mesh);
  EXPECT_TRUE(r.converged) << r.message;
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(r.poles_tried, 2);
  EXPECT_LT(r.min_plane_altitude, 1e-15);
  EXPECT_GT(r.min_plane_altitude, 1e-26);  // the second pole's plane, resolved by quad
  EXPECT_LT(r.min_sphere_altitude, 1e-16);
  EXPECT_GT(r.unresolved_faces, 100);
  EXPECT_GT(r.inverted_faces, 0);
  EXPECT_EQ(r.inverted_faces, count_inverted(mesh, r.positions));
  EXPECT_EQ(r.inverted_by_rounding, r.inverted_faces);
  EXPECT_LT(r.layout_length_error, 1e-9);
  EXPECT_LT(r.log_area_min, -70);
  EXPECT_NE(r.message.find("by rounding to double"), std::string::npos) << r.message;
  for (double x : {r.angle_distortion_mean, r.angle_distortion_max, r.log_area_min, r.log_area_max,
                   r.log_area_mean, r.log_area_stddev, r.spherical_area}) {
    EXPECT_TRUE(std::isfinite(x)) << r.message;
  }
}

TEST(SphereMap, RefusesOtherTopologies) {
  EXPECT_THROW(sphere_map(make_torus(16, 8)), InvalidInput);
  EXPECT_THROW(sphere_map(make_disk(6)), InvalidInput);
  EXPECT_THROW(sphere_map(make_closed_surface(2, 8)), InvalidInput);
  // Two spheres.
  Mesh two = make_icosphere(1);
  const Mesh other = make_icosphere(1);
  Mesh both;
  both.positions.resize(two.num_vertices() * 2, 3);
  both.positions << two.positions, other.positions.array() + 3.0;
  both.triangles.resize(two.num_faces() * 2, 3);
  both.triangles << two.triangles, other.triangles.array() + two.num_vertices();
  try {
    sphere_map(both);
    FAIL() << "two components accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("2 connected components"), std::string::npos) << e.what();
  }
  try {
    sphere_map(make_torus(16, 8));
    FAIL() << "torus accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("genus 1"), std::string::npos) << e.what();
  }
  SphereOptions bad_pole;
  bad_pole.pole = 100000;
  EXPECT_THROW(sphere_map(make_icosphere(1), bad_pole), InvalidInput);
}

/// Every closed genus-0 mesh of the shared folder. igea (134k vertices) runs here too when it
/// costs little enough; see docs/sphere.md for its timing.
TEST(SphereMap, SharedClosedGenusZeroMeshes) {
  RICCI_REQUIRE_SHARED_MESHES();
  int tested = 0;
  for (const auto& shared : testing::shared_meshes()) {
    if (!shared.manifold || shared.genus != 0 || shared.boundary_loops != 0) continue;
    const Mesh mesh = read_mesh(shared.path).mesh;
    const auto start = std::chrono::steady_clock::now();
    const SphereResult r = sphere_map(mesh);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // A very obtuse input face can come out inverted where the exact map bends its long side
    // (igea has one, a 164-degree triangle of 268,686 faces): untangling moves its vertex.
    expect_sphere_invariants(mesh, r, shared.file);
    expect_log_area_reach(mesh, r, 1e-6, shared.file);
    RecordProperty(shared.file + "_seconds", std::to_string(seconds));
    ++tested;
  }
  EXPECT_GE(tested, 2);
}

}  // namespace
}  // namespace ricci
