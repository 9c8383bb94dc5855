// Shape matching through conformal maps (issue 29): point location, the sphere's Moebius fit,
// and matches with known answers (a Moebius copy, a bent and re-triangulated copy, tori).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>

#include <Eigen/Geometry>

#include "ricci/errors.hpp"
#include "ricci/match/alignment.hpp"
#include "ricci/match/canonical_domain.hpp"
#include "ricci/match/match.hpp"
#include "ricci/match/point_location.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

double diagonal(const Mesh& mesh) {
  return (mesh.positions.colwise().maxCoeff() - mesh.positions.colwise().minCoeff()).norm();
}

// A lumpy ellipsoid: not round, so that its sphere map has a conformal factor to align.
Mesh lumpy_sphere(int subdivisions) {
  Mesh mesh = make_icosphere(subdivisions);
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
    Eigen::Vector3d p = mesh.positions.row(v);
    // No rotational symmetry (without the last term a half-turn about x would keep it).
    const double r = 1 + 0.15 * std::sin(3 * p.x()) * std::cos(2 * p.y()) + 0.1 * p.z() * p.z() +
                     0.1 * std::sin(2 * p.y() + p.z());
    p *= r;
    mesh.positions.row(v) << 1.4 * p.x(), p.y(), 0.8 * p.z();
  }
  return mesh;
}

// Each triangle split in four at points slid along its edges (t in [0.35, 0.65] from the
// smaller index): the same surface, another triangulation; A's vertices keep their indices.
Mesh split_with_slides(const Mesh& mesh, std::uint32_t seed) {
  std::mt19937 generator(seed);
  std::map<std::pair<int, int>, int> edge_point;
  std::vector<Eigen::RowVector3d> points;
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v)
    points.emplace_back(mesh.positions.row(v));
  const auto midpoint = [&](int i, int j) {
    const auto key = std::minmax(i, j);
    const auto found = edge_point.find(key);
    if (found != edge_point.end()) return found->second;
    const double t = 0.35 + 0.3 * ((generator() + 0.5) / 4294967296.0);
    points.emplace_back((1 - t) * mesh.positions.row(key.first) +
                        t * mesh.positions.row(key.second));
    const int index = static_cast<int>(points.size()) - 1;
    edge_point.emplace(key, index);
    return index;
  };
  Mesh out;
  out.triangles.resize(4 * mesh.triangles.rows(), 3);
  for (Eigen::Index f = 0; f < mesh.triangles.rows(); ++f) {
    const int a = mesh.triangles(f, 0), b = mesh.triangles(f, 1), c = mesh.triangles(f, 2);
    const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    out.triangles.row(4 * f) << a, ab, ca;
    out.triangles.row(4 * f + 1) << ab, b, bc;
    out.triangles.row(4 * f + 2) << ca, bc, c;
    out.triangles.row(4 * f + 3) << ab, bc, ca;
  }
  out.positions.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    out.positions.row(static_cast<Eigen::Index>(i)) = points[i];
  return out;
}

// A smooth bend: the x axis rolled onto a circle of the given radius in the plane of x and
// `axis` (the surface `axis` = 0 keeps its lengths; a layer at height h is stretched along x by
// 1 - h / radius): not rigid, and not conformal where the shape is thick.
Mesh bend(Mesh mesh, double radius, int axis) {
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
    const double x = mesh.positions(v, 0), h = mesh.positions(v, axis);
    const double angle = x / radius;
    mesh.positions(v, 0) = (radius - h) * std::sin(angle);
    mesh.positions(v, axis) = radius - (radius - h) * std::cos(angle);
  }
  return mesh;
}

// Vertices renumbered by a random permutation: new index of old vertex v is order[v].
Mesh permute(const Mesh& mesh, std::uint32_t seed, std::vector<int>& order) {
  order.resize(static_cast<std::size_t>(mesh.positions.rows()));
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(seed));
  Mesh out = mesh;
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v)
    out.positions.row(order[static_cast<std::size_t>(v)]) = mesh.positions.row(v);
  for (Eigen::Index f = 0; f < mesh.triangles.rows(); ++f) {
    for (int k = 0; k < 3; ++k)
      out.triangles(f, k) = order[static_cast<std::size_t>(mesh.triangles(f, k))];
  }
  return out;
}

