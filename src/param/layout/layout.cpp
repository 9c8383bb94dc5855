#include "ricci/param/layout/layout.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <queue>
#include <string>
#include <unordered_map>
#include <utility>

#include <Eigen/SparseCore>

#include "numerics/detail/parallel.hpp"
#include "param/layout/detail/layout_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/numerics/complex.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"

namespace ricci {

namespace {

using Complex = std::complex<double>;

/// Below this |angle| (radians) a transition counts as a pure translation when looking for the
/// lattice of a flat torus: the flow leaves curvature errors near 1e-10, cones are >= 1e-3.
constexpr double kTranslationAngleTolerance = 1e-6;

std::string face_message(const std::string& what, int f) {
  return "layout_flat: face " + std::to_string(f) + ": " + what;
}

/// The two copies of a cut edge's ends: a0, a1 on the side of halfedge `ha` (in its direction),
/// b0, b1 the same two original vertices seen from the other side (halfedge `hb`, the twin).
struct EdgeCopies {
  Complex a0, a1, b0, b1;
};

EdgeCopies edge_copies(const Topology& cut_topology, const std::vector<Complex>& uv, int ha,
                       int hb) {
  return {uv[cut_topology.tail(ha)], uv[cut_topology.head(ha)], uv[cut_topology.head(hb)],
          uv[cut_topology.tail(hb)]};
}

/// Least-squares rigid motion z -> a z + b taking points `from` onto `to` (2-D Procrustes: the
/// rotation of the centred cross-covariance, the translation matching the centroids).
struct RigidFit {
  Complex rotation{1}, translation{0};
};

RigidFit fit_rigid(const std::vector<Complex>& from, const std::vector<Complex>& to) {
  const double n = static_cast<double>(from.size());
  Complex from_mean{0}, to_mean{0};
  for (std::size_t i = 0; i < from.size(); ++i) {
    from_mean += from[i];
    to_mean += to[i];
  }
  from_mean /= n;
  to_mean /= n;
  Complex covariance{0};
  for (std::size_t i = 0; i < from.size(); ++i) {
    covariance += (to[i] - to_mean) * std::conj(from[i] - from_mean);
  }
  RigidFit fit;
  const double norm = std::abs(covariance);
  fit.rotation = norm > 0 ? covariance / norm : Complex{1};
  fit.translation = to_mean - fit.rotation * from_mean;
  return fit;
}

/// A rotation angle within this of -pi is a half turn, printed as +pi: std::arg returns
/// [-pi, pi], and which end a half turn lands on is rounding.
constexpr double kHalfTurnSlack = 1e-9;

SeamTransition make_transition(int edge, int segment, const RigidFit& fit) {
  SeamTransition t;
  t.edge = edge;
  t.segment = segment;
  t.rotation = fit.rotation;
  t.translation = fit.translation;
  t.angle = std::arg(fit.rotation);
  // std::arg returns [-pi, pi]; a half turn must print the same however rounding falls.
  if (t.angle <= -std::numbers::pi + kHalfTurnSlack) t.angle += 2 * std::numbers::pi;
  return t;
}

/// Translations shorter than this fraction of the longest are zero (a segment whose two sides
/// the flow's rounding alone moved apart); pairs whose parallelogram is below this fraction of
/// the longest squared do not span the plane.
constexpr double kNegligibleTranslation = 1e-9;
/// A pair spans a sublattice when its parallelogram is above this fraction of the largest (an
/// area below it is a rounding artefact of nearly parallel translations) ...
constexpr double kSpanningArea = 1e-6;
/// ... and it replaces the best pair so far only when smaller by more than this fraction (equal
/// areas keep the first pair however rounding falls).
constexpr double kSmallerArea = 1e-9;

/// A reduced basis (Lagrange-Gauss: |b1| <= |b2|, |<b1, b2>| <= |b1|^2 / 2, counter-clockwise)
/// of the lattice the translations generate. Among the pairs that span the plane, the one with
/// the smallest parallelogram is taken: for the theta and figure-eight cut graphs of a torus every
/// spanning pair of segment translations is a basis, and a smaller parallelogram can only be a
/// finer sublattice basis. Empty when the translations do not span the plane.
std::vector<Complex> reduced_lattice(const std::vector<Complex>& translations) {
  double scale = 0;
  for (Complex t : translations) scale = std::max(scale, std::abs(t));
  std::vector<Complex> candidates;
  for (Complex t : translations) {
    if (std::abs(t) > kNegligibleTranslation * scale) candidates.push_back(t);
  }
  double largest = 0;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    for (std::size_t j = i + 1; j < candidates.size(); ++j) {
      largest = std::max(largest, std::abs(cross(candidates[i], candidates[j])));
    }
  }
  if (!(largest > kNegligibleTranslation * scale * scale)) return {};
  Complex b1, b2;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    for (std::size_t j = i + 1; j < candidates.size(); ++j) {
      const double area = std::abs(cross(candidates[i], candidates[j]));
      if (area > kSpanningArea * largest && area < best * (1 - kSmallerArea)) {
        best = area;
        b1 = candidates[i];
        b2 = candidates[j];
      }
    }
  }
  for (int iteration = 0; iteration < 100; ++iteration) {
    if (std::norm(b1) > std::norm(b2)) std::swap(b1, b2);
    const double mu = std::round((b2 * std::conj(b1)).real() / std::norm(b1));
    if (mu == 0) break;
    b2 -= mu * b1;
  }
  if (cross(b1, b2) < 0) b2 = -b2;
  return {b1, b2};
}

