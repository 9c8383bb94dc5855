#include "ricci/sphere/sphere.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "param/detail/face_distortion.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/mesh/validate.hpp"
#include "ricci/numerics/timer.hpp"
#include "ricci/numerics/wide_float.hpp"
#include "sphere/detail/sphere_support.hpp"

namespace ricci {
namespace {

using sphere_support::cross;
using sphere_support::develop_disk;
using sphere_support::difference;
using sphere_support::DiskMap;
using sphere_support::dot;
using sphere_support::kDoubleResolution;
using sphere_support::Point2;
using sphere_support::Point3;
using sphere_support::smallest_altitude;
using sphere_support::to_double;
using sphere_support::untangle;

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;

/// Angle between two vectors, accurate for small and obtuse angles alike.
double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// The centre of mass of the area (sphere.hpp) and the matrix M of its linearisation.
struct Centre {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
};

Centre centre_of_mass(const Positions& P, const Triangles& F, const Eigen::VectorXd& weights) {
  Centre out;
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d s = P.row(F(f, 0)) + P.row(F(f, 1)) + P.row(F(f, 2));
    const double norm = s.norm();
    if (!(norm > 0)) continue;  // a face whose centroid is the origin has no direction
    const Eigen::Vector3d n = s / norm;
    out.c += weights[f] * n;
    out.M += weights[f] * (Eigen::Matrix3d::Identity() - n * n.transpose());
  }
  return out;
}

/// sigma_max / sigma_min of the linear map between two triangles of R^3, each in its own plane
/// (the second mirrored when `orientation` is -1), in the determinant form of
/// param/detail/face_distortion.hpp; infinity when either is degenerate.
double angle_distortion(const Eigen::Vector3d (&p)[3], const Eigen::Vector3d (&q)[3],
                        double orientation) {
  const detail::PlaneTriangle from = detail::plane_triangle(p[1] - p[0], p[2] - p[0]);
  const detail::PlaneTriangle to = detail::plane_triangle(q[1] - q[0], q[2] - q[0], orientation);
  if (!(from.twice_area > 0) || to.twice_area == 0 || !std::isfinite(to.twice_area)) {
    return std::numeric_limits<double>::infinity();
  }
  return detail::angle_distortion(from, to.z1, to.z2, to.twice_area, detail::Modulus::Exact);
}

/// Least-squares circle through points (Kasa's algebraic fit: minimises the sum of
/// (|p|^2 + D x + E y + G)^2), returned as centre and radius.
void fit_circle(const std::vector<Eigen::Vector2d>& points, Eigen::Vector2d& centre,
                double& radius) {
  Eigen::MatrixXd A(points.size(), 3);
  Eigen::VectorXd b(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    A.row(i) << points[i].x(), points[i].y(), 1.0;
    b[i] = -points[i].squaredNorm();
  }
  const Eigen::Vector3d x = A.colPivHouseholderQr().solve(b);
  centre = Eigen::Vector2d(-x[0] / 2, -x[1] / 2);
  radius = std::sqrt(std::max(centre.squaredNorm() - x[2], 0.0));
}

/// Corner angles of the mesh in R^3, summed per vertex.
/// Weighted (by w, summing to 1) mean and population standard deviation.
void weighted_stats(const std::vector<double>& values, const std::vector<double>& w, double& mean,
                    double& stddev) {
  double total = 0, sum = 0;
  for (std::size_t i = 0; i < values.size(); ++i) total += w[i], sum += w[i] * values[i];
  mean = total > 0 ? sum / total : std::numeric_limits<double>::quiet_NaN();
  double var = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    var += w[i] * (values[i] - mean) * (values[i] - mean);
  }
  stddev = total > 0 ? std::sqrt(var / total) : std::numeric_limits<double>::quiet_NaN();
}

/// Inverse stereographic projection from the north pole, mirrored (y -> -y) so that it keeps
/// the orientation: counter-clockwise in the plane seen from +z stays counter-clockwise on the
/// sphere seen from outside. The unit circle goes to the equator, its inside to the southern
/// hemisphere.
template <class T>
Point3<T> lift(const Point2<T>& p) {
  const T r2 = p[0] * p[0] + p[1] * p[1];
  const T scale = T{1} / (T{1} + r2);
  return {2 * p[0] * scale, -2 * p[1] * scale, (r2 - T{1}) * scale};
}

/// The boost phi_a of the file comment of sphere.hpp, renormalised onto the sphere.
template <class T>
Point3<T> boost(const Point3<T>& x, const Eigen::Vector3d& a) {
  const Point3<T> at{static_cast<T>(a.x()), static_cast<T>(a.y()), static_cast<T>(a.z())};
  const Point3<T> d = difference(x, at);
  const T s = static_cast<T>(1 - a.squaredNorm()) / dot(d, d);
  const Point3<T> y{s * d[0] - at[0], s * d[1] - at[1], s * d[2] - at[2]};
  const T norm = square_root(dot(y, y));
  return {y[0] / norm, y[1] / norm, y[2] / norm};
}

