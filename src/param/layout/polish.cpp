#include "ricci/param/layout/polish.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "ricci/errors.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;
using Uv = Eigen::Matrix<double, Eigen::Dynamic, 2>;

[[noreturn]] void invalid(const std::string& what) {
  throw InvalidInput("polish_angles: " + what);
}

/// The map from a 3D triangle (in a frame of its plane, z_k) to its layout (w_k) is
/// w = alpha z + beta conj(z); alpha D = sum_k a_k w_k and beta D = sum_k b_k w_k with fixed
/// coefficients (D = z1 conj(z2) - z2 conj(z1), z0 = 0). Its singular values are |alpha| +
/// |beta| and |alpha| - |beta| (orientation kept when |alpha| > |beta|), so the face's sigma
/// ratio is (A + B) / (A - B) with A = |alpha D|, B = |beta D|: D cancels, and a vertex moving
/// alone changes A and B as distances to two points (each is |P + a_k w|).
struct FaceCoefficients {
  Complex a[3], b[3];
  bool valid = false;  // positive, finite 3D area
};

FaceCoefficients coefficients(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                              const Eigen::Vector3d& p2) {
  FaceCoefficients c;
  const Eigen::Vector3d e1 = p1 - p0, e2 = p2 - p0;
  const double twice_area = e1.cross(e2).norm();
  const double length1 = e1.norm();
  if (!(std::isfinite(twice_area) && twice_area > 0 && length1 > 0)) return c;
  const Complex z1(length1, 0.0), z2(e1.dot(e2) / length1, twice_area / length1);
  c.a[0] = -(std::conj(z2) - std::conj(z1));
  c.a[1] = std::conj(z2);
  c.a[2] = -std::conj(z1);
  c.b[0] = -(z1 - z2);
  c.b[1] = -z2;
  c.b[2] = z1;
  c.valid = true;
  return c;
}

/// Vertices of more faces than this are not moved to unflip one (see nearest_feasible_point).
constexpr int kMaxUntangleValence = 24;

/// |z| without hypot's care for overflow (layout coordinates are far from it): the sweeps take
/// a few million of them.
double magnitude(Complex z) {
  return std::sqrt(z.real() * z.real() + z.imag() * z.imag());
}

/// sigma_max / sigma_min from A and B; infinity when the face is flipped or degenerate.
double ratio(double a, double b) {
  // A - B below 1e-12 A: the face has collapsed to rounding.
  if (!(a - b > 1e-12 * a)) return std::numeric_limits<double>::infinity();
  return (a + b) / (a - b);
}

/// One face around the vertex being moved: A = |p + a w|, B = |q + b w|.
struct Term {
  Complex p, q, a, b;
};

double energy(const std::vector<Term>& terms, Complex w) {
  double sum = 0;
  for (const Term& t : terms) sum += ratio(magnitude(t.p + t.a * w), magnitude(t.q + t.b * w));
  return sum;
}

/// Gradient and Hessian (in the plane, w = x + i y) of the sum of ratios.
void derivatives(const std::vector<Term>& terms, Complex w, Eigen::Vector2d& g,
                 Eigen::Matrix2d& h) {
  g.setZero();
  h.setZero();
  for (const Term& t : terms) {
    const Complex ya = t.p + t.a * w, yb = t.q + t.b * w;
    const double a = magnitude(ya), b = magnitude(yb);
    const double d = a - b;
    // grad |y| for y = p + c w is (Re z, -Im z) with z = conj(y) c / |y|; its Hessian is
    // |c|^2 (I - n n^T) / |y| with n the gradient's direction.
    const Complex za = std::conj(ya) * t.a / a;
    const Eigen::Vector2d ga(za.real(), -za.imag());
    Eigen::Vector2d gb = Eigen::Vector2d::Zero();
    Eigen::Matrix2d hb = Eigen::Matrix2d::Zero();
    const double c2 = std::norm(t.a);  // |a| = |b|: the length of the opposite edge
    const Eigen::Matrix2d ha = (Eigen::Matrix2d::Identity() - ga * ga.transpose() / c2) * c2 / a;
    if (b > 1e-14 * a) {  // at B = 0 (a conformal face) B has a kink: no gradient there
      const Complex zb = std::conj(yb) * t.b / b;
      gb = Eigen::Vector2d(zb.real(), -zb.imag());
      hb = (Eigen::Matrix2d::Identity() - gb * gb.transpose() / c2) * c2 / b;
    }
    const double d2 = d * d, d3 = d2 * d;
    const double ra = -2 * b / d2, rb = 2 * a / d2;
    const double raa = 4 * b / d3, rbb = 4 * a / d3, rab = -2 * (a + b) / d3;
    g += ra * ga + rb * gb;
    h += ra * ha + rb * hb + raa * ga * ga.transpose() + rbb * gb * gb.transpose() +
         rab * (ga * gb.transpose() + gb * ga.transpose());
  }
}

