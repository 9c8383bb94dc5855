#include "ricci/param/layout/polish.hpp"

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
#include "ricci/numerics/timer.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;
using Uv = Eigen::Matrix<double, Eigen::Dynamic, 2>;

[[noreturn]] void invalid_polish_input(const std::string& what) {
  throw InvalidInput("polish_angles: " + what);
}

/// The map from a 3D triangle to its layout is w = alpha z + beta conj(z), alpha D and beta D
/// linear in the corners' images (param/detail/face_distortion.hpp); the face's sigma ratio is
/// (A + B) / (A - B) with A = |alpha D|, B = |beta D|, and a vertex moving alone changes A and B
/// as distances to two points (each is |P + a_k w|).
using detail::FaceCoefficients;
using detail::ratio_from_moduli;

/// Vertices of more faces than this are not moved to unflip one (see nearest_feasible_point).
constexpr int kMaxUntangleValence = 24;

/// |z| without hypot's care for overflow (layout coordinates are far from it): the sweeps take
/// a few million of them.
double magnitude(Complex z) {
  return std::sqrt(z.real() * z.real() + z.imag() * z.imag());
}

/// One face around the vertex being moved: A = |p + a w|, B = |q + b w|.
struct Term {
  Complex p, q, a, b;
};

double energy(const std::vector<Term>& terms, Complex w) {
  double sum = 0;
  for (const Term& t : terms)
    sum += ratio_from_moduli(magnitude(t.p + t.a * w), magnitude(t.q + t.b * w));
  return sum;
}

/// B at most this fraction of A counts as B = 0 (a conformal face), where B has a kink and no
/// gradient: B's terms are left out.
constexpr double kConformalFace = 1e-14;

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
    if (b > kConformalFace * a) {  // at B = 0 (a conformal face) B has a kink: no gradient there
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

/// The Hessian's eigenvalues are clamped to at least this fraction of the largest modulus: a
/// direction of negative or no curvature gets a long but finite step (the caller caps it).
constexpr double kEigenvalueFloor = 1e-6;

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
  const double floor = kEigenvalueFloor * top;
  l1 = std::max(l1, floor);
  l2 = std::max(l2, floor);
  return -(v1 * (v1.dot(g) / l1) + v2 * (v2.dot(g) / l2));
}

/// A candidate may violate a constraint by this fraction of the largest offset (the rounding of
/// the projections and intersections that produced it).
constexpr double kConstraintSlack = 1e-14;
/// Two constraint lines (unit normals) whose normals' cross product is at most this are taken
/// as parallel: they have no meeting point worth trying.
constexpr double kParallelLines = 1e-12;

/// The point nearest to `from` in the half-planes n_i . v >= c_i (|n_i| = 1), a quadratic
/// programme in the plane: its optimum is `from`, the projection onto one constraint's line, or
/// the meeting point of two lines, so every candidate is tried (a handful of constraints around
/// one vertex: cubic in their number). Returns false when no candidate is feasible.
bool nearest_feasible_point(const std::vector<Eigen::Vector2d>& n, const std::vector<double>& c,
                            const Eigen::Vector2d& from, Eigen::Vector2d& best) {
  const int m = static_cast<int>(n.size());
  double scale = 0;
  for (double x : c) scale = std::max(scale, std::abs(x));
  const double slack = kConstraintSlack * scale;
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
      if (!(std::abs(det) > kParallelLines)) continue;
      consider(Eigen::Vector2d((c[i] * n[j].y() - c[j] * n[i].y()) / det,
                               (n[i].x() * c[j] - n[j].x() * c[i]) / det));
    }
  }
  return std::isfinite(nearest);
}

void check_polish_inputs(const Mesh& mesh, const Triangles& uv_triangles, const Uv& uv,
                         const PolishOptions& options) {
  const int num_faces = mesh.num_faces();
  const int num_uv = static_cast<int>(uv.rows());
  if (uv_triangles.rows() != num_faces) {
    invalid_polish_input("uv_triangles has " + std::to_string(uv_triangles.rows()) +
                         " rows but the mesh has " + std::to_string(num_faces) + " faces");
  }
  if (options.max_sweeps < 0) invalid_polish_input("max_sweeps is negative");
  if (!(options.tolerance >= 0)) invalid_polish_input("tolerance is negative or NaN");
  for (int f = 0; f < num_faces; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int i = uv_triangles(f, k), v = mesh.triangles(f, k);
      if (i < 0 || i >= num_uv) {
        invalid_polish_input("face " + std::to_string(f) + " has uv index " + std::to_string(i) +
                             " out of range [0, " + std::to_string(num_uv) + ")");
      }
      if (v < 0 || v >= mesh.num_vertices()) {
        invalid_polish_input("face " + std::to_string(f) + " has vertex " + std::to_string(v) +
                             " out of range");
      }
    }
  }
}