/// The positions rounded to double, as a #V by 3 matrix.
template <class T>
Positions to_positions(const std::vector<Point3<T>>& points) {
  Positions out(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t v = 0; v < points.size(); ++v) {
    out.row(static_cast<Eigen::Index>(v)) = to_double(points[v]).transpose();
  }
  return out;
}

/// The Moebius normalisation: damped Newton on the boost parameter a, from the positions at
/// hand until |centre| <= options.centre_tolerance. The centre of mass is a sum of unit vectors
/// weighted by area shares: double positions give it to rounding; the boosts run in T. Adds its
/// steps to result.centre_iterations, sets result.centre_of_mass; true when it stalled.
template <class T>
bool centre_map(const DiskMap& in, const SphereOptions& options, std::vector<Point3<T>>& sphere,
                SphereResult& result) {
  Centre current = centre_of_mass(to_positions(sphere), in.mesh.triangles, in.weights);
  std::vector<Point3<T>> trial = sphere;
  bool stalled = false;
  for (int steps = 0;
       current.c.norm() > options.centre_tolerance && steps < options.max_centre_iterations;
       ++steps) {
    Eigen::Vector3d a = (2 * current.M).ldlt().solve(current.c);
    if (!a.allFinite()) a = current.c / 2;
    // Steps of at most 0.5: phi_a stretches by up to (1 + |a|) / (1 - |a|), which the centre's
    // linearisation does not foresee far from a = 0.
    constexpr double kLargestStep = 0.5;
    if (a.norm() > kLargestStep) a *= kLargestStep / a.norm();
    bool accepted = false;
    for (int halving = 0; halving < 40; ++halving) {
      for (int v : in.referenced) trial[v] = boost(sphere[v], a);
      const Centre next = centre_of_mass(to_positions(trial), in.mesh.triangles, in.weights);
      if (next.c.norm() < current.c.norm()) {
        sphere.swap(trial);
        current = next;
        result.max_boost_norm = std::max(result.max_boost_norm, a.norm());
        accepted = true;
        break;
      }
      a /= 2;
    }
    ++result.centre_iterations;
    if (!accepted) {
      stalled = true;
      break;
    }
  }
  result.centre_of_mass = current.c.norm();
  return stalled;
}