/// Largest | |p_i - p_j| - l_ij | / l_ij over the edges of every face (in parallel: a maximum
/// is the same however the faces are split).
double length_error(const Topology& topology, const Topology& cut_topology,
                    const Eigen::VectorXd& lengths, const std::vector<Complex>& uv) {
  return parallel::max_of(
      cut_topology.num_faces,
      [&](std::int64_t f) {
        double worst = 0;
        for (int k = 0; k < 3; ++k) {
          const double l = lengths[topology.face_edges(f, k)];
          const double d = fast_abs(uv[cut_topology.triangles(f, (k + 1) % 3)] -
                                    uv[cut_topology.triangles(f, (k + 2) % 3)]);
          worst = std::max(worst, std::abs(d - l) / l);
        }
        return worst;
      },
      0.0);
}

/// Each face's rotation into the layout, propagated from the root faces across uncut edges
/// (breadth first): the face across an edge is turned so that its copy of the edge points the way
/// the first face's does. Unit complex numbers compose with an error that adds up (about one ulp
/// of angle per step), where positions placed vertex by vertex multiply it through needles. In
/// the same pass every vertex is placed once, by the first face that reaches it, from the two
/// corners it shares with the face it was reached from: the average of
/// p_i + R (q_k - q_i) and p_j + R (q_k - q_j). Returns the rotations.
std::vector<Complex> lay_out_by_rotations(const Topology& cut_topology,
                                          const std::vector<std::array<Complex, 3>>& q,
                                          const std::vector<int>& roots, std::vector<Complex>& uv) {
  const int nf = cut_topology.num_faces;
  std::vector<Complex> rotation(nf, Complex{0});
  std::vector<char> placed(uv.size(), 0);
  std::vector<int> queue;
  queue.reserve(nf);
  for (int root : roots) {
    rotation[root] = 1;
    for (int k = 0; k < 3; ++k) {
      uv[cut_topology.triangles(root, k)] = q[root][k];
      placed[cut_topology.triangles(root, k)] = 1;
    }
    queue.push_back(root);
  }
  for (std::size_t next = 0; next < queue.size(); ++next) {
    const int f = queue[next];
    for (int k = 0; k < 3; ++k) {
      const int twin = cut_topology.halfedge_twin[3 * f + k];
      if (twin < 0) continue;
      const int g = twin / 3, kg = twin % 3;
      if (rotation[g] != Complex{0}) continue;
      // Halfedge 3f + k runs from corner k + 1 to corner k + 2 of f; its twin the other way.
      const Complex in_f = q[f][(k + 2) % 3] - q[f][(k + 1) % 3];
      const Complex in_g = q[g][(kg + 1) % 3] - q[g][(kg + 2) % 3];
      // rotation[f] in_f / in_g up to the positive factor |in_g|^2, which the normalisation
      // drops: a multiplication by the conjugate instead of a complex division.
      const Complex turn = rotation[f] * (in_f * std::conj(in_g));
      const double size = fast_abs(turn);
      // A zero-length edge leaves the turn undetermined: keep the neighbour's.
      rotation[g] = std::isfinite(size) && size > 0 ? turn / size : rotation[f];
      queue.push_back(g);
      // The twin lies opposite corner kg of g; its ends, corners kg + 1 and kg + 2, are f's.
      const int vk = cut_topology.triangles(g, kg);
      if (placed[vk]) continue;
      const int ki = (kg + 1) % 3, kj = (kg + 2) % 3;
      const Complex from_i =
          uv[cut_topology.triangles(g, ki)] + rotation[g] * (q[g][kg] - q[g][ki]);
      const Complex from_j =
          uv[cut_topology.triangles(g, kj)] + rotation[g] * (q[g][kg] - q[g][kj]);
      uv[vk] = 0.5 * (from_i + from_j);
      placed[vk] = 1;
    }
  }
  return rotation;
}

