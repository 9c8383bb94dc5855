#include "ricci/intrinsic/intrinsic_triangulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "metric/detail/triangle_terms.hpp"
#include "numerics/detail/parallel.hpp"
#include "ricci/errors.hpp"
#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/numerics/complex.hpp"
#include "ricci/numerics/mobius.hpp"

namespace ricci {
namespace {

/// A developed face whose doubled area is below this fraction of its longest side squared is
/// counted degenerate (zero area up to the rounding of the flips undone, a few ulps per flip).
constexpr double kDegenerateFace = 1e-14;

using Complex = std::complex<double>;
using Wide = long double;
using WideComplex = std::complex<Wide>;

/// The two halfedges of a flipped edge at the moment of its flip: h0 in face f0 opposite its
/// corner k0 (the new diagonal's corner a), h1 likewise (corner b).
struct FlipRecord {
  int h0, h1;
};

/// Throws InvalidInput in the name of `caller` unless flip i of a log, of edge e, can be made in
/// `t`.
void check_flippable(const char* caller, const Topology& t, std::size_t i, int e) {
  if (e < 0 || e >= t.num_edges || !can_flip_edge(t, e)) {
    throw InvalidInput(std::string(caller) + ": flip " + std::to_string(i) + " names edge " +
                       std::to_string(e) + ", which " +
                       (e < 0 || e >= t.num_edges ? "does not exist"
                                                  : "cannot be flipped in the triangulation "
                                                    "the earlier flips leave"));
  }
}

/// Replays the flips on `t` in place, recording their halfedges.
std::vector<FlipRecord> replay(Topology& t, const std::vector<int>& flipped_edges) {
  std::vector<FlipRecord> records;
  records.reserve(flipped_edges.size());
  for (std::size_t i = 0; i < flipped_edges.size(); ++i) {
    const int e = flipped_edges[i];
    check_flippable("replay_flips", t, i, e);
    records.push_back({t.edge_halfedges(e, 0), t.edge_halfedges(e, 1)});
    flip_edge(t, e);
  }
  return records;
}

/// Undoes the recorded flips on the faces' shapes, last first. Before the flip of record r, face
/// f0 read (c, a, b) and f1 (d, b, a) from corners k0 and k1; flip_edge turned them into (a, d, c)
/// and (b, c, d). `glue(a, d0, c0, b1, c1, d1)` receives f0's corners a, d, c and f1's b, c, d,
/// each face in its own frame, and returns a, b, c, d in one frame (f1 moved onto f0 along their
/// shared edge cd); `settle` may then move each new face into a frame of its choice.
template <class Point, class Glue, class Settle>
void undo_flips(const std::vector<FlipRecord>& records, std::vector<std::array<Point, 3>>& shapes,
                Glue glue, Settle settle) {
  for (auto r = records.rbegin(); r != records.rend(); ++r) {
    const int f0 = r->h0 / 3, k0 = r->h0 % 3, f1 = r->h1 / 3, k1 = r->h1 % 3;
    auto& p0 = shapes[f0];
    auto& p1 = shapes[f1];
    const std::array<Point, 4> q = glue(p0[k0], p0[(k0 + 1) % 3], p0[(k0 + 2) % 3], p1[k1],
                                        p1[(k1 + 1) % 3], p1[(k1 + 2) % 3]);
    const Point a = q[0], b = q[1], c = q[2], d = q[3];
    p0 = {c, a, b};
    std::rotate(p0.begin(), p0.begin() + (3 - k0) % 3, p0.end());
    p1 = {d, b, a};
    std::rotate(p1.begin(), p1.begin() + (3 - k1) % 3, p1.end());
    settle(p0);
    settle(p1);
  }
}

/// Hyperbolic distance of two points of the disk.
Wide disk_distance(WideComplex p, WideComplex q) {
  return 2 * std::atanh(std::abs(to_frame(p, q)));
}

/// Moves a face into its own frame: corner 0 at the centre, corner 1 on the positive real axis
/// (points stay near the centre, where the disk loses no precision).
void settle_hyperbolic(std::array<WideComplex, 3>& p) {
  const WideComplex q1 = to_frame(p[0], p[1]), q2 = to_frame(p[0], p[2]);
  const Wide r1 = std::abs(q1);
  p = {WideComplex{0}, WideComplex{r1}, q2 * std::conj(q1) / r1};
}

}  // namespace

Topology replay_flips(const Topology& input, const std::vector<int>& flipped_edges) {
  Topology t = input;
  replay(t, flipped_edges);
  return t;
}

OverlaidReplay replay_flips_with_overlay(const Topology& start, const Eigen::VectorXd& lengths,
                                         const std::vector<int>& flipped_edges, FlipLength kind,
                                         Geometry geometry) {
  OverlaidReplay r{start, identity_overlay(start), lengths};
  for (std::size_t i = 0; i < flipped_edges.size(); ++i) {
    const int e = flipped_edges[i];
    check_flippable("replay_flips_with_overlay", r.topology, i, e);
    // The new length from the quad before the flip changes it.
    const QuadLengths quad = quad_lengths(r.topology, r.lengths, r.topology.edge_halfedges(e, 0));
    const double diagonal = kind == FlipLength::Isometric ? isometric_diagonal(quad, geometry)
                                                          : ptolemy_diagonal(quad, geometry);
    flip_edge_with_overlay(r.topology, r.overlay, e);
    r.lengths[e] = diagonal;
  }
  return r;
}

FaceShapes face_shapes_from_lengths(const Topology& topology, const Eigen::VectorXd& lengths) {
  // Only the angle at corner 0 places a face: its cosine and sine from the half-angle formula on
  // Kahan's terms (corner_angles takes the angle from the same tangent), in parallel over the
  // faces.
  const int nf = topology.num_faces;
  FaceShapes shapes(static_cast<std::size_t>(nf));
  const std::int64_t bad = parallel::first_failing(
      nf,
      [&](std::int64_t f) {
        const double l[3] = {lengths[topology.face_edges(f, 0)], lengths[topology.face_edges(f, 1)],
                             lengths[topology.face_edges(f, 2)]};
        double two_s, d[3];
        if (!triangle_terms::half_perimeter_terms(l, two_s, d)) return false;
        // With t = tan(theta_0 / 2) = sqrt(b / a), a = 2 s d_0 and b = d_1 d_2: cos theta_0 =
        // (a - b) / (a + b) and sin theta_0 = 2 sqrt(a b) / (a + b), no trigonometric call.
        const double a = two_s * d[0], b = d[1] * d[2];
        const double cos0 = (a - b) / (a + b), sin0 = 2 * std::sqrt(a) * std::sqrt(b) / (a + b);
        shapes[f] = {Complex{0}, Complex{l[2]}, Complex{l[1] * cos0, l[1] * sin0}};
        return true;
      },
      parallel::kDefaultMinChunk / 4);
  if (bad >= 0) {
    throw InvalidInput("face_shapes_from_lengths: face " + std::to_string(bad) +
                       " breaks a triangle inequality");
  }
  return shapes;
}

Development develop_input_faces(const Topology& input, const std::vector<int>& flipped_edges,
                                const Eigen::VectorXd& final_lengths) {
  // The final triangulation: the input's own when nothing was flipped (no copy needed).
  std::optional<Topology> flipped;
  std::vector<FlipRecord> records;
  if (!flipped_edges.empty()) {
    flipped = input;
    records = replay(*flipped, flipped_edges);
  }
  const Topology& t = flipped ? *flipped : input;
  if (final_lengths.size() != t.num_edges) {
    throw InvalidInput("develop_input_faces: " + std::to_string(final_lengths.size()) +
                       " lengths for " + std::to_string(t.num_edges) + " edges");
  }
  Development d;
  d.shapes = face_shapes_from_lengths(t, final_lengths);
  FaceShapes& shapes = d.shapes;
  undo_flips(
      records, shapes,
      [](Complex a, Complex d0, Complex c0, Complex b1, Complex c1, Complex d1) {
        // The rigid motion taking f1's copy of the shared edge cd onto f0's: rotation from the
        // two directions, translation matching the midpoints (the copies agree up to rounding).
        // A shared edge of no length at all (two corners rounded onto one point: the doubled
        // repaired Stanford dragon has them) leaves the turn undetermined; any turn keeps the
        // development finite, and the faces it misplaces show up as flipped.
        Complex rotation = (d0 - c0) / (d1 - c1);
        rotation /= std::abs(rotation);
        if (!std::isfinite(rotation.real()) || !std::isfinite(rotation.imag())) rotation = 1;
        const Complex b = 0.5 * (c0 + d0) + rotation * (b1 - 0.5 * (c1 + d1));
        return std::array<Complex, 4>{a, b, c0, d0};
      },
      [](std::array<Complex, 3>&) {});

  d.lengths.resize(input.num_edges);
  auto side = [&](int h) {
    const auto& p = shapes[h / 3];
    return fast_abs(p[(h % 3 + 2) % 3] - p[(h % 3 + 1) % 3]);
  };
  // In parallel: the largest mismatch (a maximum: the same however the edges are split) and
  // the counts.
  d.max_length_mismatch = parallel::max_of(
      input.num_edges,
      [&](std::int64_t e) {
        const double la = side(input.edge_halfedges(e, 0));
        d.lengths[e] = la;
        if (input.edge_halfedges(e, 1) < 0) return 0.0;
        const double lb = side(input.edge_halfedges(e, 1));
        return std::abs(la - lb) / std::max(la, lb);
      },
      0.0);
  // 1 for a degenerate face, 2 for a flipped one, each face's kind found once. (Squared side
  // lengths as x^2 + y^2: std::norm goes through std::abs, a hypot, in libstdc++.)
  auto squared = [](Complex z) { return z.real() * z.real() + z.imag() * z.imag(); };
  std::vector<char> kind(static_cast<std::size_t>(input.num_faces));
  parallel::for_each(input.num_faces, [&](std::int64_t f) {
    const auto& p = shapes[f];
    const double area = cross(p[1] - p[0], p[2] - p[0]);
    const double scale =
        std::max({squared(p[1] - p[0]), squared(p[2] - p[1]), squared(p[0] - p[2])});
    kind[f] = std::abs(area) <= kDegenerateFace * scale ? 1 : area < 0 ? 2 : 0;
  });
  d.degenerate_faces = static_cast<int>(
      parallel::count_if(input.num_faces, [&](std::int64_t f) { return kind[f] == 1; }));
  d.flipped_faces = static_cast<int>(
      parallel::count_if(input.num_faces, [&](std::int64_t f) { return kind[f] == 2; }));
  return d;
}

WideFaceShapes hyperbolic_face_shapes_from_lengths(const Topology& topology,
                                                   const WideVector& lengths) {
  WideAngles angles;
  const int bad = hyperbolic_corner_angles_wide(topology, lengths, angles).first_bad_face;
  if (bad >= 0) {
    throw InvalidInput("hyperbolic_face_shapes_from_lengths: face " + std::to_string(bad) +
                       " breaks a triangle inequality");
  }
  // A point at hyperbolic distance l from the centre lies at Euclidean radius tanh(l / 2).
  WideFaceShapes shapes(static_cast<std::size_t>(topology.num_faces));
  for (int f = 0; f < topology.num_faces; ++f) {
    shapes[f] = {WideComplex{0}, WideComplex{std::tanh(lengths[topology.face_edges(f, 2)] / 2)},
                 std::polar(std::tanh(lengths[topology.face_edges(f, 1)] / 2), angles(f, 0))};
  }
  return shapes;
}

HyperbolicDevelopment develop_input_faces_hyperbolic(const Topology& input,
                                                     const std::vector<int>& flipped_edges,
                                                     const WideVector& final_lengths) {
  Topology t = input;
  const std::vector<FlipRecord> records = replay(t, flipped_edges);
  if (final_lengths.size() != t.num_edges) {
    throw InvalidInput("develop_input_faces_hyperbolic: " + std::to_string(final_lengths.size()) +
                       " lengths for " + std::to_string(t.num_edges) + " edges");
  }
  HyperbolicDevelopment d;
  d.shapes = hyperbolic_face_shapes_from_lengths(t, final_lengths);
  undo_flips(
      records, d.shapes,
      [](WideComplex a, WideComplex d0, WideComplex c0, WideComplex b1, WideComplex c1,
         WideComplex d1) {
        // Both faces moved so that c is the centre and d lies on the positive real axis: the
        // isometry taking f1's copy of the shared edge cd onto f0's.
        const WideComplex d0_frame = to_frame(c0, d0), d1_frame = to_frame(c1, d1);
        const Wide r0 = std::abs(d0_frame), r1 = std::abs(d1_frame);
        const WideComplex a_frame = to_frame(c0, a) * std::conj(d0_frame) / r0;
        const WideComplex b_frame = to_frame(c1, b1) * std::conj(d1_frame) / r1;
        return std::array<WideComplex, 4>{a_frame, b_frame, WideComplex{0},
                                          WideComplex{(r0 + r1) / 2}};
      },
      settle_hyperbolic);

  d.lengths.resize(input.num_edges);
  auto side = [&](int h) {
    const auto& p = d.shapes[h / 3];
    return disk_distance(p[(h % 3 + 2) % 3], p[(h % 3 + 1) % 3]);
  };
  for (int e = 0; e < input.num_edges; ++e) {
    const Wide la = side(input.edge_halfedges(e, 0));
    d.lengths[e] = la;
    if (input.edge_halfedges(e, 1) >= 0) {
      const Wide lb = side(input.edge_halfedges(e, 1));
      d.max_length_mismatch = std::max(d.max_length_mismatch,
                                       static_cast<double>(std::abs(la - lb) / std::max(la, lb)));
    }
  }
  for (int f = 0; f < input.num_faces; ++f) {
    // Geodesic triangles are convex: orientation and degeneracy are those of the straight one.
    const auto& p = d.shapes[f];
    const WideComplex e1 = p[1] - p[0], e2 = p[2] - p[0];
    const Wide area = e1.real() * e2.imag() - e1.imag() * e2.real();
    const Wide scale = std::max({std::norm(e1), std::norm(p[2] - p[1]), std::norm(e2)});
    if (std::abs(area) <= Wide{kDegenerateFace} * scale) {
      ++d.degenerate_faces;
    } else if (area < 0) {
      ++d.flipped_faces;
    }
  }
  return d;
}

}  // namespace ricci