/// Steps 3 to 5 of sphere_map in arithmetic T: layout, normalisation onto the unit circle,
/// projection, Moebius normalisation. Fills the result's fields of those steps; returns the
/// positions on the sphere (#V; rows of unreferenced vertices 0).
template <class T>
std::vector<Point3<T>> map_in(const DiskMap& in, const SphereOptions& options,
                              SphereResult& result) {
  const auto layout_start = Clock::now();
  const Topology& disk = in.disk;
  const int nv = in.mesh.num_vertices();
  const std::vector<Point2<T>> laid = develop_disk<T>(in);
  // How well the layout closes up: each face's edges against its shape.
  result.layout_length_error = 0;
  for (int f = 0; f < disk.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      const Point2<T>& a = laid[disk.triangles(f, i)];
      const Point2<T>& b = laid[disk.triangles(f, j)];
      const double length =
          std::hypot(static_cast<double>(b[0] - a[0]), static_cast<double>(b[1] - a[1]));
      const double wanted = std::abs(in.shapes[f][j] - in.shapes[f][i]);
      result.layout_length_error =
          std::max(result.layout_length_error, std::abs(length - wanted) / wanted);
    }
  }
  // The least-squares circle through the boundary: any centre and radius define the
  // normalisation exactly, so double suffices for the fit, about the boundary's mean (the
  // layout's origin is wherever its smallest face was); the translation and scale run in T.
  const std::vector<int>& loop = disk.boundary_loops[0];
  Point2<T> mean{T{0}, T{0}};
  for (int v : loop) mean = {mean[0] + laid[v][0], mean[1] + laid[v][1]};
  mean = {mean[0] / static_cast<T>(loop.size()), mean[1] / static_cast<T>(loop.size())};
  std::vector<Eigen::Vector2d> boundary;
  boundary.reserve(loop.size());
  for (int v : loop) {
    boundary.emplace_back(static_cast<double>(laid[v][0] - mean[0]),
                          static_cast<double>(laid[v][1] - mean[1]));
  }
  Eigen::Vector2d centre;
  double radius = 0;
  fit_circle(boundary, centre, radius);
  std::vector<Point2<T>> plane(laid.size());
  const T cx = mean[0] + static_cast<T>(centre.x()), cy = mean[1] + static_cast<T>(centre.y());
  const T r = static_cast<T>(radius);
  for (std::size_t v = 0; v < laid.size(); ++v) {
    plane[v] = {(laid[v][0] - cx) / r, (laid[v][1] - cy) / r};
  }
  result.plane.setConstant(nv, 2, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < in.disk_vertices.size(); ++i) {
    result.plane.row(in.disk_vertices[i]) << static_cast<double>(plane[i][0]),
        static_cast<double>(plane[i][1]);
  }
  result.boundary_circle_deviation = 0;
  result.inverted_pole_faces = 0;
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const Point2<T>& p = plane[loop[k]];
    const Point2<T>& q = plane[loop[(k + 1) % loop.size()]];
    result.boundary_circle_deviation =
        std::max(result.boundary_circle_deviation,
                 std::abs(static_cast<double>(square_root(p[0] * p[0] + p[1] * p[1])) - 1));
    // The loop runs with the disk on its left, so the face (q, p, pole) beyond it keeps its
    // orientation when the pole's wedge p -> q turns counter-clockwise about the origin.
    if (!(p[0] * q[1] - p[1] * q[0] > 0)) ++result.inverted_pole_faces;
  }

  // 4. Onto the sphere, the pole at the north pole.
  std::vector<Point3<T>> sphere(nv, Point3<T>{T{0}, T{0}, T{0}});
  for (std::size_t i = 0; i < in.disk_vertices.size(); ++i) {
    sphere[in.disk_vertices[i]] = lift(plane[i]);
  }
  sphere[in.pole] = {T{0}, T{0}, T{1}};
  result.layout_seconds = seconds_since(layout_start);

  // 5. Moebius normalisation, then the faces the map leaves inverted untangled (each round
  // moves a few vertices by a fraction of their star, so the centre is restored after it).
  const auto normalisation_start = Clock::now();
  result.centre_iterations = 0;
  result.max_boost_norm = 0;
  result.untangled_vertices = 0;
  result.max_untangle_move = result.max_untangle_relative_move = 0;
  result.initial_centre =
      centre_of_mass(to_positions(sphere), in.mesh.triangles, in.weights).c.norm();
  bool stalled = centre_map(in, options, sphere, result);
  for (int round = 0; options.untangle && round < 3; ++round) {
    int moved = 0;
    for (int sweep = 0; sweep < 10; ++sweep) {
      const int now = untangle(in, sphere, result);
      if (now == 0) break;
      moved += now;
    }
    if (moved == 0) break;
    stalled = centre_map(in, options, sphere, result);
  }
  result.converged = result.centre_of_mass <= options.centre_tolerance;
  if (!result.converged) {
    result.message = "the Moebius normalisation left the centre of mass at " +
                     std::to_string(result.centre_of_mass) + " after " +
                     std::to_string(result.centre_iterations) + " steps" +
                     (stalled ? " (no step reduced it further)" : "");
  }
  result.normalisation_seconds = seconds_since(normalisation_start);
  return sphere;
}

/// det of three double points as a . ((b - a) x (c - a)) in long double: the differences of
/// nearby doubles are exact, so the sign is right down to faces of a few units in the last
/// place, where double arithmetic on the cross product would already have cancelled.
long double rounded_determinant(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                const Eigen::Vector3d& c) {
  const Point3<long double> pa{a.x(), a.y(), a.z()};
  const Point3<long double> e1 = difference(Point3<long double>{b.x(), b.y(), b.z()}, pa);
  const Point3<long double> e2 = difference(Point3<long double>{c.x(), c.y(), c.z()}, pa);
  return dot(pa, cross(e1, e2));
}