/// Global least-squares layout: positions p minimising the sum over faces and their edges
/// (a, b) of |p_b - p_a - R_f (q_b - q_a)|^2, with q_f the face's triangle in the metric and R_f
/// its rotation: first the propagated rotations (lay_out_by_rotations), then, for further
/// iterations, each face's best rotation onto the current layout. The vertex-by-vertex layout
/// multiplies rounding errors through needles (igea's 1-degree triangles in a vertex-scaling
/// metric: relative length errors up to 1e-5); this one solves one Poisson-like system and
/// spreads the metric's residual holonomy over every edge. One vertex per component keeps its
/// place (the gauge).
void refine_least_squares(const Topology& cut_topology,
                          const std::vector<std::array<Complex, 3>>& q,
                          const std::vector<Complex>& propagated, int iterations,
                          std::vector<Complex>& uv) {
  const int nf = cut_topology.num_faces, nv = cut_topology.num_vertices;
  std::vector<int> row(nv, -1);
  std::vector<char> pinned(nv, 0);
  for (const Component& c : cut_topology.components) pinned[c.vertices.front()] = 1;
  int n = 0;
  for (int v = 0; v < nv; ++v) {
    if (!pinned[v] && cut_topology.vertex_component[v] >= 0) row[v] = n++;
  }
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(12 * static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = row[cut_topology.triangles(f, (k + 1) % 3)];
      const int b = row[cut_topology.triangles(f, (k + 2) % 3)];
      if (a >= 0) triplets.emplace_back(a, a, 1.0);
      if (b >= 0) triplets.emplace_back(b, b, 1.0);
      if (a >= 0 && b >= 0) {
        triplets.emplace_back(a, b, -1.0);
        triplets.emplace_back(b, a, -1.0);
      }
    }
  }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(triplets.begin(), triplets.end());
  SparseCholesky cholesky;
  cholesky.factorize(A);
  Eigen::VectorXd bx(n), by(n);
  for (int iteration = 0; iteration < iterations; ++iteration) {
    bx.setZero();
    by.setZero();
    for (int f = 0; f < nf; ++f) {
      int v[3];
      for (int k = 0; k < 3; ++k) v[k] = cut_topology.triangles(f, k);
      Complex rotation = propagated[f];
      if (iteration > 0) {
        Complex fit{0};
        for (int k = 0; k < 3; ++k) {
          const int a = (k + 1) % 3, b = (k + 2) % 3;
          fit += (uv[v[b]] - uv[v[a]]) * std::conj(q[f][b] - q[f][a]);
        }
        rotation = fit / std::abs(fit);
      }
      for (int k = 0; k < 3; ++k) {
        const int a = (k + 1) % 3, b = (k + 2) % 3;
        const Complex d = rotation * (q[f][b] - q[f][a]);
        // Normal equations of |p_b - p_a - d|^2; a pinned end moves to the right-hand side.
        const int ra = row[v[a]], rb = row[v[b]];
        if (rb >= 0) {
          const Complex c = d + (ra < 0 ? uv[v[a]] : Complex{0});
          bx[rb] += c.real();
          by[rb] += c.imag();
        }
        if (ra >= 0) {
          const Complex c = -d + (rb < 0 ? uv[v[b]] : Complex{0});
          bx[ra] += c.real();
          by[ra] += c.imag();
        }
      }
    }
    const Eigen::VectorXd x = cholesky.solve(bx), y = cholesky.solve(by);
    for (int vtx = 0; vtx < nv; ++vtx) {
      if (row[vtx] >= 0) uv[vtx] = Complex{x[row[vtx]], y[row[vtx]]};
    }
  }
}

