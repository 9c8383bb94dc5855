// Distortion figures against layouts whose distortion is known in closed form.

#include "ricci/param/distortion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <string>

#include <Eigen/Geometry>

#include "param/detail/face_distortion.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/generate.hpp"

namespace ricci {
namespace {

using UV = Eigen::Matrix<double, Eigen::Dynamic, 2>;

/// Layout figures are sums of a few dozen rounded terms: 1e-14 leaves room for their rounding.
constexpr double kTight = 1e-14;

UV planar(const Mesh& mesh) {
  return mesh.positions.leftCols<2>();
}

/// Every uv row mapped by f.
UV mapped(const UV& uv, const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& f) {
  UV out(uv.rows(), 2);
  for (Eigen::Index r = 0; r < uv.rows(); ++r) out.row(r) = f(uv.row(r).transpose()).transpose();
  return out;
}

/// Every face mapped alike, by a similarity times a stretch whose singular values have the ratio
/// `angle_distortion`: the normalisation to equal total areas leaves no area distortion, and no
/// face is flipped or degenerate.
void expect_uniform_distortion(const Distortion& d, double angle_distortion) {
  EXPECT_NEAR(d.area_distortion_energy, 0.0, kTight);
  EXPECT_NEAR(d.log_area_min, 0.0, kTight);
  EXPECT_NEAR(d.log_area_max, 0.0, kTight);
  EXPECT_NEAR(d.log_area_mean, 0.0, kTight);
  EXPECT_NEAR(d.log_area_stddev, 0.0, kTight);
  EXPECT_NEAR(d.angle_distortion_mean, angle_distortion, kTight);
  EXPECT_NEAR(d.angle_distortion_max, angle_distortion, kTight);
  EXPECT_EQ(d.flipped_faces, 0);
  EXPECT_EQ(d.degenerate_faces, 0);
}

/// A similarity on every face.
void expect_undistorted(const Distortion& d) {
  expect_uniform_distortion(d, 1.0);
}

/// The tutorial's eq. 9 recomputed here with nothing shared with the library: 3D areas from
/// cross products, layout areas by the shoelace formula from corner 0, normalised by their sums.
double energy_by_hand(const Mesh& mesh, const Triangles& uv_triangles, const UV& uv) {
  double surface = 0, layout = 0;
  std::vector<double> area, layout_area;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = mesh.positions.row(mesh.triangles(f, 0));
    const Eigen::Vector3d b = mesh.positions.row(mesh.triangles(f, 1));
    const Eigen::Vector3d c = mesh.positions.row(mesh.triangles(f, 2));
    area.push_back(0.5 * (b - a).cross(c - a).norm());
    const Eigen::Vector2d p = uv.row(uv_triangles(f, 0)), q = uv.row(uv_triangles(f, 1)),
                          r = uv.row(uv_triangles(f, 2));
    layout_area.push_back(0.5 *
                          ((q.x() - p.x()) * (r.y() - p.y()) - (r.x() - p.x()) * (q.y() - p.y())));
    surface += area.back();
    layout += std::abs(layout_area.back());
  }
  double energy = 0;
  for (std::size_t f = 0; f < area.size(); ++f) {
    const double ratio = (layout_area[f] / layout) / (area[f] / surface);
    energy += (ratio - 1) * (ratio - 1) * area[f] / surface;
  }
  return energy;
}

TEST(Distortion, GridLaidOutAsItselfIsUndistorted) {
  const Mesh grid = make_grid(6, 4, 1.5, 1.0);
  const Distortion d = measure_distortion(grid, grid.triangles, planar(grid));
  expect_undistorted(d);
  EXPECT_NEAR(d.surface_area, 1.5, kTight);
  EXPECT_NEAR(d.layout_area, 1.5, kTight);
}

TEST(Distortion, ScalingRotatingAndTranslatingTheLayoutChangesNothing) {
  const Mesh grid = make_grid(6, 4, 1.5, 1.0);
  const Eigen::Rotation2Dd rotation(0.7);
  const UV uv = mapped(planar(grid), [&](const Eigen::Vector2d& p) -> Eigen::Vector2d {
    return 3.0 * (rotation * p) + Eigen::Vector2d(-4.0, 11.0);
  });
  const Distortion d = measure_distortion(grid, grid.triangles, uv);
  expect_undistorted(d);
  EXPECT_NEAR(d.layout_area, 9 * 1.5, 1e-13);
}

TEST(Distortion, MirroredLayoutFlipsEveryFaceButStaysConformal) {
  // (x, y) -> (-x, y): every A/Abar is -1, so eq. 9 gives sum (-2)^2 Abar = 4.
  const Mesh grid = make_grid(4, 3);
  const UV uv = mapped(planar(grid), [](const Eigen::Vector2d& p) -> Eigen::Vector2d {
    return {-p.x(), p.y()};
  });
  const Distortion d = measure_distortion(grid, grid.triangles, uv);
  EXPECT_EQ(d.flipped_faces, grid.num_faces());
  EXPECT_EQ(d.degenerate_faces, 0);
  EXPECT_NEAR(d.area_distortion_energy, 4.0, kTight);
  EXPECT_TRUE(std::isnan(d.log_area_mean));  // no unflipped face to take a logarithm of
  EXPECT_TRUE(std::isnan(d.log_area_stddev));
  EXPECT_NEAR(d.angle_distortion_mean, 1.0, kTight);
  EXPECT_NEAR(d.angle_distortion_max, 1.0, kTight);
}

TEST(Distortion, AffineStretchHasAngleDistortionTwoAndNoAreaDistortion) {
  // (x, y) -> (2x, y): singular values 2 and 1 on every face; the area ratio is 2 everywhere,
  // which the normalisation to total area 1 removes.
  const Mesh grid = make_grid(5, 7, 1.0, 2.0);
  const UV uv = mapped(planar(grid), [](const Eigen::Vector2d& p) -> Eigen::Vector2d {
    return {2 * p.x(), p.y()};
  });
  expect_uniform_distortion(measure_distortion(grid, grid.triangles, uv), 2.0);
}

TEST(Distortion, HalfTheFacesStretchedByAreaFactorTwo) {
  // The unit grid with x -> 2x on the left half and x -> x + 1/2 on the right: layout area 3/2,
  // so after normalisation A/Abar = 4/3 on the left and 2/3 on the right, each half weighing 1/2.
  const Mesh grid = make_grid(4, 3);
  const UV uv = mapped(planar(grid), [](const Eigen::Vector2d& p) -> Eigen::Vector2d {
    return {p.x() <= 0.5 ? 2 * p.x() : p.x() + 0.5, p.y()};
  });
  const Distortion d = measure_distortion(grid, grid.triangles, uv);

  const double energy = 0.5 * std::pow(4.0 / 3 - 1, 2) + 0.5 * std::pow(2.0 / 3 - 1, 2);  // 1/9
  EXPECT_NEAR(d.area_distortion_energy, energy, 1e-14);
  EXPECT_NEAR(d.area_distortion_energy, energy_by_hand(grid, grid.triangles, uv), 1e-14);
  EXPECT_NEAR(d.log_area_min, std::log(2.0 / 3), 1e-14);
  EXPECT_NEAR(d.log_area_max, std::log(4.0 / 3), 1e-14);
  EXPECT_NEAR(d.log_area_mean, 0.5 * (std::log(4.0 / 3) + std::log(2.0 / 3)), 1e-14);
  EXPECT_NEAR(d.log_area_stddev, 0.5 * std::log(2.0), 1e-14);  // half the gap between the two
  EXPECT_NEAR(d.angle_distortion_mean, 1.5, 1e-14);            // 2 on one half, 1 on the other
  EXPECT_NEAR(d.angle_distortion_max, 2.0, 1e-14);
  EXPECT_NEAR(d.layout_area, 1.5, 1e-14);
  EXPECT_EQ(d.flipped_faces, 0);
}

/// The 2 x 2 unit grid (8 faces of area 1/8), each face with its own three uv rows, laid out as
/// itself except face 0 mirrored (flipped, same |A|), face 1 collapsed onto a line and face 2
/// with a NaN coordinate.
struct DamagedGrid {
  Mesh grid = make_grid(2, 2);
  Triangles uv_triangles = Triangles(8, 3);
  UV uv = UV(24, 2);
  DamagedGrid() {
    for (int f = 0; f < 8; ++f) {
      for (int c = 0; c < 3; ++c) {
        uv_triangles(f, c) = 3 * f + c;
        uv.row(3 * f + c) = grid.positions.row(grid.triangles(f, c)).leftCols<2>();
      }
    }
    for (int c = 0; c < 3; ++c) uv(c, 0) = -uv(c, 0);
    uv.row(3) << 0, 0;
    uv.row(4) << 1, 1;
    uv.row(5) << 0.5, 0.5;
    uv(7, 1) = std::numeric_limits<double>::quiet_NaN();
  }
};

TEST(Distortion, FlippedAndDegenerateFacesAreCounted) {
  // The 2 x 2 unit grid (8 faces of area 1/8), each face with its own three uv rows, laid out as
  // itself except face 0 mirrored (flipped, same |A|), face 1 collapsed onto a line and face 2
  // with a NaN coordinate. Layout area 6/8, so A/Abar = 4/3 on the 5 good faces, -4/3 on the
  // flipped one and 0 on the degenerate ones:
  // E = (5 (1/3)^2 + (7/3)^2 + 2) / 8 = 1.
  const DamagedGrid damaged;
  const Distortion d = measure_distortion(damaged.grid, damaged.uv_triangles, damaged.uv);
  EXPECT_EQ(d.flipped_faces, 1);
  EXPECT_EQ(d.degenerate_faces, 2);
  EXPECT_NEAR(d.layout_area, 0.75, kTight);
  EXPECT_NEAR(d.area_distortion_energy, 1.0, kTight);
  // Only the 5 good faces enter the logarithm.
  EXPECT_NEAR(d.log_area_min, std::log(4.0 / 3), kTight);
  EXPECT_NEAR(d.log_area_max, std::log(4.0 / 3), kTight);
  EXPECT_NEAR(d.log_area_mean, std::log(4.0 / 3), kTight);
  EXPECT_NEAR(d.log_area_stddev, 0.0, kTight);
  // The good faces and the mirror image are conformal; the degenerate ones are left out.
  EXPECT_NEAR(d.angle_distortion_mean, 1.0, kTight);
  EXPECT_NEAR(d.angle_distortion_max, 1.0, kTight);
}

TEST(FaceDistortion, HalfTheFacesStretchedGivesTwoValuesPerFigure) {
  // As HalfTheFacesStretchedByAreaFactorTwo, face by face: A/Abar = 4/3 and angle distortion 2
  // on the left half, 2/3 and 1 on the right.
  const Mesh grid = make_grid(4, 3);
  const UV uv = mapped(planar(grid), [](const Eigen::Vector2d& p) -> Eigen::Vector2d {
    return {p.x() <= 0.5 ? 2 * p.x() : p.x() + 0.5, p.y()};
  });
  const FaceDistortion faces = measure_face_distortion(grid, grid.triangles, uv);
  ASSERT_EQ(faces.log_area.size(), grid.num_faces());
  ASSERT_EQ(faces.angle.size(), grid.num_faces());
  ASSERT_EQ(faces.flipped.size(), static_cast<std::size_t>(grid.num_faces()));
  for (int f = 0; f < grid.num_faces(); ++f) {
    double x = 0;
    for (int c = 0; c < 3; ++c) x += grid.positions(grid.triangles(f, c), 0) / 3;
    const bool left = x < 0.5;
    EXPECT_NEAR(faces.log_area[f], std::log(left ? 4.0 / 3 : 2.0 / 3), 1e-14) << f;
    EXPECT_NEAR(faces.angle[f], left ? 2.0 : 1.0, 1e-14) << f;
    EXPECT_EQ(faces.flipped[f], 0);
  }
}

TEST(FaceDistortion, AgreesWithTheStatisticsAndMarksFlippedAndDegenerateFaces) {
  // The faces of FlippedAndDegenerateFacesAreCounted: the mirrored face keeps its |A| (ln 4/3)
  // and conformality and is flagged; the collapsed and the NaN face have no figures.
  const DamagedGrid damaged;
  const FaceDistortion faces =
      measure_face_distortion(damaged.grid, damaged.uv_triangles, damaged.uv);
  EXPECT_EQ(faces.flipped, (std::vector<char>{1, 0, 0, 0, 0, 0, 0, 0}));
  for (int f : {0, 3, 4, 5, 6, 7}) {
    EXPECT_NEAR(faces.log_area[f], std::log(4.0 / 3), kTight) << f;
    EXPECT_NEAR(faces.angle[f], 1.0, kTight) << f;
  }
  for (int f : {1, 2}) {
    EXPECT_TRUE(std::isnan(faces.log_area[f])) << f;
    EXPECT_TRUE(std::isnan(faces.angle[f])) << f;
  }
}

TEST(FaceDistortion, CurvedDiskMatchesTheWholeMeshFigures) {
  // The per-face values are the terms of measure_distortion's statistics.
  const Mesh disk = make_disk(6, 0.6);
  const UV uv = planar(disk);
  const Distortion d = measure_distortion(disk, disk.triangles, uv);
  const FaceDistortion faces = measure_face_distortion(disk, disk.triangles, uv);
  EXPECT_NEAR(faces.log_area.minCoeff(), d.log_area_min, kTight);
  EXPECT_NEAR(faces.log_area.maxCoeff(), d.log_area_max, kTight);
  EXPECT_NEAR(faces.angle.maxCoeff(), d.angle_distortion_max, kTight);
}

TEST(FaceDistortion, FacesOfZeroAreaGetNoFigures) {
  // measure_distortion refuses a face of zero 3D area; the per-face figures leave it out.
  Mesh grid = make_grid(2, 2);
  const UV uv = planar(grid);
  grid.positions.row(grid.triangles(4, 2)) = grid.positions.row(grid.triangles(4, 1));
  const FaceDistortion faces = measure_face_distortion(grid, grid.triangles, uv);
  for (int f = 0; f < grid.num_faces(); ++f) {
    const Eigen::Vector3d a = grid.positions.row(grid.triangles(f, 0));
    const Eigen::Vector3d b = grid.positions.row(grid.triangles(f, 1));
    const Eigen::Vector3d c = grid.positions.row(grid.triangles(f, 2));
    if ((b - a).cross(c - a).norm() == 0) {
      EXPECT_TRUE(std::isnan(faces.log_area[f])) << f;
    } else {
      EXPECT_TRUE(std::isfinite(faces.log_area[f])) << f;
    }
  }
  EXPECT_THROW(measure_face_distortion(Mesh{}, Triangles(0, 3), uv), InvalidInput);
}

TEST(Distortion, AllFacesDegenerate) {
  // Every face collapsed to a point: A = 0 everywhere, E = sum Abar = 1, no statistics.
  const Mesh grid = make_grid(2, 1);
  const UV uv = UV::Zero(grid.num_vertices(), 2);
  const Distortion d = measure_distortion(grid, grid.triangles, uv);
  EXPECT_EQ(d.degenerate_faces, grid.num_faces());
  EXPECT_EQ(d.flipped_faces, 0);
  EXPECT_NEAR(d.area_distortion_energy, 1.0, kTight);
  EXPECT_TRUE(std::isnan(d.log_area_min));
  EXPECT_TRUE(std::isnan(d.angle_distortion_max));
}

TEST(Distortion, CurvedDiskProjectedOnItsPlane) {
  // Projecting a face whose normal makes the angle t with +z scales its area by cos t and maps it
  // with singular values 1 and cos t: angle distortion 1 / cos t. Every figure follows from the
  // per-face cos t, computed here from the 3D normals.
  const Mesh disk = make_disk(6, 0.6);
  const Distortion d = measure_distortion(disk, disk.triangles, planar(disk));

  double surface = 0, layout = 0, min_cos = 1, weighted_secant = 0;
  std::vector<double> area, cosine;
  for (int f = 0; f < disk.num_faces(); ++f) {
    const Eigen::Vector3d a = disk.positions.row(disk.triangles(f, 0));
    const Eigen::Vector3d b = disk.positions.row(disk.triangles(f, 1));
    const Eigen::Vector3d c = disk.positions.row(disk.triangles(f, 2));
    const Eigen::Vector3d normal = (b - a).cross(c - a);
    area.push_back(0.5 * normal.norm());
    cosine.push_back(normal.z() / normal.norm());
    surface += area.back();
    layout += area.back() * cosine.back();
    min_cos = std::min(min_cos, cosine.back());
    weighted_secant += area.back() / cosine.back();
  }
  double energy = 0;
  for (std::size_t f = 0; f < area.size(); ++f) {
    energy += std::pow(cosine[f] * surface / layout - 1, 2) * area[f] / surface;
  }

  EXPECT_EQ(d.flipped_faces, 0);
  EXPECT_EQ(d.degenerate_faces, 0);
  EXPECT_GT(d.area_distortion_energy, 1e-4);
  EXPECT_NEAR(d.area_distortion_energy, energy, 1e-13);
  EXPECT_NEAR(d.area_distortion_energy, energy_by_hand(disk, disk.triangles, planar(disk)), 1e-13);
  EXPECT_NEAR(d.surface_area, surface, 1e-13);
  EXPECT_NEAR(d.layout_area, layout, 1e-13);
  // Jensen: the area-weighted mean of ln(A/Abar) is below ln(sum A) = 0, so the range spans 0.
  EXPECT_LT(d.log_area_mean, 0.0);
  EXPECT_LT(d.log_area_min, 0.0);
  EXPECT_GT(d.log_area_max, 0.0);
  EXPECT_NEAR(d.log_area_min, std::log(min_cos * surface / layout), 1e-13);
  EXPECT_GT(d.log_area_stddev, 0.0);
  EXPECT_NEAR(d.angle_distortion_max, 1 / min_cos, 1e-13);
  EXPECT_NEAR(d.angle_distortion_mean, weighted_secant / surface, 1e-13);
  EXPECT_GT(d.angle_distortion_mean, 1.0);
}

/// The message of the InvalidInput that measure_distortion throws.
std::string invalid_input_message(const Mesh& mesh, const Triangles& uv_triangles, const UV& uv) {
  try {
    measure_distortion(mesh, uv_triangles, uv);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InvalidInput thrown";
  return "";
}

TEST(Distortion, SizeMismatchesAreInvalidInput) {
  const Mesh grid = make_grid(2, 2);
  const UV uv = planar(grid);
  auto expect_message = [](const std::string& message, const std::string& piece) {
    EXPECT_NE(message.find("measure_distortion"), std::string::npos) << message;
    EXPECT_NE(message.find(piece), std::string::npos) << message;
  };
  expect_message(invalid_input_message(grid, grid.triangles.topRows(7), uv),
                 "uv_triangles has 7 rows but the mesh has 8 faces");

  Triangles bad_uv = grid.triangles;
  bad_uv(5, 2) = 9;
  expect_message(invalid_input_message(grid, bad_uv, uv),
                 "face 5 corner 2: uv index 9 is out of range [0, 9)");
  expect_message(invalid_input_message(grid, grid.triangles, uv.topRows(8)),
                 "uv index 8 is out of range [0, 8)");

  Mesh bad_vertex = grid;
  bad_vertex.triangles(3, 0) = -1;
  expect_message(invalid_input_message(bad_vertex, grid.triangles, uv), "vertex index -1");

  Mesh flat_face = grid;
  flat_face.triangles(4, 2) = flat_face.triangles(4, 1);  // no other face changes
  expect_message(invalid_input_message(flat_face, grid.triangles, uv), "face 4 has zero area");

  expect_message(invalid_input_message(Mesh{}, Triangles(0, 3), uv), "no faces");
}

// The one-face kernel (param/detail/face_distortion.hpp) that measure_distortion, the sphere map
// and the angle polish share.

/// A triangle of R^3 off every coordinate plane, and a linear map of its plane.
struct KernelCase {
  Eigen::Vector3d e1{1.3, 0.4, -0.2}, e2{0.2, 0.9, 0.7};
};

TEST(FaceDistortionKernel, PlaneTriangleKeepsLengthsAndArea) {
  const KernelCase k;
  const detail::PlaneTriangle t = detail::plane_triangle(k.e1, k.e2);
  EXPECT_NEAR(std::abs(t.z1), k.e1.norm(), kTight);
  EXPECT_EQ(t.z1.imag(), 0);
  EXPECT_NEAR(std::abs(t.z2), k.e2.norm(), kTight);
  EXPECT_NEAR(std::abs(t.z2 - t.z1), (k.e2 - k.e1).norm(), kTight);
  EXPECT_NEAR(t.twice_area, k.e1.cross(k.e2).norm(), kTight);
  EXPECT_GT(t.z2.imag(), 0);
  const detail::PlaneTriangle m = detail::plane_triangle(k.e1, k.e2, -1.0);
  EXPECT_EQ(m.z1, t.z1);
  EXPECT_EQ(m.z2, std::conj(t.z2));
  EXPECT_EQ(m.twice_area, -t.twice_area);
}

TEST(FaceDistortionKernel, RatioOfKnownMaps) {
  const KernelCase k;
  const detail::PlaneTriangle t = detail::plane_triangle(k.e1, k.e2);
  using C = std::complex<double>;
  auto image = [&](const std::function<C(C)>& map, double& twice_image, C& w1, C& w2) {
    w1 = map(t.z1), w2 = map(t.z2);
    twice_image = w1.real() * w2.imag() - w1.imag() * w2.real();
  };
  double twice_image = 0;
  C w1, w2;
  for (const auto modulus : {detail::Modulus::Fast, detail::Modulus::Exact}) {
    // A similarity and a mirrored one: conformal.
    image([](C z) { return C(0.3, -1.7) * z; }, twice_image, w1, w2);
    EXPECT_NEAR(detail::angle_distortion(t, w1, w2, twice_image, modulus), 1, kTight);
    image([](C z) { return C(2.0, 0.5) * std::conj(z); }, twice_image, w1, w2);
    EXPECT_LT(twice_image, 0);
    EXPECT_NEAR(detail::angle_distortion(t, w1, w2, twice_image, modulus), 1, kTight);
    // A stretch by 3 along one axis of the plane, then a rotation: sigma ratio 3.
    image([](C z) { return C(0.6, 0.8) * C(3 * z.real(), z.imag()); }, twice_image, w1, w2);
    EXPECT_NEAR(detail::angle_distortion(t, w1, w2, twice_image, modulus), 3, 4 * kTight);
  }
}

TEST(FaceDistortionKernel, CoefficientsAndModuliFormAgreeWithTheDeterminantForm) {
  const KernelCase k;
  const detail::PlaneTriangle t = detail::plane_triangle(k.e1, k.e2);
  const detail::FaceCoefficients c = detail::face_coefficients(t);
  ASSERT_TRUE(c.valid);
  using C = std::complex<double>;
  // An affine image with a translation: the coefficients take the corners' images themselves.
  auto map = [](C z) { return C(1.1, 0.3) * z + C(0.2, -0.4) * std::conj(z) + C(5, -2); };
  const C w[3] = {map(0), map(t.z1), map(t.z2)};
  C alpha_d = 0, beta_d = 0;
  for (int i = 0; i < 3; ++i) alpha_d += c.a[i] * w[i], beta_d += c.b[i] * w[i];
  // alpha D and beta D with D = -2 i twice_area.
  const C d(0, -2 * t.twice_area);
  EXPECT_NEAR(std::abs(alpha_d / d - C(1.1, 0.3)), 0, kTight);
  EXPECT_NEAR(std::abs(beta_d / d - C(0.2, -0.4)), 0, kTight);
  const C w1 = w[1] - w[0], w2 = w[2] - w[0];
  const double twice_image = w1.real() * w2.imag() - w1.imag() * w2.real();
  const double determinant_form =
      detail::angle_distortion(t, w1, w2, twice_image, detail::Modulus::Exact);
  EXPECT_NEAR(detail::ratio_from_moduli(std::abs(alpha_d), std::abs(beta_d)), determinant_form,
              8 * kTight);
  // |alpha| < |beta|: the image is mirrored, and the moduli form calls it flipped.
  EXPECT_TRUE(std::isinf(detail::ratio_from_moduli(std::abs(beta_d), std::abs(alpha_d))));
  // A degenerate 3D triangle has no coefficients.
  EXPECT_FALSE(detail::face_coefficients(detail::plane_triangle(k.e1, 2 * k.e1)).valid);
}

}  // namespace
}  // namespace ricci