/// Step 6: the output positions (rounded to double) and every figure of the final map, each
/// face measured from its positions in T: its edge vectors are formed before rounding, so a face
/// far below double resolution still has its shape, area and orientation.
template <class T>
void measure_map(const DiskMap& in, const std::vector<Point3<T>>& sphere, SphereResult& result) {
  const Mesh& mesh = in.mesh;
  result.positions = to_positions(sphere);
  result.max_radius_deviation = 0;
  for (int v : in.referenced) {
    result.max_radius_deviation =
        std::max(result.max_radius_deviation, std::abs(result.positions.row(v).norm() - 1));
  }
  const int nf = mesh.num_faces();
  std::vector<double> ratios(nf), log_area, log_weight;
  double ratio_sum = 0, angle_error_sum = 0;
  result.inverted_faces = result.inverted_by_rounding = result.unresolved_faces = 0;
  result.spherical_area = 0;
  result.angle_distortion_max = result.angle_error_max = 0;
  result.min_sphere_altitude = std::numeric_limits<double>::infinity();
  result.log_area_min = std::numeric_limits<double>::infinity();
  result.log_area_max = -std::numeric_limits<double>::infinity();
  for (int f = 0; f < nf; ++f) {
    const int i = mesh.triangles(f, 0), j = mesh.triangles(f, 1), k = mesh.triangles(f, 2);
    const Point3<T> e1 = difference(sphere[j], sphere[i]);
    const Point3<T> e2 = difference(sphere[k], sphere[i]);
    const T det = dot(sphere[i], cross(e1, e2));
    const bool kept = det > 0;
    const Eigen::Vector3d a = result.positions.row(i), b = result.positions.row(j),
                          c = result.positions.row(k);
    if (!(rounded_determinant(a, b, c) > 0)) {
      ++result.inverted_faces;
      if (kept) ++result.inverted_by_rounding;
    }
    // The chordal triangle from its own edge vectors, exact to rounding at any scale.
    const Eigen::Vector3d q[3] = {Eigen::Vector3d::Zero(), to_double(e1), to_double(e2)};
    const double altitude = smallest_altitude(q[1], q[2]);
    result.min_sphere_altitude = std::min(result.min_sphere_altitude, altitude);
    if (altitude < kDoubleResolution) ++result.unresolved_faces;
    const double area =
        2 * std::atan2(static_cast<double>(det), 1 + a.dot(b) + b.dot(c) + c.dot(a));
    result.spherical_area += area;
    Eigen::Vector3d p[3];
    for (int corner = 0; corner < 3; ++corner)
      p[corner] = mesh.positions.row(mesh.triangles(f, corner));
    ratios[f] = angle_distortion(p, q, kept ? 1.0 : -1.0);
    result.angle_distortion_max = std::max(result.angle_distortion_max, ratios[f]);
    ratio_sum += in.weights[f] * ratios[f];
    for (int corner = 0; corner < 3; ++corner) {
      const int next = (corner + 1) % 3, last = (corner + 2) % 3;
      const double error = std::abs(angle_between(q[next] - q[corner], q[last] - q[corner]) -
                                    angle_between(p[next] - p[corner], p[last] - p[corner]));
      angle_error_sum += error;
      result.angle_error_max = std::max(result.angle_error_max, error);
    }
    if (area > 0) {
      const double value = std::log(area / (4 * kPi) / in.weights[f]);
      log_area.push_back(value);
      log_weight.push_back(in.weights[f]);
      result.log_area_min = std::min(result.log_area_min, value);
      result.log_area_max = std::max(result.log_area_max, value);
    }
  }
  result.angle_distortion_mean = ratio_sum;
  result.angle_error_mean = angle_error_sum / (3.0 * nf);
  weighted_stats(log_area, log_weight, result.log_area_mean, result.log_area_stddev);
  const auto p95 = ratios.begin() + static_cast<std::ptrdiff_t>(0.95 * (nf - 1));
  std::nth_element(ratios.begin(), p95, ratios.end());
  result.angle_distortion_p95 = *p95;
}

/// Steps 3 to 6 in arithmetic T.
template <class T>
void map_and_measure(const DiskMap& in, const SphereOptions& options, SphereResult& result) {
  result.precision_bits = significand_bits<T>();
  result.message.clear();  // a narrower arithmetic's, when this one is a retry
  const std::vector<Point3<T>> sphere = map_in<T>(in, options, result);
  measure_map(in, sphere, result);
}

/// A face keeps its shape through the layout and the boosts when its smallest altitude (in the
/// unit of the unit circle or the unit sphere) is well above the arithmetic's resolution:
/// 0 when double resolves it with a margin of 2^20, 1 for long double, 2 for quad, 3 for none.
int precision_level(double altitude) {
  constexpr double kMargin = 0x1p20;
  const int bits[] = {significand_bits<double>(), significand_bits<long double>(),
                      significand_bits<Quad>()};
  for (int level = 0; level < 3; ++level) {
    if (altitude >= kMargin * std::ldexp(1.0, 1 - bits[level])) return level;
  }
  return 3;
}

/// The vertex of valence 5 or more whose star covers the most of the sphere in `positions`
/// (spherical areas of its faces summed, from double positions: the widest stars are far above
/// double resolution); -1 when none has positive area.
int widest_star_vertex(const Topology& t, const Positions& positions) {
  std::vector<double> star(t.num_vertices, 0.0);
  for (int f = 0; f < t.num_faces; ++f) {
    const Eigen::Vector3d a = positions.row(t.triangles(f, 0));
    const Eigen::Vector3d b = positions.row(t.triangles(f, 1));
    const Eigen::Vector3d c = positions.row(t.triangles(f, 2));
    const double det = a.dot((b - a).cross(c - a));
    const double area = 2 * std::atan2(det, 1 + a.dot(b) + b.dot(c) + c.dot(a));
    for (int k = 0; k < 3; ++k) star[t.triangles(f, k)] += area;
  }
  int best = -1;
  double widest = 0;
  for (int v = 0; v < t.num_vertices; ++v) {
    if (t.vertex_degree[v] >= 5 && star[v] > widest) {
      widest = star[v];
      best = v;
    }
  }
  return best;
}

