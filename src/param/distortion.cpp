#include "ricci/param/distortion.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "numerics/detail/parallel.hpp"
#include "param/detail/face_distortion.hpp"
#include "ricci/errors.hpp"
#include "ricci/numerics/complex.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;

[[noreturn]] void invalid_distortion_input(const std::string& what) {
  throw InvalidInput("measure_distortion: " + what);
}

/// What one face contributes: twice its 3D area, twice its signed layout area and the ratio
/// sigma_max / sigma_min of the linear map between them.
struct FaceMeasure {
  double twice_area = 0;         // |e1 x e2| in R^3
  double twice_layout_area = 0;  // cross(u1, u2) in the plane, signed
  double angle_distortion = 0;   // meaningful only when twice_layout_area is finite and != 0
};

/// The face's ratio in the determinant form of param/detail/face_distortion.hpp.
FaceMeasure measure_face(const Eigen::Vector3d (&p)[3], const Eigen::Vector2d (&q)[3]) {
  // Both edges from the corner opposite the longest edge are the two shortest: the cross products
  // from there lose the least to cancellation.
  int origin = 0;
  double longest = -1;
  for (int c = 0; c < 3; ++c) {
    const double opposite = (p[(c + 2) % 3] - p[(c + 1) % 3]).squaredNorm();
    if (opposite > longest) longest = opposite, origin = c;
  }
  const int j = (origin + 1) % 3, k = (origin + 2) % 3;
  const Eigen::Vector2d u1 = q[j] - q[origin], u2 = q[k] - q[origin];

  // The 3D triangle in its own plane, counter-clockwise: z0 = 0, z1 on the real axis.
  const detail::PlaneTriangle z = detail::plane_triangle(p[j] - p[origin], p[k] - p[origin]);
  FaceMeasure m;
  m.twice_area = z.twice_area;
  m.twice_layout_area = u1.x() * u2.y() - u1.y() * u2.x();
  if (!(std::isfinite(m.twice_area) && m.twice_area > 0)) return m;
  if (!(std::isfinite(m.twice_layout_area) && m.twice_layout_area != 0)) return m;
  m.angle_distortion = detail::angle_distortion(z, Complex(u1.x(), u1.y()), Complex(u2.x(), u2.y()),
                                                m.twice_layout_area, detail::Modulus::Fast);
  return m;
}

/// Checks the shapes and indices of a layout, then measures every face (in parallel).
std::vector<FaceMeasure> measure_faces(const char* function, const Mesh& mesh,
                                       const Triangles& uv_triangles,
                                       const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv) {
  auto invalid = [function](const std::string& what) {
    throw InvalidInput(std::string(function) + ": " + what);
  };
  const int num_faces = mesh.num_faces();
  if (num_faces == 0) invalid("the mesh has no faces");
  if (uv_triangles.rows() != num_faces) {
    invalid("uv_triangles has " + std::to_string(uv_triangles.rows()) + " rows but the mesh has " +
            std::to_string(num_faces) + " faces");
  }
  const Eigen::Index num_vertices = mesh.positions.rows(), num_uv = uv.rows();
  const std::int64_t bad_faces = parallel::count_if(num_faces, [&](std::int64_t f) {
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.triangles(f, c), t = uv_triangles(f, c);
      if (v < 0 || v >= num_vertices || t < 0 || t >= num_uv) return true;
    }
    return false;
  });
  for (int f = 0; f < num_faces && bad_faces > 0; ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.triangles(f, c), t = uv_triangles(f, c);
      if (v < 0 || v >= num_vertices) {
        invalid("face " + std::to_string(f) + " corner " + std::to_string(c) + ": vertex index " +
                std::to_string(v) + " is out of range [0, " + std::to_string(num_vertices) + ")");
      }
      if (t < 0 || t >= num_uv) {
        invalid("face " + std::to_string(f) + " corner " + std::to_string(c) + ": uv index " +
                std::to_string(t) + " is out of range [0, " + std::to_string(num_uv) + ")");
      }
    }
  }

  std::vector<FaceMeasure> faces(static_cast<std::size_t>(num_faces));
  parallel::for_each(
      num_faces,
      [&](std::int64_t f) {
        Eigen::Vector3d p[3];
        Eigen::Vector2d q[3];
        for (int c = 0; c < 3; ++c) {
          p[c] = mesh.positions.row(mesh.triangles(f, c)).transpose();
          q[c] = uv.row(uv_triangles(f, c)).transpose();
        }
        faces[static_cast<std::size_t>(f)] = measure_face(p, q);
      },
      parallel::kDefaultMinChunk / 4);
  return faces;
}

bool usable_layout(const FaceMeasure& m) {
  return std::isfinite(m.twice_layout_area) && m.twice_layout_area != 0;
}

}  // namespace