// A Moebius transformation of space: inversion in the sphere about `centre` of radius rho, then
// the mirror z -> -z (the two orientation reversals cancel). Lengths of a triangulated surface
// change by l_ij' = l_ij rho^2 / (|x_i - c| |x_j - c|): discrete conformal (vertex scaling).
Mesh invert(Mesh mesh, const Eigen::Vector3d& centre, double rho) {
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
    const Eigen::Vector3d d = mesh.positions.row(v).transpose() - centre;
    Eigen::Vector3d p = centre + rho * rho * d / d.squaredNorm();
    p.z() = -p.z();
    mesh.positions.row(v) = p.transpose();
  }
  return mesh;
}

// Vertices at the extremes of the bounding box (A's indices), spread over the surface.
std::vector<int> extreme_vertices(const Mesh& mesh, int count) {
  std::vector<int> chosen;
  for (int axis = 0; static_cast<int>(chosen.size()) < count && axis < 3; ++axis) {
    for (int side : {1, -1}) {
      if (static_cast<int>(chosen.size()) == count) break;
      Eigen::Index best = 0;
      (side * mesh.positions.col(axis)).maxCoeff(&best);
      chosen.push_back(static_cast<int>(best));
    }
  }
  return chosen;
}

// Mean and max over A's vertices of the distance from where the match sends vertex v to B's
// vertex order[v] (the known correspondence), relative to B's diagonal.
std::pair<double, double> known_error(const Mesh& a, const Mesh& b, const MatchResult& m,
                                      const std::vector<int>& order) {
  const Positions image = mapped_positions(b, m.forward);
  double sum = 0, worst = 0;
  for (Eigen::Index v = 0; v < a.positions.rows(); ++v) {
    const double e = (image.row(v) - b.positions.row(order[static_cast<std::size_t>(v)])).norm();
    sum += e;
    worst = std::max(worst, e);
  }
  return {sum / static_cast<double>(a.positions.rows()) / diagonal(b), worst / diagonal(b)};
}

// Mean and max over A's vertices of |A -> B -> A - identity|, relative to A's diagonal.
std::pair<double, double> round_trip_error(const Mesh& a, const Mesh& b, const MatchResult& m) {
  const Positions back = mapped_positions(a, m.backward);  // B's vertices on A
  double sum = 0, worst = 0;
  for (Eigen::Index v = 0; v < a.positions.rows(); ++v) {
    Eigen::RowVector3d p = Eigen::RowVector3d::Zero();
    for (int k = 0; k < 3; ++k)
      p += m.forward.weights(v, k) * back.row(b.triangles(m.forward.face(v), k));
    const double e = (p - a.positions.row(v)).norm() / diagonal(a);
    sum += e;
    worst = std::max(worst, e);
  }
  return {sum / static_cast<double>(a.positions.rows()), worst};
}

TEST(PointLocation, PlanarPointsAreFoundWithTheirWeights) {
  const Mesh grid = make_grid(17, 9, 2.0, 1.0);
  const Eigen::Matrix<double, Eigen::Dynamic, 2> uv = grid.positions.leftCols(2);
  const PlanarLocator locator(uv, grid.triangles);
  std::mt19937 generator(7);
  for (int k = 0; k < 500; ++k) {
    const Eigen::Vector2d p(2.0 * (generator() / 4294967296.0), generator() / 4294967296.0);
    const FaceLocation at = locator.locate(p);
    ASSERT_GE(at.face, 0);
    EXPECT_TRUE(at.inside);
    Eigen::Vector2d q = Eigen::Vector2d::Zero();
    for (int c = 0; c < 3; ++c) q += at.weights(c) * uv.row(grid.triangles(at.face, c)).transpose();
    EXPECT_LT((q - p).norm(), 1e-12);
  }
  // Outside: the nearest face, clamped, and flagged.
  const FaceLocation out = locator.locate({2.1, 0.5});
  EXPECT_FALSE(out.inside);
  EXPECT_GT(out.outside_by, 0);
  EXPECT_NEAR(out.weights.sum(), 1.0, 1e-15);
}