/// Whether map a is better than map b: valid first, then converged with a plane some
/// arithmetic resolves (the figures of the other are not to be trusted), then fewer inverted
/// faces, then the narrower arithmetic.
bool preferred(const SphereResult& a, const SphereResult& b) {
  if (a.valid != b.valid) return a.valid;
  if (a.converged != b.converged) return a.converged;
  const bool a_resolved = precision_level(a.min_plane_altitude) < 3;
  const bool b_resolved = precision_level(b.min_plane_altitude) < 3;
  if (a_resolved != b_resolved) return a_resolved;
  if (a.inverted_faces != b.inverted_faces) return a.inverted_faces < b.inverted_faces;
  return a.precision_bits < b.precision_bits;
}

std::string figure(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

/// Sets `valid`, and `message` and `fixes` when the map fails its own checks: an inverted face
/// in the output or a figure that is not finite.
void check_map(const SphereOptions& options, SphereResult& r) {
  // Every figure the report prints: a map that passes shows no inf or NaN.
  const double figures[] = {r.max_radius_deviation, r.spherical_area,
                            r.centre_of_mass,       r.initial_centre,
                            r.max_boost_norm,       r.angle_distortion_mean,
                            r.angle_distortion_p95, r.angle_distortion_max,
                            r.angle_error_mean,     r.angle_error_max,
                            r.log_area_min,         r.log_area_max,
                            r.log_area_mean,        r.log_area_stddev,
                            r.min_sphere_altitude,  r.min_plane_altitude,
                            r.layout_length_error,  r.boundary_circle_deviation,
                            r.max_untangle_move,    r.max_untangle_relative_move};
  const bool finite = std::all_of(std::begin(figures), std::end(figures),
                                  [](double x) { return std::isfinite(x); });
  r.valid = r.converged && r.inverted_faces == 0 && finite;
  if (r.valid || !r.converged) return;
  std::string why;
  if (r.inverted_faces > 0) {
    why = std::to_string(r.inverted_faces) + " face(s) of the output are inverted on the sphere";
    const int by_map = r.inverted_faces - r.inverted_by_rounding;
    if (by_map > 0) {
      why += "; " + std::to_string(by_map) + " by the map itself (";
      why += r.reversed_disk_faces > 0
                 ? std::to_string(r.reversed_disk_faces) +
                       " of the input's faces are reversed in the disk's flat metric, as vertex "
                       "scaling does to needles and slivers)"
                 : "very obtuse faces whose chordal triangles the projection bends over)";
      why += options.untangle ? ", which untangling (" + std::to_string(r.untangled_vertices) +
                                    " vertex moves) could not free: their stars are folded too"
                              : "; untangling was off";
    }
    if (r.inverted_by_rounding > 0) {
      why += "; " + std::to_string(r.inverted_by_rounding) +
             " by rounding to double: the conformal map shrinks part of the surface (log area "
             "ratio down to " +
             figure(r.log_area_min) + ", smallest altitude " + figure(r.min_sphere_altitude) +
             " on the unit sphere) below double resolution, " + std::to_string(r.unresolved_faces) +
             " face(s) under 1.4e-14; no pole, scheme or arithmetic changes that";
    }
  }
  if (!finite) {
    why += std::string(why.empty() ? "" : "; ") + "a figure of the map is not finite";
  }
  if (precision_level(r.min_plane_altitude) == 3) {
    why += "; the disk's layout needs more than quad precision (a face of relative altitude " +
           figure(r.min_plane_altitude) +
           " in the plane), so the faces below it are not laid out right either";
  }
  r.message = why;
}

}  // namespace

int choose_pole_vertex(const Mesh& mesh) {
  return choose_pole_vertex(mesh, build_topology(mesh.triangles, mesh.num_vertices()));
}