/// Each face's triangle in the metric, corner 0 at 0 and corner 1 on the positive real axis:
/// from the lengths of its sides 1 and 2 and the signed angle at its corner 0, angle0(f) (it
/// turns the direction to corner 1 into the direction to corner 2; negative on a face whose
/// shape is reversed). In parallel over the faces.
template <class Angle0>
std::vector<std::array<Complex, 3>> face_triangles(const Topology& topology,
                                                   const Eigen::VectorXd& lengths, Angle0 angle0) {
  std::vector<std::array<Complex, 3>> q(static_cast<std::size_t>(topology.num_faces));
  parallel::for_each(
      topology.num_faces,
      [&](std::int64_t f) {
        q[f] = {Complex{0}, Complex{lengths[topology.face_edges(f, 2)]},
                std::polar(lengths[topology.face_edges(f, 1)], angle0(f))};
      },
      parallel::kDefaultMinChunk / 4);
  return q;
}

/// The layout proper, from each edge's length and each face's triangle (face_triangles).
Layout layout_from_triangles(const Topology& topology, const Eigen::VectorXd& lengths,
                             const std::vector<std::array<Complex, 3>>& q, const CutGraph& cut,
                             const CutMesh& cut_mesh, const LayoutOptions& options,
                             const layout_support::Roots* ahead = nullptr) {
  const Topology& cut_topology = cut_mesh.topology;
  const int nf = topology.num_faces;
  const int ncv = cut_topology.num_vertices;
  Layout layout;
  std::vector<int> own_roots;
  if (ahead) {
    layout.root_face = ahead->first;
  } else {
    own_roots = layout_support::root_faces(cut_topology, options.root_face, layout.root_face);
  }
  const std::vector<int>& roots = ahead ? ahead->faces : own_roots;

  // Each face's triangle in the metric, corner 0 at 0 and corner 1 on the positive real axis,
  // and its rotation into the layout, propagated face to face across uncut edges from the roots
  // (lay_out_by_rotations): rotation errors add up, about one ulp of angle per step. Vertices are
  // then placed breadth first over the same faces, each new corner from the two it shares with
  // the face it was reached from, by that face's own rotated triangle: positions take no
  // direction from other positions, so rounding is not magnified through needles, which is how
  // placing each vertex from the direction p_j - p_i went wrong (errors multiplied by l_ik / l_ij
  // per step: 1.8e-8 relative on a 1M-face disk, 1e-5 on igea's 1-degree needles in a
  // vertex-scaling metric; this gives 1e-10 and below at the cost of one pass).
  std::vector<Complex> uv(ncv, Complex{0});
  const std::vector<Complex> rotation = lay_out_by_rotations(cut_topology, q, roots, uv);

  layout.max_length_relative_error = length_error(topology, cut_topology, lengths, uv);
  if (options.refine_above >= 0 && layout.max_length_relative_error > options.refine_above) {
    refine_least_squares(cut_topology, q, rotation, options.refine_iterations, uv);
    layout.refined = true;
    layout.max_length_relative_error = length_error(topology, cut_topology, lengths, uv);
  }

  layout.uv.resize(ncv, 2);
  parallel::for_each(ncv, [&](std::int64_t v) {
    layout.uv(v, 0) = uv[v].real();
    layout.uv(v, 1) = uv[v].imag();
  });
  layout.num_flipped_faces = static_cast<int>(parallel::count_if(nf, [&](std::int64_t f) {
    const Complex p0 = uv[cut_topology.triangles(f, 0)];
    return !(cross(uv[cut_topology.triangles(f, 1)] - p0, uv[cut_topology.triangles(f, 2)] - p0) >
             0);
  }));

  if (cut.is_cut_edge.empty()) return layout;

  const layout_support::SegmentEdges segments =
      layout_support::segment_edges("layout_flat", topology, cut);
  const std::vector<int>& edge_segment = segments.edge_segment;

  // One rigid motion per cut edge, side B onto side A.
  for (int e = 0; e < topology.num_edges; ++e) {
    if (!cut.is_cut_edge[e]) continue;
    const int ha = topology.edge_halfedges(e, 0), hb = topology.edge_halfedges(e, 1);
    if (ha < 0 || hb < 0) continue;  // a boundary edge: nothing on the other side
    const EdgeCopies c = edge_copies(cut_topology, uv, ha, hb);
    const RigidFit fit = fit_rigid({c.b0, c.b1}, {c.a0, c.a1});
    SeamTransition t = make_transition(e, edge_segment[e], fit);
    t.mismatch = std::max(std::abs(fit.rotation * c.b0 + fit.translation - c.a0),
                          std::abs(fit.rotation * c.b1 + fit.translation - c.a1)) /
                 lengths[e];
    layout.transitions.push_back(t);
  }

  // One rigid motion per segment, fitted to the ends of all its edges. Side A is the side of
  // edge_halfedges(e, 0) for the segment's first edge, and the same side of the path (left or
  // right of its direction) for the others: edge_halfedges(e, 0) alone may switch sides along a
  // path.
  for (std::size_t s = 0; s < cut.segments.size(); ++s) {
    const std::vector<int>& edges = segments.segment_edges[s];
    std::vector<Complex> from, to;
    std::vector<double> scale;
    for (int e : edges) {
      const int ha = segments.side_a_halfedge[e];
      if (ha < 0) continue;
      const EdgeCopies c = edge_copies(cut_topology, uv, ha, topology.halfedge_twin[ha]);
      from.insert(from.end(), {c.b0, c.b1});
      to.insert(to.end(), {c.a0, c.a1});
      scale.insert(scale.end(), {lengths[e], lengths[e]});
    }
    if (from.empty()) {
      layout.segment_transitions.push_back(
          make_transition(edges.empty() ? -1 : edges.front(), static_cast<int>(s), {}));
      continue;
    }
    const RigidFit fit = fit_rigid(from, to);
    SeamTransition t = make_transition(edges.front(), static_cast<int>(s), fit);
    for (std::size_t i = 0; i < from.size(); ++i) {
      t.mismatch = std::max(t.mismatch,
                            std::abs(fit.rotation * from[i] + fit.translation - to[i]) / scale[i]);
    }
    layout.segment_transitions.push_back(t);
  }

  // The lattice of a flat torus: the segments' translations generate it.
  if (topology.components.size() == 1 && topology.components[0].genus == 1 &&
      topology.components[0].num_boundary_loops == 0 && !layout.segment_transitions.empty()) {
    std::vector<Complex> translations;
    bool translations_only = true;
    for (const SeamTransition& t : layout.segment_transitions) {
      translations_only = translations_only && std::abs(t.angle) < kTranslationAngleTolerance;
      translations.push_back(t.translation);
    }
    if (translations_only) layout.lattice = reduced_lattice(translations);
  }
  return layout;
}

}  // namespace