/// The corners (3 f + k) around each uv vertex, in compressed rows: those of vertex i are
/// corners[offset[i]] .. corners[offset[i + 1] - 1].
struct Incidence {
  std::vector<int> offset, corners;
};

Incidence incident_corners(const Triangles& uv_triangles, int num_uv) {
  const int num_faces = static_cast<int>(uv_triangles.rows());
  Incidence in{std::vector<int>(num_uv + 1, 0),
               std::vector<int>(3 * static_cast<size_t>(num_faces))};
  for (int f = 0; f < num_faces; ++f) {
    for (int k = 0; k < 3; ++k) ++in.offset[uv_triangles(f, k) + 1];
  }
  for (int i = 0; i < num_uv; ++i) in.offset[i + 1] += in.offset[i];
  std::vector<int> next(in.offset.begin(), in.offset.end() - 1);
  for (int f = 0; f < num_faces; ++f) {
    for (int k = 0; k < 3; ++k) in.corners[next[uv_triangles(f, k)]++] = 3 * f + k;
  }
  return in;
}

/// Minimum free vertices per thread in a colour class: a visit takes about a microsecond, and a
/// helper thread at hand a microsecond or two to take a chunk (parallel.hpp). With a thread
/// started per chunk (40-50 us) this was 512, and spot's classes (under 500 vertices) ran on one
/// core.
constexpr int kMinVerticesPerThread = 64;

/// The uv vertices on a boundary edge of the uv mesh (an edge of one face there: the seams and
/// the mesh boundary; also edges of three or more faces): those with a neighbour that the faces
/// around them name other than twice. In parallel over the vertices (a sort of all edges took
/// 4 ms of bunny's 35 ms polish).
std::vector<char> uv_boundary_vertices(const Triangles& uv_triangles, const Incidence& in) {
  const int num_uv = static_cast<int>(in.offset.size()) - 1;
  std::vector<char> fixed(num_uv, 0);
  parallel::for_chunks(
      num_uv,
      [&](std::int64_t begin, std::int64_t end, int) {
        std::vector<int> neighbours;
        for (std::int64_t i = begin; i < end; ++i) {
          neighbours.clear();
          for (int s = in.offset[i]; s < in.offset[i + 1]; ++s) {
            const int f = in.corners[s] / 3, k = in.corners[s] % 3;
            neighbours.push_back(uv_triangles(f, (k + 1) % 3));
            neighbours.push_back(uv_triangles(f, (k + 2) % 3));
          }
          std::sort(neighbours.begin(), neighbours.end());
          for (std::size_t r = 0; r < neighbours.size() && !fixed[i];) {
            std::size_t e = r;
            while (e < neighbours.size() && neighbours[e] == neighbours[r]) ++e;
            fixed[i] = e - r != 2;
            r = e;
          }
        }
      },
      kMinVerticesPerThread);
  return fixed;
}

/// The layout being polished with its faces' coefficients: what every step reads.
struct Drawing {
  const Mesh& mesh;
  const Triangles& uv_triangles;
  std::vector<FaceCoefficients> faces;
  Uv& uv;
  Incidence incidence;

  int num_faces() const { return static_cast<int>(faces.size()); }
  Complex w_of(int i) const { return Complex(uv(i, 0), uv(i, 1)); }
  double face_ratio(int f) const {
    Complex a = 0, b = 0;
    for (int k = 0; k < 3; ++k) {
      const Complex w = w_of(uv_triangles(f, k));
      a += faces[f].a[k] * w;
      b += faces[f].b[k] * w;
    }
    return ratio_from_moduli(magnitude(a), magnitude(b));
  }
  /// Mean over the faces with a finite ratio (positive 3D and layout area).
  double mean_ratio() const {
    double sum = 0;
    int count = 0;
    for (int f = 0; f < num_faces(); ++f) {
      if (!faces[f].valid) continue;
      const double r = face_ratio(f);
      if (std::isfinite(r)) sum += r, ++count;
    }
    return count > 0 ? sum / count : std::numeric_limits<double>::quiet_NaN();
  }
  double signed_area(int f) const {
    const Complex a = w_of(uv_triangles(f, 0));
    const Complex b = w_of(uv_triangles(f, 1)) - a, c = w_of(uv_triangles(f, 2)) - a;
    return b.real() * c.imag() - b.imag() * c.real();
  }
  int count_flipped() const {
    int n = 0;
    for (int f = 0; f < num_faces(); ++f) n += faces[f].valid && !(signed_area(f) > 0);
    return n;
  }
};