int choose_pole_vertex(const Mesh& mesh, const Topology& t) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  Eigen::VectorXd sums = Eigen::VectorXd::Zero(nv);
  Eigen::MatrixXd corner(nf, 3);
  std::vector<int> star_start(nv + 1, 0), star_corner(3 * static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = mesh.positions.row(mesh.triangles(f, k));
      corner(f, k) =
          angle_between(mesh.positions.row(mesh.triangles(f, (k + 1) % 3)).transpose() - p,
                        mesh.positions.row(mesh.triangles(f, (k + 2) % 3)).transpose() - p);
      sums[mesh.triangles(f, k)] += corner(f, k);
      ++star_start[mesh.triangles(f, k) + 1];
    }
  }
  for (int v = 0; v < nv; ++v) star_start[v + 1] += star_start[v];
  {
    std::vector<int> fill(star_start.begin(), star_start.end() - 1);
    for (int f = 0; f < nf; ++f) {
      for (int k = 0; k < 3; ++k) star_corner[fill[mesh.triangles(f, k)]++] = 3 * f + k;
    }
  }
  // Removing the pole's star leaves each vertex w of its link on the disk's boundary with the
  // interior angle it had outside the star, where the disk-length target asks for about
  // pi - 2 pi / valence. The flow bridges the difference with the boundary edges held (they
  // cannot flip), so the pole is the vertex whose link comes closest, which also keeps needles
  // away from the star (a link vertex left with a sliver of angle broke the triangles along the
  // boundary of a needle-ridden scan and stalled the flow at error 1), and which is flat.
  std::vector<double> removed(nv, 0.0);
  double best_score = std::numeric_limits<double>::infinity();
  int best = -1;
  for (int v = 0; v < nv; ++v) {
    const int valence = t.vertex_degree[v];
    if (t.vertex_component[v] < 0 || valence < 3) continue;
    for (int c = star_start[v]; c < star_start[v + 1]; ++c) {
      const int f = star_corner[c] / 3, k = star_corner[c] % 3;
      removed[mesh.triangles(f, (k + 1) % 3)] += corner(f, (k + 1) % 3);
      removed[mesh.triangles(f, (k + 2) % 3)] += corner(f, (k + 2) % 3);
    }
    const double wanted = kPi - 2 * kPi / valence;
    double score = std::abs(2 * kPi - sums[v]);
    for (int c = star_start[v]; c < star_start[v + 1]; ++c) {
      const int f = star_corner[c] / 3, k = star_corner[c] % 3;
      for (int j : {(k + 1) % 3, (k + 2) % 3}) {
        const int w = mesh.triangles(f, j);
        score = std::max(score, std::abs(sums[w] - removed[w] - wanted));
      }
    }
    if (valence < 5) score += kPi;  // a triangle or square for the disk's boundary: last resort
    for (int c = star_start[v]; c < star_start[v + 1]; ++c) {
      const int f = star_corner[c] / 3, k = star_corner[c] % 3;
      removed[mesh.triangles(f, (k + 1) % 3)] = 0;
      removed[mesh.triangles(f, (k + 2) % 3)] = 0;
    }
    if (score < best_score) {
      best_score = score;
      best = v;
    }
  }
  return best;
}