TEST(PointLocation, SpherePointsAreFoundRadially) {
  const Mesh sphere = make_icosphere(3);
  const SphereLocator locator(sphere.positions, sphere.triangles);
  std::mt19937 generator(11);
  for (int k = 0; k < 500; ++k) {
    Eigen::Vector3d p(generator() / 4294967296.0 - 0.5, generator() / 4294967296.0 - 0.5,
                      generator() / 4294967296.0 - 0.5);
    p.normalize();
    const FaceLocation at = locator.locate(p);
    ASSERT_GE(at.face, 0);
    EXPECT_TRUE(at.inside);
    Eigen::Vector3d q = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c)
      q += at.weights(c) * sphere.positions.row(sphere.triangles(at.face, c)).transpose();
    EXPECT_LT((q.normalized() - p).norm(), 1e-12);  // the crossing point is radially below p
  }
}

TEST(SphereMobius, ThreePairsFixItAndMoreAreFittedExactly) {
  Eigen::Matrix2cd m;
  m << std::complex<double>(1.2, 0.3), std::complex<double>(-0.4, 0.7),
      std::complex<double>(0.2, -0.1), std::complex<double>(0.9, 0.2);
  std::vector<Eigen::Vector3d> x, y;
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 1),
        Eigen::Vector3d(0.3, -0.5, -0.8), Eigen::Vector3d(-0.6, 0.6, 0.2)}) {
    x.push_back(p.normalized());
    y.push_back(apply_sphere_mobius(m, p));
  }
  for (std::size_t count : {std::size_t(3), std::size_t(5)}) {
    const std::vector<Eigen::Vector3d> xs(x.begin(), x.begin() + static_cast<long>(count));
    const std::vector<Eigen::Vector3d> ys(y.begin(), y.begin() + static_cast<long>(count));
    const Eigen::Matrix2cd fit = fit_sphere_mobius(xs, ys);
    for (int k = 0; k < 50; ++k) {
      const Eigen::Vector3d p =
          Eigen::Vector3d(std::sin(k), std::cos(3 * k), std::sin(0.7 * k)).normalized();
      EXPECT_LT((apply_sphere_mobius(fit, p) - apply_sphere_mobius(m, p)).norm(), 1e-10) << count;
    }
  }
  EXPECT_THROW(fit_sphere_mobius({x[0], x[1]}, {y[0], y[1]}), InvalidInput);
}

TEST(Lattice, ReductionGivesTheFundamentalDomain) {
  const auto l = reduce_lattice({3.0, 1.0}, {5.0, 2.0});  // det 1: the square lattice's class
  const std::complex<double> tau = l[1] / l[0];
  EXPECT_GE(std::abs(tau), 1 - 1e-12);
  EXPECT_LE(std::abs(tau.real()), 0.5 + 1e-12);
  EXPECT_GT(tau.imag(), 0);
  EXPECT_NEAR(std::abs((std::conj(l[0]) * l[1]).imag()), 1.0, 1e-12);
}

// B is A moved by a Moebius transformation of space, renumbered: the two are discretely
// conformally equivalent, so their sphere maps differ by a Moebius transformation of the sphere,
// which four landmarks recover.
TEST(Match, AMoebiusCopyOnTheSphereIsRecovered) {
  const Mesh a = lumpy_sphere(3);
  std::vector<int> order;
  const Mesh b = permute(invert(a, {3.0, 0.5, -0.4}, 2.5), 5, order);
  MatchOptions options;
  for (int v : extreme_vertices(a, 4))
    options.landmarks.emplace_back(v, order[static_cast<std::size_t>(v)]);
  options.reverse = true;
  const MatchResult m = match_surfaces(a, b, options);
  ASSERT_TRUE(m.converged) << m.message;
  EXPECT_EQ(m.domain, DomainKind::Sphere);
  const double worst = known_error(a, b, m, order).second;
  EXPECT_LT(worst, 1e-6);
  EXPECT_LT(m.landmark_max / diagonal(b), 1e-6);
  EXPECT_EQ(m.forward.outside, 0);
  EXPECT_EQ(m.distortion.flipped_faces, 0);
  EXPECT_LT(round_trip_error(a, b, m).second, 1e-6);
}