/// Newton direction with the Hessian's eigenvalues clamped positive.
Eigen::Vector2d newton_direction(const Eigen::Vector2d& g, const Eigen::Matrix2d& h) {
  const double mean = 0.5 * (h(0, 0) + h(1, 1));
  const double half = 0.5 * (h(0, 0) - h(1, 1));
  const double radius = std::hypot(half, h(0, 1));
  double l1 = mean + radius, l2 = mean - radius;
  Eigen::Vector2d v1;
  if (radius == 0) {
    v1 = Eigen::Vector2d(1, 0);
  } else if (half >= 0) {
    v1 = Eigen::Vector2d(half + radius, h(0, 1)).normalized();
  } else {
    v1 = Eigen::Vector2d(h(0, 1), radius - half).normalized();
  }
  const Eigen::Vector2d v2(-v1.y(), v1.x());
  const double top = std::max(std::abs(l1), std::abs(l2));
  if (!(top > 0) || !std::isfinite(top)) return -g;
  const double floor = 1e-6 * top;
  l1 = std::max(l1, floor);
  l2 = std::max(l2, floor);
  return -(v1 * (v1.dot(g) / l1) + v2 * (v2.dot(g) / l2));
}

/// The point nearest to `from` in the half-planes n_i . v >= c_i (|n_i| = 1), a quadratic
/// programme in the plane: its optimum is `from`, the projection onto one constraint's line, or
/// the meeting point of two lines, so every candidate is tried (a handful of constraints around
/// one vertex: cubic in their number). Returns false when no candidate is feasible.
bool nearest_feasible_point(const std::vector<Eigen::Vector2d>& n, const std::vector<double>& c,
                            const Eigen::Vector2d& from, Eigen::Vector2d& best) {
  const int m = static_cast<int>(n.size());
  double scale = 0;
  for (double x : c) scale = std::max(scale, std::abs(x));
  const double slack = 1e-14 * scale;
  double nearest = std::numeric_limits<double>::infinity();
  auto consider = [&](const Eigen::Vector2d& p) {
    const double d = (p - from).squaredNorm();
    if (!(d < nearest) || !p.allFinite()) return;
    for (int q = 0; q < m; ++q) {
      if (n[q].dot(p) < c[q] - slack) return;
    }
    nearest = d, best = p;
  };
  consider(from);
  for (int i = 0; i < m; ++i) {
    consider(from + (c[i] - n[i].dot(from)) * n[i]);
    for (int j = i + 1; j < m; ++j) {
      const double det = n[i].x() * n[j].y() - n[i].y() * n[j].x();
      if (!(std::abs(det) > 1e-12)) continue;
      consider(Eigen::Vector2d((c[i] * n[j].y() - c[j] * n[i].y()) / det,
                               (n[i].x() * c[j] - n[j].x() * c[i]) / det));
    }
  }
  return std::isfinite(nearest);
}

}  // namespace