/// sphere_map with the pole given, from step 1 on (the checks of sphere_map done).
SphereResult map_with_pole(const Mesh& mesh, const Topology& topology, int pole,
                           const SphereOptions& options) {
  const auto start = Clock::now();
  SphereResult result;
  const int nv = mesh.num_vertices();
  const Component& component = topology.components[0];
  result.pole = pole;

  // 1. The disk: every referenced vertex but the pole, every face not touching it.
  std::vector<int> to_disk(nv, -1);
  for (int v = 0; v < nv; ++v) {
    if (v == pole || topology.vertex_component[v] < 0) continue;
    to_disk[v] = static_cast<int>(result.disk_vertices.size());
    result.disk_vertices.push_back(v);
  }
  Mesh disk;
  disk.positions.resize(static_cast<Eigen::Index>(result.disk_vertices.size()), 3);
  for (std::size_t i = 0; i < result.disk_vertices.size(); ++i) {
    disk.positions.row(static_cast<Eigen::Index>(i)) = mesh.positions.row(result.disk_vertices[i]);
  }
  std::vector<int> disk_faces;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    if (mesh.triangles(f, 0) != pole && mesh.triangles(f, 1) != pole &&
        mesh.triangles(f, 2) != pole) {
      disk_faces.push_back(f);
    }
  }
  disk.triangles.resize(static_cast<Eigen::Index>(disk_faces.size()), 3);
  for (std::size_t i = 0; i < disk_faces.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      disk.triangles(static_cast<Eigen::Index>(i), k) = to_disk[mesh.triangles(disk_faces[i], k)];
    }
  }

  // 2. Flat metric on the disk, boundary turning in proportion to its length.
  TargetSpec disk_target;
  disk_target.kind = TargetKind::Flat;
  disk_target.boundary = BoundaryMode::DiskLength;
  // The disk's problem (topology, lengths, structure), built once: the layout reads it too.
  FlowProblem disk_problem = make_flow_problem(disk, options.structure);
  const Eigen::VectorXd plain_initial_u = disk_problem.structure.structure.initial_u;
  result.exact_pole_star =
      options.exact_pole_star && disk_problem.structure.structure.scheme == Scheme::VertexScaling;
  if (result.exact_pole_star) {
    // Equal spokes in the plane: u_i = -2 ln l(pole, i), centred, fixed on the boundary
    // (BoundaryMode::Free holds the boundary's u where it starts).
    disk_target.boundary = BoundaryMode::Free;
    std::vector<std::pair<int, double>> spokes;
    double mean = 0;
    for (int f = 0; f < mesh.num_faces(); ++f) {
      for (int k = 0; k < 3; ++k) {
        if (mesh.triangles(f, k) != pole) continue;
        const int i = mesh.triangles(f, (k + 1) % 3);
        const double length = (mesh.positions.row(i) - mesh.positions.row(pole)).norm();
        spokes.emplace_back(to_disk[i], -2 * std::log(length));
        mean += spokes.back().second;
      }
    }
    mean /= static_cast<double>(spokes.size());
    // The interior starts at the boundary's values spread inwards (Gauss-Seidel sweeps of the
    // graph Laplacian): an unchanged interior under a changed boundary would break the triangles
    // along it, whose boundary edges cannot flip. Where the interior starts does not change
    // where the flow ends.
    const Topology& t = disk_problem.topology;
    Eigen::VectorXd delta = Eigen::VectorXd::Zero(t.num_vertices);
    std::vector<char> fixed(static_cast<std::size_t>(t.num_vertices), 0);
    for (const auto& [i, u] : spokes) {
      delta(i) = u - mean;
      fixed[static_cast<std::size_t>(i)] = 1;
    }
    std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(t.num_vertices));
    for (int e = 0; e < t.num_edges; ++e) {
      neighbours[static_cast<std::size_t>(t.edge_vertices(e, 0))].push_back(t.edge_vertices(e, 1));
      neighbours[static_cast<std::size_t>(t.edge_vertices(e, 1))].push_back(t.edge_vertices(e, 0));
    }
    for (int sweep = 0; sweep < 200; ++sweep) {
      for (int v = 0; v < t.num_vertices; ++v) {
        const auto& n = neighbours[static_cast<std::size_t>(v)];
        if (fixed[static_cast<std::size_t>(v)] || n.empty()) continue;
        double sum = 0;
        for (int w : n) sum += delta(w);
        delta(v) = sum / static_cast<double>(n.size());
      }
    }
    disk_problem.structure.structure.initial_u += delta;
  }
  MeshFlowOptions flow_options = mesh_flow_options(options.structure, options.flow, disk_target);
  for (int v : result.disk_vertices) flow_options.vertex_labels.push_back(v);
  // The exact star's boundary can break a triangle along it (its edges cannot flip) or stall the
  // flow: then the length-proportional boundary, and the result says so.
  const auto plain_boundary = [&] {
    result.exact_pole_star = false;
    disk_problem.structure.structure.initial_u = plain_initial_u;
    disk_target.boundary = BoundaryMode::DiskLength;
    flow_options.target = disk_target;
  };
  try {
    result.flow = flow_mesh(disk_problem, flow_options);
  } catch (const InvalidInput&) {
    if (!result.exact_pole_star) throw;
    plain_boundary();
    result.flow = flow_mesh(disk_problem, flow_options);
  }
  if (result.exact_pole_star && !result.flow.converged) {
    plain_boundary();
    result.flow = flow_mesh(disk_problem, flow_options);
  }
  result.flow_seconds = result.flow.total_seconds;
  if (!result.flow.converged) {
    result.message = "the flow on the disk did not converge: " + result.flow.message;
    result.fixes = result.flow.fixes;
    result.seconds = seconds_since(start);
    return result;
  }

  // 3.-6. Layout, projection, normalisation and figures, in the precision the faces need.
  const Topology& disk_topology = disk_problem.topology;
  if (disk_topology.components.size() != 1 || disk_topology.boundary_loops.size() != 1) {
    throw Error("sphere_map: removing the pole's star did not leave a disk (internal error)");
  }
  // The disk's own faces, developed in the flat metric when the flow flipped edges (the same
  // vertex positions as a layout of the intrinsic triangulation, which may be a Delta-complex).
  const Development development = develop_input_faces(disk_topology, result.flow);
  result.reversed_disk_faces = development.flipped_faces;
  // The normalised plane's unit is the boundary's radius, about its length over 2 pi; each
  // face's smallest altitude in that unit says how fine the arithmetic must be.
  double boundary_length = 0;
  for (int e = 0; e < disk_topology.num_edges; ++e) {
    if (disk_topology.is_boundary_edge[e]) boundary_length += development.lengths[e];
  }
  const double plane_unit = boundary_length / (2 * kPi);
  result.min_plane_altitude = std::numeric_limits<double>::infinity();
  for (int f = 0; f < disk_topology.num_faces; ++f) {
    const auto& s = development.shapes[f];
    const Eigen::Vector3d e1((s[1] - s[0]).real(), (s[1] - s[0]).imag(), 0);
    const Eigen::Vector3d e2((s[2] - s[0]).real(), (s[2] - s[0]).imag(), 0);
    result.min_plane_altitude =
        std::min(result.min_plane_altitude, smallest_altitude(e1, e2) / plane_unit);
  }
  Eigen::VectorXd weights(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = mesh.positions.row(mesh.triangles(f, 0));
    const Eigen::Vector3d b = mesh.positions.row(mesh.triangles(f, 1));
    const Eigen::Vector3d c = mesh.positions.row(mesh.triangles(f, 2));
    weights[f] = (b - a).cross(c - a).norm();
  }
  weights /= weights.sum();
  std::vector<std::vector<int>> stars(nv);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) stars[mesh.triangles(f, k)].push_back(f);
  }
  const DiskMap in{
      mesh,  disk_topology, development.shapes, result.disk_vertices, component.vertices, weights,
      stars, pole};
  // The narrowest arithmetic that resolves the plane's faces, then wider while the sphere's
  // faces ask for it.
  for (int level = std::min(precision_level(result.min_plane_altitude), 2);; ++level) {
    if (level == 0) {
      map_and_measure<double>(in, options, result);
    } else if (level == 1) {
      map_and_measure<long double>(in, options, result);
    } else {
      map_and_measure<Quad>(in, options, result);
    }
    if (level == 2 || precision_level(result.min_sphere_altitude) <= level) break;
  }
  check_map(options, result);
  result.seconds = seconds_since(start);
  return result;
}