/// The fractions of its own height each face around a moved vertex must keep, tried in turn:
/// the largest that a position fits.
constexpr double kHeightFractions[] = {0.5, 0.1, 0.01};

/// Moves uv vertex i (free, of few faces) as little as keeps each face around it at least a
/// fraction of its own height above its far edge (a half-plane per face), the largest fraction
/// of kHeightFractions that fits. Returns true when it moved and every face around it is
/// positive (else it stays where it was).
bool unflip_vertex(Drawing& d, int i) {
  const std::vector<int>& offset = d.incidence.offset;
  const std::vector<int>& incident = d.incidence.corners;
  std::vector<Eigen::Vector2d> normals;
  std::vector<double> heights, offsets;
  for (int s = offset[i]; s < offset[i + 1]; ++s) {
    const int g = incident[s] / 3, j = incident[s] % 3;
    const Complex a = d.w_of(d.uv_triangles(g, (j + 1) % 3));
    const Complex b = d.w_of(d.uv_triangles(g, (j + 2) % 3));
    const Complex edge = b - a;
    // The face's own height over that edge, at the scale the layout gives the edge: what it
    // would have drawn undistorted.
    const Eigen::Vector3d pa = d.mesh.positions.row(d.mesh.triangles(g, (j + 1) % 3));
    const Eigen::Vector3d pb = d.mesh.positions.row(d.mesh.triangles(g, (j + 2) % 3));
    const Eigen::Vector3d pv = d.mesh.positions.row(d.mesh.triangles(g, j));
    const double edge_3d = (pb - pa).norm();
    if (!(magnitude(edge) > 0 && edge_3d > 0)) return false;
    const double height_3d = (pa - pv).cross(pb - pv).norm() / edge_3d;
    // v left of a -> b: cross(b - a, v - a) > 0, i.e. n . v > n . a, n = i (b - a).
    normals.emplace_back(Eigen::Vector2d(-edge.imag(), edge.real()) / magnitude(edge));
    heights.push_back(height_3d * magnitude(edge) / edge_3d);
    offsets.push_back(normals.back().dot(Eigen::Vector2d(a.real(), a.imag())));
  }
  const Eigen::Vector2d from(d.uv(i, 0), d.uv(i, 1));
  Eigen::Vector2d point;
  bool found = false;
  for (double fraction : kHeightFractions) {
    std::vector<double> c(normals.size());
    for (std::size_t q = 0; q < normals.size(); ++q) c[q] = offsets[q] + fraction * heights[q];
    if ((found = nearest_feasible_point(normals, c, from, point))) break;
  }
  if (!found) return false;
  const Eigen::RowVector2d before = d.uv.row(i);
  d.uv.row(i) = point.transpose();
  bool all_positive = true;
  for (int s = offset[i]; s < offset[i + 1] && all_positive; ++s) {
    all_positive = d.signed_area(incident[s] / 3) > 0;
  }
  if (!all_positive) d.uv.row(i) = before;
  return all_positive;
}

/// Untangle: a face drawn flipped (a needle or an obtuse sliver whose vertices' exact images
/// fold it) may have a vertex that is free to move. Where the faces around it leave room, it
/// moves as little as keeps each of them a fraction of its own height above its far edge, and
/// the face unflips without flipping another; the sweeps then smooth it. Returns the faces
/// unflipped.
int unflip_faces(Drawing& d, const std::vector<char>& fixed, std::vector<char>& moved) {
  const std::vector<int>& offset = d.incidence.offset;
  const int flipped_before = d.count_flipped();
  for (int f = 0; f < d.num_faces(); ++f) {
    if (d.signed_area(f) > 0 || !d.faces[f].valid) continue;
    for (int k = 0; k < 3 && !(d.signed_area(f) > 0); ++k) {
      const int i = d.uv_triangles(f, k);
      // The candidates are cubic in the vertex's valence: a CAD fan's hub is left alone.
      if (fixed[i] || offset[i + 1] - offset[i] > kMaxUntangleValence) continue;
      if (unflip_vertex(d, i)) moved[i] = 1;
    }
  }
  return flipped_before - d.count_flipped();
}