Layout layout_flat(const Topology& topology, const Eigen::VectorXd& lengths, const CutGraph& cut,
                   const CutMesh& cut_mesh, const LayoutOptions& options) {
  layout_support::check_inputs("layout_flat", topology, lengths, cut, cut_mesh, options.root_face);
  // Corner angles of the original faces are those of the cut mesh's: same faces, same corners.
  CornerAngles angles;
  const int bad = corner_angles(topology, lengths, angles).first_bad_face;
  if (bad >= 0) {
    throw InvalidInput(face_message(
        "its lengths " + std::to_string(lengths[topology.face_edges(bad, 0)]) + ", " +
            std::to_string(lengths[topology.face_edges(bad, 1)]) + ", " +
            std::to_string(lengths[topology.face_edges(bad, 2)]) + " break a triangle inequality",
        bad));
  }
  const auto q = face_triangles(topology, lengths, [&](std::int64_t f) { return angles(f, 0); });
  return layout_from_triangles(topology, lengths, q, cut, cut_mesh, options);
}

namespace {

Layout layout_flat_from_shapes(const Topology& topology, const FaceShapes& shapes,
                               const CutGraph& cut, const CutMesh& cut_mesh,
                               const LayoutOptions& options, const layout_support::Roots* ahead) {
  if (shapes.size() != static_cast<std::size_t>(topology.num_faces)) {
    throw InvalidInput("layout_flat: " + std::to_string(shapes.size()) + " face shapes for " +
                       std::to_string(topology.num_faces) + " faces");
  }
  // Each edge's length as its first face sees it (its other face agrees up to rounding).
  Eigen::VectorXd lengths(topology.num_edges);
  parallel::for_each(topology.num_edges, [&](std::int64_t e) {
    const int h = topology.edge_halfedges(e, 0);
    const auto& p = shapes[h / 3];
    lengths[e] = fast_abs(p[(h % 3 + 2) % 3] - p[(h % 3 + 1) % 3]);
  });
  layout_support::check_inputs("layout_flat", topology, lengths, cut, cut_mesh, options.root_face);
  // Each face's turn at corner 0 from its shape (only that one places the face): the unit
  // complex number z / |z| for z = (p2 - p0) / (p1 - p0), its angle's cosine and sine without
  // a trigonometric call (a degenerate shape: from the angle, as std::arg gives it).
  std::vector<std::array<Complex, 3>> q(static_cast<std::size_t>(topology.num_faces));
  parallel::for_each(
      topology.num_faces,
      [&](std::int64_t f) {
        const auto& p = shapes[f];
        const Complex z = (p[2] - p[0]) / (p[1] - p[0]);
        const double r = std::abs(z);
        const double l1 = lengths[topology.face_edges(f, 1)];
        const Complex corner2 = r > 0 && std::isfinite(r)
                                    ? Complex{l1 * (z.real() / r), l1 * (z.imag() / r)}
                                    : std::polar(l1, std::arg(z));
        q[f] = {Complex{0}, Complex{lengths[topology.face_edges(f, 2)]}, corner2};
      },
      parallel::kDefaultMinChunk / 4);
  return layout_from_triangles(topology, lengths, q, cut, cut_mesh, options, ahead);
}

}  // namespace

Layout layout_flat(const Topology& topology, const FaceShapes& shapes, const CutGraph& cut,
                   const CutMesh& cut_mesh, const LayoutOptions& options) {
  return layout_flat_from_shapes(topology, shapes, cut, cut_mesh, options, nullptr);
}

Layout layout_support::layout_flat_with_roots(const Topology& topology, const FaceShapes& shapes,
                                              const CutGraph& cut, const CutMesh& cut_mesh,
                                              const LayoutOptions& options, const Roots& roots) {
  return layout_flat_from_shapes(topology, shapes, cut, cut_mesh, options, &roots);
}

}  // namespace ricci