SphereResult sphere_map(const Mesh& mesh, const SphereOptions& options) {
  const auto start = Clock::now();
  if (!(options.centre_tolerance > 0) || !std::isfinite(options.centre_tolerance)) {
    throw InvalidInput("sphere_map: centre_tolerance must be positive and finite");
  }
  if (options.max_centre_iterations < 1) {
    throw InvalidInput("sphere_map: max_centre_iterations must be at least 1");
  }
  validate_mesh(mesh, "sphere_map");
  const Topology topology = build_topology(mesh.triangles, mesh.num_vertices());
  if (topology.components.size() != 1) {
    throw InvalidInput("sphere_map: the mesh has " + std::to_string(topology.components.size()) +
                       " connected components; the sphere map needs exactly one");
  }
  const Component& component = topology.components[0];
  if (component.num_boundary_loops != 0) {
    throw InvalidInput("sphere_map: the mesh has " + std::to_string(component.num_boundary_loops) +
                       " boundary loop(s); the sphere map needs a closed surface");
  }
  if (component.genus != 0) {
    throw InvalidInput("sphere_map: the mesh has genus " + std::to_string(component.genus) +
                       " (Euler characteristic " + std::to_string(component.euler_characteristic) +
                       "); only genus 0 maps conformally onto the sphere");
  }

  const int nv = mesh.num_vertices();
  int pole = options.pole;
  if (pole < 0) {
    pole = choose_pole_vertex(mesh, topology);
  } else if (pole >= nv || topology.vertex_component[pole] < 0) {
    throw InvalidInput("sphere_map: pole vertex " + std::to_string(pole) +
                       (pole >= nv
                            ? " is out of range (the mesh has " + std::to_string(nv) + " vertices)"
                            : " belongs to no face"));
  }
  SphereResult result = map_with_pole(mesh, topology, pole, options);
  // A pole on the tip of a limb (flat and regular, as choose_pole_vertex likes) squeezes the
  // rest of the surface into a corner of the plane by the limb's conformal factor, e^-37 at the
  // tip of a finger six times as long as it is round: beyond what even quad resolves, where the
  // sphere may need far less. The map at hand, right where the plane was resolved (the bulk of
  // the surface), says where the surface is widest on the sphere; the vertex whose star is
  // largest there makes the plane no more squeezed than the sphere. (Where quad suffices it
  // costs less than a second flow: 0.5 s on 14k vertices.)
  if (options.pole < 0 && result.flow.converged &&
      precision_level(result.min_plane_altitude) == 3) {
    const int wide = widest_star_vertex(topology, result.positions);
    if (wide >= 0 && wide != pole) {
      SphereResult second = map_with_pole(mesh, topology, wide, options);
      second.poles_tried = 2;
      if (preferred(second, result)) result = std::move(second);
    }
    result.poles_tried = 2;
  }
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace ricci