PolishResult polish_angles(const Mesh& mesh, const Triangles& uv_triangles, const Uv& uv,
                           const PolishOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const int num_faces = mesh.num_faces();
  const int num_uv = static_cast<int>(uv.rows());
  if (uv_triangles.rows() != num_faces) {
    invalid("uv_triangles has " + std::to_string(uv_triangles.rows()) + " rows but the mesh has " +
            std::to_string(num_faces) + " faces");
  }
  if (options.max_sweeps < 0) invalid("max_sweeps is negative");
  if (!(options.tolerance >= 0)) invalid("tolerance is negative or NaN");
  for (int f = 0; f < num_faces; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int i = uv_triangles(f, k), v = mesh.triangles(f, k);
      if (i < 0 || i >= num_uv) {
        invalid("face " + std::to_string(f) + " has uv index " + std::to_string(i) +
                " out of range [0, " + std::to_string(num_uv) + ")");
      }
      if (v < 0 || v >= mesh.num_vertices()) {
        invalid("face " + std::to_string(f) + " has vertex " + std::to_string(v) + " out of range");
      }
    }
  }

  PolishResult result;
  result.uv = uv;
  auto w_of = [&](int i) { return Complex(result.uv(i, 0), result.uv(i, 1)); };

  std::vector<FaceCoefficients> faces(num_faces);
  for (int f = 0; f < num_faces; ++f) {
    faces[f] = coefficients(mesh.positions.row(mesh.triangles(f, 0)).transpose(),
                            mesh.positions.row(mesh.triangles(f, 1)).transpose(),
                            mesh.positions.row(mesh.triangles(f, 2)).transpose());
  }
  auto face_ratio = [&](int f) {
    Complex a = 0, b = 0;
    for (int k = 0; k < 3; ++k) {
      const Complex w = w_of(uv_triangles(f, k));
      a += faces[f].a[k] * w;
      b += faces[f].b[k] * w;
    }
    return ratio(magnitude(a), magnitude(b));
  };
  // Mean over the faces with a finite ratio (positive 3D and layout area).
  auto mean_ratio = [&] {
    double sum = 0;
    int count = 0;
    for (int f = 0; f < num_faces; ++f) {
      if (!faces[f].valid) continue;
      const double r = face_ratio(f);
      if (std::isfinite(r)) sum += r, ++count;
    }
    return count > 0 ? sum / count : std::numeric_limits<double>::quiet_NaN();
  };

  // Free vertices: on no boundary edge of the uv mesh (an edge of one face there: the seams and
  // the mesh boundary; also edges of three or more faces), on no degenerate or flipped face.
  std::vector<char> fixed(num_uv, 0);
  {
    std::vector<std::uint64_t> edges;
    edges.reserve(3 * static_cast<size_t>(num_faces));
    for (int f = 0; f < num_faces; ++f) {
      for (int k = 0; k < 3; ++k) {
        const auto i = static_cast<std::uint64_t>(uv_triangles(f, k));
        const auto j = static_cast<std::uint64_t>(uv_triangles(f, (k + 1) % 3));
        edges.push_back(std::min(i, j) << 32 | std::max(i, j));
      }
    }
    std::sort(edges.begin(), edges.end());
    for (size_t s = 0; s < edges.size();) {
      size_t e = s;
      while (e < edges.size() && edges[e] == edges[s]) ++e;
      if (e - s != 2) {
        fixed[edges[s] >> 32] = 1;
        fixed[edges[s] & 0xffffffffu] = 1;
      }
      s = e;
    }
  }
  // Faces around each uv vertex (compressed rows).
  std::vector<int> offset(num_uv + 1, 0), incident(3 * static_cast<size_t>(num_faces));
  for (int f = 0; f < num_faces; ++f) {
    for (int k = 0; k < 3; ++k) ++offset[uv_triangles(f, k) + 1];
  }
  for (int i = 0; i < num_uv; ++i) offset[i + 1] += offset[i];
  {
    std::vector<int> next(offset.begin(), offset.end() - 1);
    for (int f = 0; f < num_faces; ++f) {
      for (int k = 0; k < 3; ++k) incident[next[uv_triangles(f, k)]++] = 3 * f + k;
    }
  }
  // Untangle: a face drawn flipped (a needle or an obtuse sliver whose vertices' exact images
  // fold it) may have a vertex that is free to move. Where the faces around it leave room, it
  // moves as little as keeps each of them a fraction of its own height above its far edge (a
  // half-plane per face), and the face unflips without flipping another; the sweeps below then
  // smooth it.
  auto signed_area = [&](int f) {
    const Complex a = w_of(uv_triangles(f, 0));
    const Complex b = w_of(uv_triangles(f, 1)) - a, c = w_of(uv_triangles(f, 2)) - a;
    return b.real() * c.imag() - b.imag() * c.real();
  };
  result.angle_distortion_before = mean_ratio();
  std::vector<char> moved(num_uv, 0);
  auto count_flipped = [&] {
    int n = 0;
    for (int f = 0; f < num_faces; ++f) n += faces[f].valid && !(signed_area(f) > 0);
    return n;
  };
  if (options.enabled) {
    const int flipped_before = count_flipped();
    std::vector<Eigen::Vector2d> normals;
    std::vector<double> heights, offsets;
    for (int f = 0; f < num_faces; ++f) {
      if (signed_area(f) > 0 || !faces[f].valid) continue;
      for (int k = 0; k < 3 && !(signed_area(f) > 0); ++k) {
        const int i = uv_triangles(f, k);
        // The candidates are cubic in the vertex's valence: a CAD fan's hub is left alone.
        if (fixed[i] || offset[i + 1] - offset[i] > kMaxUntangleValence) continue;
        normals.clear();
        heights.clear();
        offsets.clear();
        bool usable = true;
        for (int s = offset[i]; s < offset[i + 1] && usable; ++s) {
          const int g = incident[s] / 3, j = incident[s] % 3;
          const Complex a = w_of(uv_triangles(g, (j + 1) % 3));
          const Complex b = w_of(uv_triangles(g, (j + 2) % 3));
          const Complex edge = b - a;
          // The face's own height over that edge, at the scale the layout gives the edge: what
          // it would have drawn undistorted.
          const Eigen::Vector3d pa = mesh.positions.row(mesh.triangles(g, (j + 1) % 3));
          const Eigen::Vector3d pb = mesh.positions.row(mesh.triangles(g, (j + 2) % 3));
          const Eigen::Vector3d pv = mesh.positions.row(mesh.triangles(g, j));
          const double edge_3d = (pb - pa).norm();
          usable = magnitude(edge) > 0 && edge_3d > 0;
          if (!usable) break;
          const double height_3d = (pa - pv).cross(pb - pv).norm() / edge_3d;
          // v left of a -> b: cross(b - a, v - a) > 0, i.e. n . v > n . a, n = i (b - a).
          normals.emplace_back(Eigen::Vector2d(-edge.imag(), edge.real()) / magnitude(edge));
          heights.push_back(height_3d * magnitude(edge) / edge_3d);
          offsets.push_back(normals.back().dot(Eigen::Vector2d(a.real(), a.imag())));
        }
        if (!usable) continue;
        // The least move that leaves every face around the vertex at least this fraction of
        // its own height (so the unflipped face is not a new sliver), the largest that fits.
        const Eigen::Vector2d from(result.uv(i, 0), result.uv(i, 1));
        Eigen::Vector2d point;
        bool found = false;
        for (double fraction : {0.5, 0.1, 0.01}) {
          std::vector<double> c(normals.size());
          for (std::size_t q = 0; q < normals.size(); ++q)
            c[q] = offsets[q] + fraction * heights[q];
          if ((found = nearest_feasible_point(normals, c, from, point))) break;
        }
        if (!found) continue;
        const Eigen::RowVector2d before = result.uv.row(i);
        result.uv.row(i) = point.transpose();
        bool all_positive = true;
        for (int s = offset[i]; s < offset[i + 1] && all_positive; ++s) {
          all_positive = signed_area(incident[s] / 3) > 0;
        }
        if (!all_positive) {
          result.uv.row(i) = before;
          continue;
        }
        moved[i] = 1;
      }
    }
    result.untangled_faces = flipped_before - count_flipped();
  }
  // Faces degenerate in 3D, or still flipped or degenerate in the layout, keep their vertices.
  for (int f = 0; f < num_faces; ++f) {
    if (faces[f].valid && std::isfinite(face_ratio(f))) continue;
    for (int k = 0; k < 3; ++k) fixed[uv_triangles(f, k)] = 1;
  }
  std::vector<int> free;
  for (int i = 0; i < num_uv; ++i) {
    if (!fixed[i] && offset[i + 1] > offset[i]) free.push_back(i);
  }
  result.free_vertices = static_cast<int>(free.size());
  result.angle_distortion_after = mean_ratio();
  if (!options.enabled || free.empty()) {
    result.moved_vertices = static_cast<int>(std::count(moved.begin(), moved.end(), 1));
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }

  std::vector<Term> terms;
  double mean = result.angle_distortion_after;
  // A vertex is visited again only when it, or a vertex of one of its faces, lowered its own
  // faces' excess by a noticeable fraction in the sweep before: later sweeps touch the few
  // places that still change (igea, 134k free vertices: 5 full sweeps took 1.6 s).
  std::vector<char> active(num_uv, 1), next_active(num_uv, 0);
  for (int sweep = 0; sweep < options.max_sweeps; ++sweep) {
    for (const int i : free) {
      if (!active[i]) continue;
      terms.clear();
      double shortest = std::numeric_limits<double>::infinity();
      const Complex w0 = w_of(i);
      for (int s = offset[i]; s < offset[i + 1]; ++s) {
        const int f = incident[s] / 3, k = incident[s] % 3;
        Term t{0, 0, faces[f].a[k], faces[f].b[k]};
        for (int j = 0; j < 3; ++j) {
          if (j == k) continue;
          const Complex w = w_of(uv_triangles(f, j));
          t.p += faces[f].a[j] * w;
          t.q += faces[f].b[j] * w;
          shortest = std::min(shortest, magnitude(w - w0));
        }
        terms.push_back(t);
      }
      Complex w = w0;
      double e = energy(terms, w);
      const double e0 = e;
      for (int step = 0; step < 2; ++step) {
        Eigen::Vector2d g;
        Eigen::Matrix2d h;
        derivatives(terms, w, g, h);
        Eigen::Vector2d d = newton_direction(g, h);
        // At most a quarter of the shortest edge at a time: the ratios blow up where a face
        // flips, and the line search should not have to find its way back from there.
        const double cap = 0.25 * shortest;
        if (d.norm() > cap) d *= cap / d.norm();
        if (!d.allFinite() || d.norm() == 0) break;
        // A decrease within rounding of the sum is none: a conformal layout stays bit for bit.
        const double negligible = 1e-13 * e;
        if (!(-g.dot(d) > negligible)) break;
        bool accepted = false;
        for (double t = 1; t > 1e-6; t *= 0.5) {
          const Complex trial = w + t * Complex(d.x(), d.y());
          const double et = energy(terms, trial);
          if (et < e - negligible) {
            w = trial, e = et, accepted = true;
            break;
          }
        }
        if (!accepted) break;
      }
      if (w != w0) {
        result.uv(i, 0) = w.real();
        result.uv(i, 1) = w.imag();
        moved[i] = 1;
      }
      // e0 - #faces is the excess of the ratios over 1 on its faces.
      if (e0 - e > options.tolerance * (e0 - static_cast<double>(terms.size()))) {
        for (int s = offset[i]; s < offset[i + 1]; ++s) {
          const int f = incident[s] / 3;
          for (int j = 0; j < 3; ++j) next_active[uv_triangles(f, j)] = 1;
        }
      }
    }
    active.swap(next_active);
    std::fill(next_active.begin(), next_active.end(), 0);
    ++result.sweeps;
    const double now = mean_ratio();
    const double gain = mean - now;
    mean = now;
    if (!(gain > options.tolerance * (mean - 1))) break;
  }
  result.angle_distortion_after = mean;
  result.moved_vertices = static_cast<int>(std::count(moved.begin(), moved.end(), 1));
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace ricci