namespace ricci {

IntrinsicTriangulation::IntrinsicTriangulation(std::shared_ptr<const Topology> input,
                                               ConformalStructure structure)
    : input_(std::move(input)), structure_(std::move(structure)) {
  if (!input_) throw InvalidInput("IntrinsicTriangulation: no input triangulation");
  if (structure_.eta.size() != input_->num_edges ||
      structure_.epsilon.size() != input_->num_vertices ||
      structure_.initial_u.size() != input_->num_vertices) {
    throw InvalidInput(
        "IntrinsicTriangulation: the conformal structure does not belong to the "
        "input triangulation");
  }
}

IntrinsicTriangulation::IntrinsicTriangulation(const Topology& input, ConformalStructure structure)
    // An aliasing pointer with no owner: it refers to `input` and never deletes it.
    : IntrinsicTriangulation(std::shared_ptr<const Topology>(std::shared_ptr<void>(), &input),
                             std::move(structure)) {}

namespace {
const Topology kNoTopology;
}  // namespace

const Topology& IntrinsicTriangulation::input() const {
  return input_ ? *input_ : kNoTopology;
}

const Topology& IntrinsicTriangulation::topology() const {
  return flipped_ ? *flipped_ : input();
}

void IntrinsicTriangulation::adopt_input(std::shared_ptr<const Topology> input) {
  if (!input || (input_ && (input->num_vertices != input_->num_vertices ||
                            input->num_edges != input_->num_edges ||
                            input->num_faces != input_->num_faces))) {
    throw InvalidInput("IntrinsicTriangulation::adopt_input: not the same triangulation");
  }
  input_ = std::move(input);
}

void IntrinsicTriangulation::set_eta(Eigen::VectorXd eta) {
  if (eta.size() != topology().num_edges) {
    throw InvalidInput("IntrinsicTriangulation::set_eta: expected " +
                       std::to_string(topology().num_edges) + " values, got " +
                       std::to_string(eta.size()));
  }
  structure_.eta = std::move(eta);
}

int IntrinsicTriangulation::isometric_flips() const {
  return static_cast<int>(
      std::count(flip_is_isometric_.begin(), flip_is_isometric_.end(), char{1}));
}

Topology& IntrinsicTriangulation::own_topology() {
  if (!flipped_) {
    flipped_ = std::make_shared<Topology>(*input_);
  } else if (flipped_.use_count() > 1) {
    flipped_ = std::make_shared<Topology>(*flipped_);
  }
  return *flipped_;
}

DelaunayFlipResult IntrinsicTriangulation::flip_to_delaunay(const Eigen::VectorXd& u,
                                                            Eigen::VectorXd& lengths,
                                                            const DelaunayFlipOptions& options) {
  // A connectivity that would have to be copied first is copied only when some edge fails the
  // test (ricci::flip_to_delaunay returns at once when none does, as here).
  if ((!flipped_ || flipped_.use_count() > 1) &&
      count_non_delaunay_edges(topology(), lengths, options.tolerance, structure_.geometry) == 0) {
    blocked_ = 0;
    return {};
  }
  DelaunayFlipResult r = ricci::flip_to_delaunay(own_topology(), structure_, u, lengths, options);
  flips_ += r.flips;
  flipped_edges_.insert(flipped_edges_.end(), r.flipped_edges.begin(), r.flipped_edges.end());
  flip_is_isometric_.insert(flip_is_isometric_.end(), r.flipped_edges.size(),
                            options.isometric ? 1 : 0);
  blocked_ = r.blocked;
  return r;
}

bool IntrinsicTriangulation::is_simplicial() const {
  return ricci::is_simplicial(topology());
}

Topology IntrinsicTriangulation::replayed() const {
  return replay_flips(*input_, flipped_edges_);
}

Development IntrinsicTriangulation::develop_input_faces(
    const Eigen::VectorXd& final_lengths) const {
  return ricci::develop_input_faces(*input_, flipped_edges_, final_lengths);
}

HyperbolicDevelopment IntrinsicTriangulation::develop_input_faces_hyperbolic(
    const WideVector& final_lengths) const {
  return ricci::develop_input_faces_hyperbolic(*input_, flipped_edges_, final_lengths);
}

void IntrinsicTriangulation::gather_component(const IntrinsicTriangulation& part,
                                              const std::vector<int>& faces,
                                              const std::vector<int>& vertex_map,
                                              const std::vector<int>& edge_map) {
  const Topology& local = part.topology();
  if (static_cast<int>(faces.size()) != local.num_faces ||
      static_cast<int>(vertex_map.size()) != local.num_vertices ||
      static_cast<int>(edge_map.size()) != local.num_edges) {
    throw InvalidInput(
        "IntrinsicTriangulation::gather_component: the maps do not match the "
        "component's triangulation");
  }
  flips_ += part.flips_;
  blocked_ += part.blocked_;
  if (part.flipped_edges_.empty()) return;
  // Flips reuse face and edge indices, so face f and edge e of the component stay face faces[f]
  // and edge edge_map[e] of the whole mesh; only what they join changes.
  Topology& whole = own_topology();
  auto halfedge = [&](int h) { return h < 0 ? -1 : 3 * faces[h / 3] + h % 3; };
  for (int f = 0; f < local.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int h = 3 * f + k, hw = halfedge(h), fw = faces[f];
      whole.triangles(fw, k) = vertex_map[local.triangles(f, k)];
      whole.face_edges(fw, k) = edge_map[local.face_edges(f, k)];
      whole.halfedge_edge[hw] = edge_map[local.halfedge_edge[h]];
      whole.halfedge_twin[hw] = halfedge(local.halfedge_twin[h]);
    }
  }
  for (int e = 0; e < local.num_edges; ++e) {
    const int ew = edge_map[e];
    // vertex_map is ascending, so the smaller end stays first.
    whole.edge_vertices(ew, 0) = vertex_map[local.edge_vertices(e, 0)];
    whole.edge_vertices(ew, 1) = vertex_map[local.edge_vertices(e, 1)];
    whole.edge_halfedges(ew, 0) = halfedge(local.edge_halfedges(e, 0));
    whole.edge_halfedges(ew, 1) = halfedge(local.edge_halfedges(e, 1));
  }
  for (int i = 0; i < local.num_vertices; ++i) {
    whole.vertex_degree[vertex_map[i]] = local.vertex_degree[i];
  }
  for (int e : part.flipped_edges_) flipped_edges_.push_back(edge_map[e]);
  flip_is_isometric_.insert(flip_is_isometric_.end(), part.flip_is_isometric_.begin(),
                            part.flip_is_isometric_.end());
}

void IntrinsicTriangulation::add_flip_counts(const IntrinsicTriangulation& part) {
  flips_ += part.flips_;
  blocked_ += part.blocked_;
}

}  // namespace ricci