// B is A split 1 to 4 with the new vertices slid along the edges, bent (a stretch that is not
// conformal) and renumbered; A's vertices are among B's, which gives the true correspondence.
TEST(Match, ABentRetriangulatedSphereWithFourLandmarks) {
  const Mesh a = lumpy_sphere(3);
  std::vector<int> order;
  const Mesh b = permute(bend(split_with_slides(a, 3), 8.0, 1), 9, order);
  MatchOptions options;
  for (int v : extreme_vertices(a, 4))
    options.landmarks.emplace_back(v, order[static_cast<std::size_t>(v)]);
  options.reverse = true;
  const MatchResult m = match_surfaces(a, b, options);
  ASSERT_TRUE(m.converged) << m.message;
  const double mean = known_error(a, b, m, order).first;
  RecordProperty("mean_error", std::to_string(mean));
  std::printf("bent sphere: mean error %.3g of the diagonal, landmarks max %.3g\n", mean,
              m.landmark_max / diagonal(b));
  EXPECT_LT(mean, 0.01);
  const auto [trip_mean, trip_max] = round_trip_error(a, b, m);
  std::printf("bent sphere: A -> B -> A mean %.3g max %.3g\n", trip_mean, trip_max);
  // Each way is exact in the domains (the inverse alignment); in space the two piecewise-linear
  // interpolations leave this much.
  EXPECT_LT(trip_mean, 1e-3);
  EXPECT_LT(trip_max, 5e-3);
}

// Without landmarks the conformal factors align the rotation: a rotated, renumbered copy.
TEST(Match, ARotatedCopyIsFoundWithoutLandmarks) {
  const Mesh a = lumpy_sphere(3);
  Mesh rotated = a;
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, 0.8, -0.5).normalized()).toRotationMatrix();
  rotated.positions = (a.positions * r.transpose()).eval();
  std::vector<int> order;
  const Mesh b = permute(rotated, 4, order);
  const MatchResult m = match_surfaces(a, b);
  ASSERT_TRUE(m.converged) << m.message;
  EXPECT_EQ(m.alignment.method, "conformal factor");
  const double worst = known_error(a, b, m, order).second;
  EXPECT_LT(worst, 1e-3);
  EXPECT_LT(m.alignment.factor_mismatch, 1e-3);
}

TEST(Match, ADiskIsAlignedByABoundaryPointAndAnInteriorPoint) {
  const Mesh a = make_disk(12, 0.6);
  std::vector<int> order;
  const Mesh b = permute(invert(a, {2.5, 0.3, 0.4}, 2.0), 8, order);
  MatchOptions options;
  const int boundary = static_cast<int>(a.positions.rows()) - 1;  // on the outer ring
  const int interior = 20;
  options.landmarks = {{boundary, order[static_cast<std::size_t>(boundary)]},
                       {interior, order[static_cast<std::size_t>(interior)]}};
  options.reverse = true;
  const MatchResult m = match_surfaces(a, b, options);
  ASSERT_TRUE(m.converged) << m.message;
  EXPECT_EQ(m.domain, DomainKind::Disk);
  const double worst = known_error(a, b, m, order).second;
  // The disk's boundary turns in proportion to its length (BoundaryMode::DiskLength): right to
  // the mesh's resolution, not exactly Moebius-invariant like the sphere's map.
  EXPECT_LT(worst, 1e-4);
  EXPECT_LT(round_trip_error(a, b, m).second, 1e-4);
}

