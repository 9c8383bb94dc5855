#include "ricci/intrinsic/delaunay_flips.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <utility>
#include <vector>

#include "numerics/detail/parallel.hpp"
#include "ricci/errors.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/metric/hyperbolic.hpp"

namespace ricci {
namespace {

/// An isometric flip's new diagonal shorter than this fraction of the quad's longest side joins
/// two corners that nearly coincide (see flip_to_delaunay). The corners are rounded at about
/// 1e-16 of the quad's size, so a diagonal of 1e-9 of it still has its direction to about seven
/// digits.
constexpr double kShortestDiagonal = 1e-9;

/// The quad of interior edge e: halfedge h0 = a -> b in face f0 with opposite corner c, its twin
/// h1 = b -> a in face f1 with opposite corner d.
struct EdgeQuad {
  int h0, h1, a, b, c, d;
  int ca, cb, da, db;  // edges of the four outer sides
};

EdgeQuad quad_of(const Topology& t, int e) {
  EdgeQuad q;
  q.h0 = t.edge_halfedges(e, 0);
  q.h1 = t.edge_halfedges(e, 1);
  const int f0 = q.h0 / 3, k0 = q.h0 % 3, f1 = q.h1 / 3, k1 = q.h1 % 3;
  q.a = t.tail(q.h0);
  q.b = t.head(q.h0);
  q.c = t.triangles(f0, k0);
  q.d = t.triangles(f1, k1);
  // In face f0 the side opposite a (corner k0 + 1) is bc, the side opposite b is ca; in f1 the
  // side opposite b (corner k1 + 1) is ad, the side opposite a is db.
  q.cb = t.face_edges(f0, (k0 + 1) % 3);
  q.ca = t.face_edges(f0, (k0 + 2) % 3);
  q.da = t.face_edges(f1, (k1 + 1) % 3);
  q.db = t.face_edges(f1, (k1 + 2) % 3);
  return q;
}

/// (x^2 + y^2 - z^2) / (x y), arranged so that large lengths do not overflow.
double cosine_term(double z, double x, double y) {
  return x / y + y / x - (z / x) * (z / y);
}

/// Whether vertices c and d are joined by an edge: walks the halfedges around c starting from
/// `start` (which leaves c), both ways when the walk meets the boundary.
bool joined(const Topology& t, int start, int d) {
  int h = start;
  do {
    if (t.head(h) == d) return true;
    const int twin = t.halfedge_twin[h];
    if (twin < 0) break;
    h = Topology::next(twin);
  } while (h != start);
  if (h == start && t.halfedge_twin[h] >= 0) return false;  // went all the way round
  h = start;
  for (;;) {
    const int incoming = Topology::prev(h);
    if (t.tail(incoming) == d) return true;
    const int twin = t.halfedge_twin[incoming];
    if (twin < 0) return false;
    h = twin;
    if (h == start) return false;
  }
}

}  // namespace

double euclidean_diagonal(double ab, double ca, double cb, double da, double db) {
  // The quad unfolded into the plane: a at 0, b on the positive real axis, c above, d below.
  const double angle_c = angle_from_lengths(cb, ca, ab);  // at a in (c, a, b)
  const double angle_d = angle_from_lengths(db, da, ab);  // at a in (d, b, a)
  const std::complex<double> c = std::polar(ca, angle_c), d = std::polar(da, -angle_d);
  return std::abs(c - d);
}

double delaunay_margin(double ab, double ca, double cb, double da, double db) {
  return cosine_term(ab, ca, cb) + cosine_term(ab, da, db);
}

double lambda_length(double length, Geometry geometry) {
  return geometry == Geometry::Hyperbolic ? std::sinh(0.5 * length) : length;
}

double length_from_lambda(double lambda, Geometry geometry) {
  return geometry == Geometry::Hyperbolic ? 2.0 * std::asinh(lambda) : lambda;
}

double ptolemy_diagonal(const QuadLengths& q, Geometry geometry) {
  // Ptolemy's relation for the decorated quad a, d, b, c, on the lambda lengths.
  auto lambda = [&](double length) { return lambda_length(length, geometry); };
  return length_from_lambda(
      (lambda(q.ca) * lambda(q.db) + lambda(q.da) * lambda(q.cb)) / lambda(q.ab), geometry);
}

double isometric_diagonal(const QuadLengths& q, Geometry geometry) {
  return geometry == Geometry::Hyperbolic ? hyperbolic_diagonal(q.ab, q.ca, q.cb, q.da, q.db)
                                          : euclidean_diagonal(q.ab, q.ca, q.cb, q.da, q.db);
}

double hyperbolic_delaunay_margin(double ab, double ca, double cb, double da, double db) {
  const auto s = [](double l) { return std::sinh(0.5 * l); };
  return delaunay_margin(s(ab), s(ca), s(cb), s(da), s(db));
}

double hyperbolic_diagonal(double ab, double ca, double cb, double da, double db) {
  // The angle of the quad at a: the angles at a of (c, a, b) and (d, b, a).
  const double alpha =
      hyperbolic_angle_from_lengths(cb, ca, ab) + hyperbolic_angle_from_lengths(db, da, ab);
  // cosh cd = cosh ca cosh da - sinh ca sinh da cos alpha, minus cosh(ca - da), with
  // cosh x - 1 = 2 sinh^2(x / 2) and 1 - cos alpha = 2 sin^2(alpha / 2).
  const double h = std::sinh(0.5 * (ca - da)), s = std::sin(0.5 * alpha);
  return 2.0 * std::asinh(std::sqrt(h * h + std::sinh(ca) * std::sinh(da) * s * s));
}

bool can_flip_edge(const Topology& t, int e, bool keep_simplicial) {
  if (t.edge_halfedges(e, 1) < 0) return false;
  const EdgeQuad q = quad_of(t, e);
  if (q.h0 / 3 == q.h1 / 3) return false;  // an edge inside one self-glued face
  if (!keep_simplicial) return true;
  if (q.c == q.d) return false;
  // The halfedge c -> a of face f0 leaves c.
  const int leaving_c = 3 * (q.h0 / 3) + (q.h0 % 3 + 2) % 3;
  return !joined(t, leaving_c, q.d);
}

void flip_edge(Topology& t, int e) {
  const EdgeQuad q = quad_of(t, e);
  const int f0 = q.h0 / 3, k0 = q.h0 % 3, f1 = q.h1 / 3, k1 = q.h1 % 3;
  // The four outer halfedges c->a, a->d, d->b, b->c and the slots they move to: the new faces
  // are (a, d, c) with corner a at k0 and (b, c, d) with corner b at k1, so that h0 and h1
  // (opposite corners k0 and k1) become the diagonal d -> c and c -> d.
  const int from[4] = {3 * f0 + (k0 + 2) % 3, 3 * f1 + (k1 + 1) % 3, 3 * f1 + (k1 + 2) % 3,
                       3 * f0 + (k0 + 1) % 3};
  const int to[4] = {3 * f0 + (k0 + 1) % 3, 3 * f0 + (k0 + 2) % 3, 3 * f1 + (k1 + 1) % 3,
                     3 * f1 + (k1 + 2) % 3};
  // In a triangulation with multi-edges and loops two outer halfedges can be twins, or halves of
  // one edge, so every stored halfedge index goes through this map.
  auto moved = [&](int g) {
    for (int j = 0; j < 4; ++j) {
      if (g == from[j]) return to[j];
    }
    return g;
  };
  int edge[4], twin[4], halves[4][2];
  for (int i = 0; i < 4; ++i) {
    edge[i] = t.halfedge_edge[from[i]];
    twin[i] = t.halfedge_twin[from[i]];
    halves[i][0] = t.edge_halfedges(edge[i], 0);
    halves[i][1] = t.edge_halfedges(edge[i], 1);
  }
  t.triangles(f0, k0) = q.a;
  t.triangles(f0, (k0 + 1) % 3) = q.d;
  t.triangles(f0, (k0 + 2) % 3) = q.c;
  t.triangles(f1, k1) = q.b;
  t.triangles(f1, (k1 + 1) % 3) = q.c;
  t.triangles(f1, (k1 + 2) % 3) = q.d;
  for (int i = 0; i < 4; ++i) {
    const int h = to[i];
    t.halfedge_edge[h] = edge[i];
    t.face_edges(h / 3, h % 3) = edge[i];
    t.halfedge_twin[h] = twin[i] < 0 ? -1 : moved(twin[i]);
    if (twin[i] >= 0) t.halfedge_twin[moved(twin[i])] = h;
    t.edge_halfedges(edge[i], 0) = halves[i][0] < 0 ? -1 : moved(halves[i][0]);
    t.edge_halfedges(edge[i], 1) = halves[i][1] < 0 ? -1 : moved(halves[i][1]);
  }
  t.edge_vertices(e, 0) = std::min(q.c, q.d);
  t.edge_vertices(e, 1) = std::max(q.c, q.d);
  --t.vertex_degree[q.a];
  --t.vertex_degree[q.b];
  ++t.vertex_degree[q.c];
  ++t.vertex_degree[q.d];
}

bool is_simplicial(const Topology& t) {
  for (int f = 0; f < t.num_faces; ++f) {
    const int a = t.triangles(f, 0), b = t.triangles(f, 1), c = t.triangles(f, 2);
    if (a == b || b == c || c == a) return false;
  }
  std::vector<std::pair<int, int>> pairs(static_cast<std::size_t>(t.num_edges));
  for (int e = 0; e < t.num_edges; ++e) pairs[e] = {t.edge_vertices(e, 0), t.edge_vertices(e, 1)};
  std::sort(pairs.begin(), pairs.end());
  return std::adjacent_find(pairs.begin(), pairs.end()) == pairs.end();
}

namespace {

/// Flips edge e of quad q to the new length cd, with the eta that makes edge_lengths reproduce
/// it: lambda_cd^2 = 2 eta exp(u_c + u_d) in both backgrounds (vertex scaling, epsilon = 0).
void set_flipped_edge(Topology& t, ConformalStructure& structure, const Eigen::VectorXd& u,
                      Eigen::VectorXd& l, int e, const EdgeQuad& q, double cd) {
  flip_edge(t, e);
  l[e] = cd;
  const double lambda = lambda_length(cd, structure.geometry);
  structure.eta[e] = 0.5 * std::exp(2.0 * std::log(lambda) - u[q.c] - u[q.d]);
}

/// The Delaunay margin of the quad's edge ab in the given background (the flips' one test of the
/// background besides the lambda lengths and the isometric diagonal).
double margin_in(Geometry geometry, const QuadLengths& q) {
  return geometry == Geometry::Hyperbolic ? hyperbolic_delaunay_margin(q.ab, q.ca, q.cb, q.da, q.db)
                                          : delaunay_margin(q.ab, q.ca, q.cb, q.da, q.db);
}

/// An interior edge whose Delaunay margin is below -tolerance (the test of every edge at every
/// trial point: quad_lengths reads only the four sides' edges, no vertex look-ups).
bool is_non_delaunay(const Topology& t, const Eigen::VectorXd& l, int e, double tolerance,
                     Geometry geometry) {
  if (t.edge_halfedges(e, 1) < 0) return false;
  return margin_in(geometry, quad_lengths(t, l, t.edge_halfedges(e, 0))) < -tolerance;
}

}  // namespace

double ptolemy_flip(Topology& t, ConformalStructure& structure, const Eigen::VectorXd& u,
                    Eigen::VectorXd& l, int e) {
  const EdgeQuad q = quad_of(t, e);
  const double cd = ptolemy_diagonal(quad_lengths(t, l, q.h0), structure.geometry);
  set_flipped_edge(t, structure, u, l, e, q, cd);
  return cd;
}

int count_non_delaunay_edges(const Topology& t, const Eigen::VectorXd& l, double tolerance,
                             Geometry geometry) {
  return static_cast<int>(parallel::count_if(t.num_edges, [&](std::int64_t e) {
    return is_non_delaunay(t, l, static_cast<int>(e), tolerance, geometry);
  }));
}

DelaunayFlipResult flip_to_delaunay(Topology& t, ConformalStructure& structure,
                                    const Eigen::VectorXd& u, Eigen::VectorXd& l,
                                    const DelaunayFlipOptions& options) {
  if (!scheme_traits(structure.scheme).ptolemy_flips) {
    throw InvalidInput(
        "flip_to_delaunay: Ptolemy flips keep the conformal class of vertex scaling only; this "
        "structure is " +
        std::string(scheme_name(structure.scheme)));
  }
  const Geometry geometry = structure.geometry;
  DelaunayFlipResult result;
  const int max_flips = options.max_flips > 0 ? options.max_flips : 50 * t.num_edges;
  // Which edges fail the test at the start, in parallel. An edge whose quad no flip has touched
  // since (`touched`: the flipped edge and the four sides of its quad) fails exactly when it
  // failed then, so the sequential pass below tests only those; it makes the same flips in the
  // same order as testing every edge would. Without a failing edge there is nothing to do.
  std::vector<char> failing(static_cast<std::size_t>(t.num_edges), 0);
  const std::int64_t initially_failing = parallel::count_if(t.num_edges, [&](std::int64_t e) {
    failing[e] = is_non_delaunay(t, l, static_cast<int>(e), options.tolerance, geometry);
    return failing[e] != 0;
  });
  if (initially_failing == 0) return result;
  std::vector<char> touched(static_cast<std::size_t>(t.num_edges), 0);
  // A stack of edges to check, lowest index on top; an edge re-enters when a flip changes its
  // quad.
  std::vector<int> stack;
  std::vector<char> queued(t.num_edges, 0);
  for (int e = t.num_edges - 1; e >= 0; --e) {
    if (t.edge_halfedges(e, 1) < 0) continue;
    stack.push_back(e);
    queued[e] = 1;
  }
  while (!stack.empty()) {
    const int e = stack.back();
    stack.pop_back();
    queued[e] = 0;
    if (!touched[e] && !failing[e]) continue;
    const EdgeQuad q = quad_of(t, e);
    const QuadLengths lengths = quad_lengths(t, l, q.h0);
    if (!(margin_in(geometry, lengths) < -options.tolerance)) continue;
    if (!can_flip_edge(t, e, options.keep_simplicial)) {
      ++result.blocked;
      continue;
    }
    if (result.flips >= max_flips) {
      result.complete = false;
      break;
    }
    if (options.isometric) {
      const double cd = isometric_diagonal(lengths, geometry);
      // A diagonal of almost no length joins two corners that nearly coincide: a loop around a
      // needle (the doubled Stanford dragon folds its 0.04-degree boundary ears onto
      // themselves). Its direction is lost to rounding, and with it the relative position of
      // its two faces, so it is not made: the edge stays, counted as blocked.
      if (!(cd > kShortestDiagonal * std::max({lengths.ca, lengths.cb, lengths.da, lengths.db}))) {
        ++result.blocked;
        continue;
      }
      set_flipped_edge(t, structure, u, l, e, q, cd);
    } else {
      ptolemy_flip(t, structure, u, l, e);
    }
    ++result.flips;
    result.flipped_edges.push_back(e);
    touched[e] = 1;
    for (int side : {q.ca, q.cb, q.da, q.db}) touched[side] = 1;
    for (int side : {q.ca, q.cb, q.da, q.db}) {
      if (!queued[side] && t.edge_halfedges(side, 1) >= 0) {
        stack.push_back(side);
        queued[side] = 1;
      }
    }
  }
  // Blocked edges were counted each time they were visited; report those still not Delaunay.
  if (result.blocked > 0) {
    result.blocked = count_non_delaunay_edges(t, l, options.tolerance, geometry);
  }
  return result;
}

}  // namespace ricci