/// Newton steps per vertex visit.
constexpr int kNewtonSteps = 2;
/// A step moves the vertex by at most this fraction of its shortest edge: the ratios blow up
/// where a face flips, and the line search should not have to find its way back from there.
constexpr double kStepCap = 0.25;
/// A decrease below this fraction of the sum is within its rounding: none (a conformal layout
/// stays bit for bit).
constexpr double kNegligibleDecrease = 1e-13;
/// The line search halves the step down to this fraction of the Newton step.
constexpr double kSmallestPolishStep = 1e-6;

/// The sum over vertex i's faces before and after relax_vertex, and how many faces.
struct VertexEnergy {
  double before = 0, after = 0;
  std::size_t faces = 0;
  bool moved = false;
};

/// Up to kNewtonSteps Newton steps (Hessian clamped positive, backtracking) of free vertex i on
/// the sum of its faces' ratios; moves it when the sum decreased.
VertexEnergy relax_vertex(Drawing& d, int i, std::vector<Term>& terms) {
  const std::vector<int>& offset = d.incidence.offset;
  const std::vector<int>& incident = d.incidence.corners;
  terms.clear();
  double shortest = std::numeric_limits<double>::infinity();
  const Complex w0 = d.w_of(i);
  for (int s = offset[i]; s < offset[i + 1]; ++s) {
    const int f = incident[s] / 3, k = incident[s] % 3;
    Term t{0, 0, d.faces[f].a[k], d.faces[f].b[k]};
    for (int j = 0; j < 3; ++j) {
      if (j == k) continue;
      const Complex w = d.w_of(d.uv_triangles(f, j));
      t.p += d.faces[f].a[j] * w;
      t.q += d.faces[f].b[j] * w;
      shortest = std::min(shortest, magnitude(w - w0));
    }
    terms.push_back(t);
  }
  Complex w = w0;
  double e = energy(terms, w);
  const double e0 = e;
  for (int step = 0; step < kNewtonSteps; ++step) {
    Eigen::Vector2d g;
    Eigen::Matrix2d h;
    derivatives(terms, w, g, h);
    Eigen::Vector2d dir = newton_direction(g, h);
    const double cap = kStepCap * shortest;
    if (dir.norm() > cap) dir *= cap / dir.norm();
    if (!dir.allFinite() || dir.norm() == 0) break;
    const double negligible = kNegligibleDecrease * e;
    if (!(-g.dot(dir) > negligible)) break;
    bool accepted = false;
    for (double t = 1; t > kSmallestPolishStep; t *= 0.5) {
      const Complex trial = w + t * Complex(dir.x(), dir.y());
      const double et = energy(terms, trial);
      if (et < e - negligible) {
        w = trial, e = et, accepted = true;
        break;
      }
    }
    if (!accepted) break;
  }
  const bool moved = w != w0;
  if (moved) {
    d.uv(i, 0) = w.real();
    d.uv(i, 1) = w.imag();
  }
  return {e0, e, terms.size(), moved};
}

/// The free vertices in classes no two of whose vertices share a face (greedy colouring in the
/// order of `free`, each class in that order): a vertex's relaxation reads only its faces'
/// vertices, so one class's vertices relax independently, in parallel, and give the same
/// layout whatever the thread count.
std::vector<std::vector<int>> independent_classes(const Drawing& d, const std::vector<int>& free) {
  const std::vector<int>& offset = d.incidence.offset;
  const std::vector<int>& incident = d.incidence.corners;
  const int num_uv = static_cast<int>(d.uv.rows());
  std::vector<int> colour(num_uv, -1);
  std::vector<int> taken_by;  // taken_by[c] == i: colour c is used next to vertex i
  std::vector<std::vector<int>> classes;
  for (const int i : free) {
    for (int s = offset[i]; s < offset[i + 1]; ++s) {
      const int f = incident[s] / 3;
      for (int j = 0; j < 3; ++j) {
        const int c = colour[d.uv_triangles(f, j)];
        if (c >= 0) taken_by[c] = i;
      }
    }
    int c = 0;
    while (c < static_cast<int>(taken_by.size()) && taken_by[c] == i) ++c;
    if (c == static_cast<int>(taken_by.size())) {
      taken_by.push_back(-1);
      classes.emplace_back();
    }
    colour[i] = c;
    classes[c].push_back(i);
  }
  return classes;
}