TEST(Match, ABentRetriangulatedDiskWithFourLandmarks) {
  const Mesh a = make_disk(12, 0.6);
  std::vector<int> order;
  const Mesh b = permute(bend(split_with_slides(a, 4), 6.0, 2), 6, order);
  MatchOptions options;
  for (int v : {static_cast<int>(a.positions.rows()) - 1, static_cast<int>(a.positions.rows()) - 37,
                0, 40}) {
    options.landmarks.emplace_back(v, order[static_cast<std::size_t>(v)]);
  }
  options.reverse = true;
  const MatchResult m = match_surfaces(a, b, options);
  ASSERT_TRUE(m.converged) << m.message;
  const double mean = known_error(a, b, m, order).first;
  const auto [trip_mean, trip_max] = round_trip_error(a, b, m);
  std::printf("bent disk: mean error %.3g of the diagonal; A -> B -> A mean %.3g max %.3g\n", mean,
              trip_mean, trip_max);
  EXPECT_LT(mean, 0.01);
  EXPECT_LT(trip_mean, 1e-3);
  EXPECT_LT(trip_max, 5e-3);
}

// The torus of revolution with radii R > r is conformally the rectangle 2 pi by
// 2 pi r / sqrt(R^2 - r^2): modulus i sqrt(R^2 - r^2) / r in the fundamental domain (R = 3 r).
TEST(Match, TheModulusOfATorusOfRevolution) {
  const Mesh torus = make_torus(96, 32, 3.0, 1.0);
  const CanonicalDomain d = canonical_domain(torus);
  ASSERT_TRUE(d.converged) << d.message;
  EXPECT_EQ(d.kind, DomainKind::Torus);
  const std::complex<double> expected(0, std::sqrt(8.0));
  std::printf("torus R = 3 r: modulus %.9f%+.9fi, expected %.9fi\n", d.modulus.real(),
              d.modulus.imag(), expected.imag());
  EXPECT_LT(std::abs(d.modulus - expected) / std::abs(expected), 2e-3);
}

TEST(Match, AMoebiusCopyOfATorusHasTheSameModulusAndIsRecovered) {
  const Mesh a = make_torus(48, 16, 3.0, 1.0);
  std::vector<int> order;
  const Mesh b = permute(invert(a, {5.0, 1.0, 2.0}, 4.0), 2, order);
  MatchOptions options;
  // Two landmarks: the torus of revolution has an isometry (a half-turn) about any vertex, so
  // one landmark leaves two equally good maps.
  options.landmarks = {{0, order[0]}, {100, order[100]}};
  options.reverse = true;
  const MatchResult m = match_surfaces(a, b, options);
  ASSERT_TRUE(m.converged) << m.message;
  EXPECT_LT(std::abs(m.modulus_a - m.modulus_b), 1e-8);
  EXPECT_LT(m.alignment.modulus_distance, 1e-8);
  const double worst = known_error(a, b, m, order).second;
  EXPECT_LT(worst, 1e-6);
}

// A sheared torus is no longer conformal to A: the report gives both moduli, how far apart
// they are, and the affine map between the lattices; the round trip is still the identity.
TEST(Match, ATorusAgainstAShearedTorus) {
  const Mesh a = make_torus(64, 24, 3.0, 1.0);
  Mesh sheared = a;
  for (Eigen::Index v = 0; v < a.positions.rows(); ++v) {
    sheared.positions(v, 0) += 0.8 * a.positions(v, 2) + 0.3 * a.positions(v, 1);
  }
  std::vector<int> order;
  const Mesh b = permute(split_with_slides(sheared, 1), 3, order);
  MatchOptions options;
  options.reverse = true;
  const MatchResult m = match_surfaces(a, b, options);
  ASSERT_TRUE(m.converged) << m.message;
  EXPECT_NEAR(m.modulus_a.imag() / std::sqrt(8.0), 1.0, 5e-3);
  EXPECT_GT(m.alignment.modulus_distance, 1e-3);
  EXPECT_GT(m.alignment.torus_distortion, 1.0 + 1e-4);
  std::printf("sheared torus: moduli %.6f%+.6fi and %.6f%+.6fi, distance %.4g, affine K %.6f\n",
              m.modulus_a.real(), m.modulus_a.imag(), m.modulus_b.real(), m.modulus_b.imag(),
              m.alignment.modulus_distance, m.alignment.torus_distortion);
  const auto [trip_mean, trip_max] = round_trip_error(a, b, m);
  EXPECT_LT(trip_mean, 1e-3);
  EXPECT_LT(trip_max, 5e-3);
}

