#include "ricci/param/sphere.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "ricci/errors.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/mesh/validate.hpp"
#include "ricci/param/layout.hpp"

namespace ricci {
namespace {

using Clock = std::chrono::steady_clock;
using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Angle between two vectors, accurate for small and obtuse angles alike.
double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// det(a, b, c) = a . (b x c), computed from the differences b - a and c - a, which keeps its
/// relative accuracy on small triangles of points far from the origin.
double det3(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return a.dot((b - a).cross(c - a));
}

/// Signed area of the geodesic triangle a b c on the unit sphere (Van Oosterom and Strackee 1983):
/// tan(E / 2) = det(a, b, c) / (1 + a.b + b.c + c.a).
double spherical_area(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                      const Eigen::Vector3d& c) {
  return 2 * std::atan2(det3(a, b, c), 1 + a.dot(b) + b.dot(c) + c.dot(a));
}

/// Inverse stereographic projection from the north pole, mirrored (y -> -y) so that it keeps
/// the orientation: counter-clockwise in the plane seen from +z stays counter-clockwise on the
/// sphere seen from outside. The unit circle goes to the equator, its inside to the southern
/// hemisphere.
Eigen::Vector3d lift(const Eigen::Vector2d& p) {
  const double r2 = p.squaredNorm();
  return Eigen::Vector3d(2 * p.x(), -2 * p.y(), r2 - 1) / (1 + r2);
}

/// The boost phi_a of the file comment of sphere.hpp, renormalised onto the sphere.
Eigen::Vector3d boost(const Eigen::Vector3d& x, const Eigen::Vector3d& a) {
  const Eigen::Vector3d d = x - a;
  const Eigen::Vector3d y = (1 - a.squaredNorm()) / d.squaredNorm() * d - a;
  return y / y.norm();
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

/// sigma_max / sigma_min of the linear map between two triangles of R^3, each in its own plane,
/// and twice their areas (the second signed by `orientation`). In complex coordinates of the
/// planes, w = alpha z + beta conj(z); the singular values are |alpha| +- |beta| and
/// |alpha|^2 - |beta|^2 is the area ratio, so the ratio is (|alpha| + |beta|)^2 / |area ratio|
/// (the determinant from the cross products, not from the cancelling |alpha| - |beta|).
double angle_distortion(const Eigen::Vector3d (&p)[3], const Eigen::Vector3d (&q)[3],
                        double orientation) {
  auto frame = [](const Eigen::Vector3d& e1, const Eigen::Vector3d& e2, double sign, Complex& z1,
                  Complex& z2) {
    const double l1 = e1.norm();
    const double twice_area = e1.cross(e2).norm();
    z1 = Complex(l1, 0);
    z2 = Complex(e1.dot(e2) / l1, sign * twice_area / l1);
    return sign * twice_area;
  };
  Complex z1, z2, w1, w2;
  const double twice_area = frame(p[1] - p[0], p[2] - p[0], 1.0, z1, z2);
  const double twice_image = frame(q[1] - q[0], q[2] - q[0], orientation, w1, w2);
  if (!(twice_area > 0) || twice_image == 0 || !std::isfinite(twice_image)) {
    return std::numeric_limits<double>::infinity();
  }
  // alpha D and beta D with D = z1 conj(z2) - z2 conj(z1), |D| = 2 twice_area, and
  // |alpha|^2 - |beta|^2 = twice_image / twice_area.
  const double alpha_d = std::abs(w1 * std::conj(z2) - w2 * std::conj(z1));
  const double beta_d = std::abs(w2 * z1 - w1 * z2);
  const double sum = alpha_d + beta_d;
  return sum * sum / std::abs(4 * twice_area * twice_image);
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

  SphereResult result;
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
  MeshFlowOptions flow_options;
  flow_options.structure = options.structure;
  flow_options.flow = options.flow;
  flow_options.target.kind = TargetKind::Flat;
  flow_options.target.boundary = BoundaryMode::DiskLength;
  for (int v : result.disk_vertices) flow_options.vertex_labels.push_back(v);
  // The disk's problem (topology, lengths, structure), built once: the layout reads it too.
  const FlowProblem disk_problem = make_flow_problem(disk, options.structure);
  result.flow = flow_mesh(disk_problem, flow_options);
  result.flow_seconds = result.flow.total_seconds;
  if (!result.flow.converged) {
    result.message = "the flow on the disk did not converge: " + result.flow.message;
    result.seconds = seconds_since(start);
    return result;
  }

  // 3. Layout, normalised so that the boundary's least-squares circle is the unit circle.
  const auto layout_start = Clock::now();
  // The disk's own faces, developed in the flat metric when the flow flipped edges (the same
  // vertex positions as a layout of the intrinsic triangulation, which may be a Delta-complex).
  const Topology& disk_topology = disk_problem.topology;
  if (disk_topology.components.size() != 1 || disk_topology.boundary_loops.size() != 1) {
    throw Error("sphere_map: removing the pole's star did not leave a disk (internal error)");
  }
  CutMesh uncut;
  uncut.triangles = disk_topology.triangles;
  uncut.topology = disk_topology;
  uncut.to_original.resize(disk_topology.num_vertices);
  for (int v = 0; v < disk_topology.num_vertices; ++v) uncut.to_original[v] = v;
  const Layout layout = layout_flat(
      disk_topology, develop_input_faces(disk_topology, result.flow).shapes, CutGraph{}, uncut);
  result.layout_length_error = layout.max_length_relative_error;
  const std::vector<int>& loop = disk_topology.boundary_loops[0];
  std::vector<Eigen::Vector2d> boundary;
  boundary.reserve(loop.size());
  for (int v : loop) boundary.emplace_back(layout.uv.row(v).transpose());
  Eigen::Vector2d centre;
  double radius = 0;
  fit_circle(boundary, centre, radius);
  result.plane.setConstant(nv, 2, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < result.disk_vertices.size(); ++i) {
    result.plane.row(result.disk_vertices[i]) =
        (layout.uv.row(static_cast<Eigen::Index>(i)) - centre.transpose()) / radius;
  }
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const Eigen::Vector2d p = result.plane.row(result.disk_vertices[loop[k]]);
    const Eigen::Vector2d q = result.plane.row(result.disk_vertices[loop[(k + 1) % loop.size()]]);
    result.boundary_circle_deviation =
        std::max(result.boundary_circle_deviation, std::abs(p.norm() - 1));
    // The loop runs with the disk on its left, so the face (q, p, pole) beyond it keeps its
    // orientation when the pole's wedge p -> q turns counter-clockwise about the origin.
    if (!(p.x() * q.y() - p.y() * q.x() > 0)) ++result.inverted_pole_faces;
  }

  // 4. Onto the sphere, the pole at the north pole.
  result.positions.setZero(nv, 3);
  for (int v : result.disk_vertices) {
    result.positions.row(v) = lift(result.plane.row(v).transpose()).transpose();
  }
  result.positions.row(pole) << 0, 0, 1;
  result.layout_seconds = seconds_since(layout_start);

  // 5. Moebius normalisation: damped Newton on the boost parameter a.
  const auto normalisation_start = Clock::now();
  Eigen::VectorXd weights(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = mesh.positions.row(mesh.triangles(f, 0));
    const Eigen::Vector3d b = mesh.positions.row(mesh.triangles(f, 1));
    const Eigen::Vector3d c = mesh.positions.row(mesh.triangles(f, 2));
    weights[f] = (b - a).cross(c - a).norm();
  }
  const double total_area = weights.sum();
  weights /= total_area;
  Centre current = centre_of_mass(result.positions, mesh.triangles, weights);
  result.initial_centre = current.c.norm();
  Positions trial(nv, 3);
  const std::vector<int>& referenced = component.vertices;
  bool stalled = false;
  while (current.c.norm() > options.centre_tolerance &&
         result.centre_iterations < options.max_centre_iterations) {
    Eigen::Vector3d a = (2 * current.M).ldlt().solve(current.c);
    if (!a.allFinite()) a = current.c / 2;
    // Steps of at most 0.5: phi_a stretches by up to (1 + |a|) / (1 - |a|), which the centre's
    // linearisation does not foresee far from a = 0.
    constexpr double kLargestStep = 0.5;
    if (a.norm() > kLargestStep) a *= kLargestStep / a.norm();
    bool accepted = false;
    for (int halving = 0; halving < 40; ++halving) {
      trial = result.positions;
      for (int v : referenced) {
        trial.row(v) = boost(result.positions.row(v).transpose(), a).transpose();
      }
      const Centre next = centre_of_mass(trial, mesh.triangles, weights);
      if (next.c.norm() < current.c.norm()) {
        result.positions.swap(trial);
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
  result.normalisation_seconds = seconds_since(normalisation_start);

  // 6. Invariants and distortion of the final map.
  for (int v : referenced) {
    result.max_radius_deviation =
        std::max(result.max_radius_deviation, std::abs(result.positions.row(v).norm() - 1));
  }
  const int nf = mesh.num_faces();
  std::vector<double> ratios(nf), log_area, log_weight;
  double ratio_sum = 0, angle_error_sum = 0;
  result.log_area_min = std::numeric_limits<double>::infinity();
  result.log_area_max = -std::numeric_limits<double>::infinity();
  for (int f = 0; f < nf; ++f) {
    Eigen::Vector3d p[3], q[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = mesh.positions.row(mesh.triangles(f, k));
      q[k] = result.positions.row(mesh.triangles(f, k));
    }
    const double det = det3(q[0], q[1], q[2]);
    if (!(det > 0)) ++result.inverted_faces;
    const double area = spherical_area(q[0], q[1], q[2]);
    result.spherical_area += area;
    ratios[f] = angle_distortion(p, q, det < 0 ? -1.0 : 1.0);
    result.angle_distortion_max = std::max(result.angle_distortion_max, ratios[f]);
    ratio_sum += weights[f] * ratios[f];
    for (int k = 0; k < 3; ++k) {
      const int j = (k + 1) % 3, l = (k + 2) % 3;
      const double error = std::abs(angle_between(q[j] - q[k], q[l] - q[k]) -
                                    angle_between(p[j] - p[k], p[l] - p[k]));
      angle_error_sum += error;
      result.angle_error_max = std::max(result.angle_error_max, error);
    }
    if (area > 0) {
      const double value = std::log(area / (4 * kPi) / weights[f]);
      log_area.push_back(value);
      log_weight.push_back(weights[f]);
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

  result.converged = result.centre_of_mass <= options.centre_tolerance;
  if (!result.converged) {
    result.message = "the Moebius normalisation left the centre of mass at " +
                     std::to_string(result.centre_of_mass) + " after " +
                     std::to_string(result.centre_iterations) + " steps" +
                     (stalled ? " (no step reduced it further)" : "");
  }
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace ricci