/// The sweeps over the free vertices: each visited vertex relaxes on its own faces until a
/// sweep lowers the mean ratio's excess over 1 by less than options.tolerance of it; a sweep
/// takes the independent classes in turn, each in parallel. A vertex is visited again only
/// when it, or a vertex of one of its faces, lowered its own faces' excess by a noticeable
/// fraction in the sweep before: later sweeps touch the few places that still change (igea,
/// 134k free vertices: 5 full sweeps took 1.6 s). Sets result.sweeps and
/// result.angle_distortion_after (which holds the mean on entry).
void sweep_free_vertices(Drawing& d, const std::vector<int>& free, const PolishOptions& options,
                         std::vector<char>& moved, PolishResult& result) {
  const std::vector<int>& offset = d.incidence.offset;
  const std::vector<int>& incident = d.incidence.corners;
  const int num_uv = static_cast<int>(d.uv.rows());
  const std::vector<std::vector<int>> classes = independent_classes(d, free);
  double mean = result.angle_distortion_after;
  std::vector<char> active(num_uv, 1), next_active(num_uv, 0), improved(num_uv, 0);
  for (int sweep = 0; sweep < options.max_sweeps; ++sweep) {
    for (const std::vector<int>& members : classes) {
      parallel::for_chunks(
          static_cast<std::int64_t>(members.size()),
          [&](std::int64_t begin, std::int64_t end, int) {
            std::vector<Term> terms;
            for (std::int64_t a = begin; a < end; ++a) {
              const int i = members[a];
              if (!active[i]) continue;
              const VertexEnergy e = relax_vertex(d, i, terms);
              if (e.moved) moved[i] = 1;
              // before - #faces is the excess of the ratios over 1 on its faces.
              improved[i] = e.before - e.after >
                            options.tolerance * (e.before - static_cast<double>(e.faces));
            }
          },
          kMinVerticesPerThread);
    }
    for (const int i : free) {
      if (!active[i] || !improved[i]) continue;
      for (int s = offset[i]; s < offset[i + 1]; ++s) {
        const int f = incident[s] / 3;
        for (int j = 0; j < 3; ++j) next_active[d.uv_triangles(f, j)] = 1;
      }
    }
    active.swap(next_active);
    std::fill(next_active.begin(), next_active.end(), 0);
    std::fill(improved.begin(), improved.end(), 0);
    ++result.sweeps;
    const double now = d.mean_ratio();
    const double gain = mean - now;
    mean = now;
    if (!(gain > options.tolerance * (mean - 1))) break;
  }
  result.angle_distortion_after = mean;
}

}  // namespace

PolishResult polish_angles(const Mesh& mesh, const Triangles& uv_triangles, const Uv& uv,
                           const PolishOptions& options) {
  const auto start = Clock::now();
  check_polish_inputs(mesh, uv_triangles, uv, options);
  const int num_faces = mesh.num_faces();
  const int num_uv = static_cast<int>(uv.rows());
  PolishResult result;
  result.uv = uv;
  Drawing d{mesh, uv_triangles, std::vector<FaceCoefficients>(num_faces), result.uv,
            incident_corners(uv_triangles, num_uv)};
  for (int f = 0; f < num_faces; ++f) {
    const Eigen::Vector3d p0 = mesh.positions.row(mesh.triangles(f, 0)).transpose();
    const Eigen::Vector3d p1 = mesh.positions.row(mesh.triangles(f, 1)).transpose();
    const Eigen::Vector3d p2 = mesh.positions.row(mesh.triangles(f, 2)).transpose();
    d.faces[f] = detail::face_coefficients(detail::plane_triangle(p1 - p0, p2 - p0));
  }
  // Free vertices: on no boundary edge of the uv mesh, on no degenerate or flipped face.
  std::vector<char> fixed = uv_boundary_vertices(uv_triangles, d.incidence);
  result.angle_distortion_before = d.mean_ratio();
  std::vector<char> moved(num_uv, 0);
  if (options.enabled) result.untangled_faces = unflip_faces(d, fixed, moved);
  // Faces degenerate in 3D, or still flipped or degenerate in the layout, keep their vertices.
  for (int f = 0; f < num_faces; ++f) {
    if (d.faces[f].valid && std::isfinite(d.face_ratio(f))) continue;
    for (int k = 0; k < 3; ++k) fixed[uv_triangles(f, k)] = 1;
  }
  std::vector<int> free;
  for (int i = 0; i < num_uv; ++i) {
    if (!fixed[i] && d.incidence.offset[i + 1] > d.incidence.offset[i]) free.push_back(i);
  }
  result.free_vertices = static_cast<int>(free.size());
  result.angle_distortion_after = d.mean_ratio();
  if (options.enabled && !free.empty()) sweep_free_vertices(d, free, options, moved, result);
  result.moved_vertices = static_cast<int>(std::count(moved.begin(), moved.end(), 1));
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace ricci