Distortion measure_distortion(const Mesh& mesh, const Triangles& uv_triangles,
                              const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv) {
  const int num_faces = mesh.num_faces();
  // The sums below stay sequential (their rounding depends on the order).
  const std::vector<FaceMeasure> faces =
      measure_faces("measure_distortion", mesh, uv_triangles, uv);
  Distortion d;
  double twice_surface = 0, twice_layout = 0;
  for (int f = 0; f < num_faces; ++f) {
    const FaceMeasure& m = faces[static_cast<std::size_t>(f)];
    if (!(std::isfinite(m.twice_area) && m.twice_area > 0)) {
      invalid_distortion_input("face " + std::to_string(f) + " has " +
                               (std::isfinite(m.twice_area) ? "zero" : "non-finite") +
                               " area in R^3");
    }
    twice_surface += m.twice_area;
    if (std::isfinite(m.twice_layout_area)) twice_layout += std::abs(m.twice_layout_area);
    if (!(std::isfinite(m.twice_layout_area) && m.twice_layout_area != 0)) {
      ++d.degenerate_faces;
    } else if (m.twice_layout_area < 0) {
      ++d.flipped_faces;
    }
  }
  d.surface_area = twice_surface / 2;
  d.layout_area = twice_layout / 2;

  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  // log(layout share / area share) of each face the sums below take the logarithm of (NaN for
  // the others), in parallel: the logarithms are the costly part of those sums.
  std::vector<double> log_ratios(faces.size(), nan);
  parallel::for_each(num_faces, [&](std::int64_t f) {
    const FaceMeasure& m = faces[static_cast<std::size_t>(f)];
    if (!(std::isfinite(m.twice_layout_area) && m.twice_layout_area != 0)) return;
    const double layout = m.twice_layout_area / twice_layout;
    if (layout < 0) return;
    const double area = m.twice_area / twice_surface;
    log_ratios[static_cast<std::size_t>(f)] = std::log(layout / area);
  });
  double energy = 0;
  double log_weight = 0, log_sum = 0, angle_weight = 0, angle_sum = 0;
  double log_min = std::numeric_limits<double>::infinity(), log_max = -log_min, angle_max = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const FaceMeasure& m = faces[f];
    const double area = m.twice_area / twice_surface;
    const bool usable = std::isfinite(m.twice_layout_area) && m.twice_layout_area != 0;
    // twice_layout > 0 whenever a face is usable.
    const double layout = usable ? m.twice_layout_area / twice_layout : 0.0;
    const double ratio = layout / area;
    energy += (ratio - 1) * (ratio - 1) * area;
    if (!usable) continue;
    angle_weight += area;
    angle_sum += area * m.angle_distortion;
    angle_max = std::max(angle_max, m.angle_distortion);
    if (layout < 0) continue;
    const double log_ratio = log_ratios[f];  // std::log(ratio)
    log_weight += area;
    log_sum += area * log_ratio;
    log_min = std::min(log_min, log_ratio);
    log_max = std::max(log_max, log_ratio);
  }
  d.area_distortion_energy = energy;

  if (log_weight > 0) {
    const double mean = log_sum / log_weight;
    double squares = 0;
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const FaceMeasure& m = faces[f];
      if (!(std::isfinite(m.twice_layout_area) && m.twice_layout_area > 0)) continue;
      const double area = m.twice_area / twice_surface;
      const double deviation = log_ratios[f] - mean;
      squares += area * deviation * deviation;
    }
    d.log_area_min = log_min;
    d.log_area_max = log_max;
    d.log_area_mean = mean;
    d.log_area_stddev = std::sqrt(squares / log_weight);
  } else {
    d.log_area_min = d.log_area_max = d.log_area_mean = d.log_area_stddev = nan;
  }
  if (angle_weight > 0) {
    d.angle_distortion_mean = angle_sum / angle_weight;
    d.angle_distortion_max = angle_max;
  } else {
    d.angle_distortion_mean = d.angle_distortion_max = nan;
  }
  return d;
}

FaceDistortion measure_face_distortion(const Mesh& mesh, const Triangles& uv_triangles,
                                       const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv) {
  const std::vector<FaceMeasure> faces =
      measure_faces("measure_face_distortion", mesh, uv_triangles, uv);
  double twice_surface = 0, twice_layout = 0;
  for (const FaceMeasure& m : faces) {
    if (std::isfinite(m.twice_area)) twice_surface += m.twice_area;
    if (std::isfinite(m.twice_layout_area)) twice_layout += std::abs(m.twice_layout_area);
  }
  if (!(std::isfinite(twice_surface) && twice_surface > 0)) {
    throw InvalidInput("measure_face_distortion: the mesh has " +
                       std::string(std::isfinite(twice_surface) ? "zero" : "non-finite") +
                       " total area in R^3");
  }
  const Eigen::Index num_faces = static_cast<Eigen::Index>(faces.size());
  FaceDistortion d;
  d.log_area.resize(num_faces);
  d.angle.resize(num_faces);
  d.flipped.assign(faces.size(), 0);
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  parallel::for_each(num_faces, [&](std::int64_t f) {
    const FaceMeasure& m = faces[static_cast<std::size_t>(f)];
    d.flipped[static_cast<std::size_t>(f)] = m.twice_layout_area < 0;
    if (!usable_layout(m) || !(std::isfinite(m.twice_area) && m.twice_area > 0)) {
      d.log_area[f] = d.angle[f] = nan;
      return;
    }
    const double layout = std::abs(m.twice_layout_area) / twice_layout;
    const double area = m.twice_area / twice_surface;
    d.log_area[f] = std::log(layout / area);
    d.angle[f] = m.angle_distortion;
  });
  return d;
}

}  // namespace ricci