// Every shared mesh of a matchable topology (closed genus 0, disk, closed genus 1, up to 60k
// faces; files with defects repaired as the command line does), matched to a rotated, renumbered
// copy of itself without landmarks: every vertex onto its copy (the rotation search, polished on
// the factor read exactly, then by Levenberg-Marquardt: 1e-11 of the diagonal or better here,
// whichever way BLAS rounds, where coordinate steps alone had stopped at 5e-3 on spot).
TEST(SharedMeshes, EachMatchableMeshFindsItsRotatedCopy) {
  RICCI_REQUIRE_SHARED_MESHES();
  int matched = 0;
  for (const testing::SharedMesh& shared : testing::shared_meshes()) {
    const bool sphere = shared.genus == 0 && shared.boundary_loops == 0;
    const bool disk = shared.genus == 0 && shared.boundary_loops == 1;
    const bool torus = shared.genus == 1 && shared.boundary_loops == 0;
    if (!shared.manifold || !(sphere || disk || torus) || shared.faces > 60000 ||
        shared.faces < 100) {
      continue;  // a 4-face disk has too little shape for its factor to single out a rotation
    }
    ReadOptions read_options;
    read_options.auto_repair = true;  // degtri_sliding.off has zero-area faces
    const ReadResult read = read_mesh(shared.path, read_options);
    const Mesh& a = read.mesh;
    Mesh rotated = a;
    const Eigen::Matrix3d r =
        Eigen::AngleAxisd(0.8, Eigen::Vector3d(0.2, 0.9, 0.4).normalized()).toRotationMatrix();
    rotated.positions = (a.positions * r.transpose()).rowwise() + Eigen::RowVector3d(1, -2, 0.5);
    std::vector<int> order;
    const Mesh b = permute(rotated, 13, order);
    const MatchResult m = match_surfaces(a, b);
    ASSERT_TRUE(m.converged) << shared.file << ": " << m.message;
    const double worst = known_error(a, b, m, order).second;
    std::printf("%s: %s, worst %.3g of the diagonal, %.2f s\n", shared.file.c_str(),
                enum_name(m.domain), worst, m.seconds);
    EXPECT_LT(worst, 1e-8) << shared.file;
    EXPECT_EQ(m.distortion.flipped_faces, 0) << shared.file;
    ++matched;
  }
  EXPECT_GE(matched, 1);
}

TEST(Match, RefusesMismatchedTopologiesAndBadLandmarks) {
  const Mesh sphere = make_icosphere(2);
  const Mesh torus = make_torus(24, 8, 3.0, 1.0);
  EXPECT_THROW(match_surfaces(sphere, torus), InvalidInput);
  EXPECT_THROW(match_surfaces(make_closed_surface(2, 6), make_closed_surface(2, 6)), InvalidInput);
  MatchOptions options;
  options.landmarks = {{0, 100000}};
  EXPECT_THROW(match_surfaces(sphere, sphere, options), InvalidInput);
}

TEST(Morph, FramesRunFromAToTheTargetAlignedRigidly) {
  const Mesh a = lumpy_sphere(2);
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY()).toRotationMatrix();
  Positions target = (a.positions * r.transpose()).rowwise() + Eigen::RowVector3d(3, 1, 0);
  const auto frames = morph_frames(a, target, 5);
  ASSERT_EQ(frames.size(), 5U);
  // A rigid copy: aligned back onto A, every frame is A.
  for (const Positions& p : frames) EXPECT_LT((p - a.positions).cwiseAbs().maxCoeff(), 1e-12);
  const auto loose = morph_frames(a, target, 3, false);
  EXPECT_LT((loose[2] - target).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((loose[1] - 0.5 * (a.positions + target)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_THROW(morph_frames(a, target, 1), InvalidInput);
}

}  // namespace
}  // namespace ricci
