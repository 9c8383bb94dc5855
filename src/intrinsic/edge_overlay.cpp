#include "ricci/intrinsic/edge_overlay.hpp"

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <string>
#include <tuple>

#include "ricci/errors.hpp"
#include "ricci/intrinsic/delaunay_flips.hpp"

namespace ricci {
namespace {

/// The arcs of a face from its side counts: cut[j] arcs cut corner j (they join the two sides at
/// j), and `emanating` arcs leave corner `emanating_corner` for the opposite side.
struct FaceCounts {
  int n[3] = {0, 0, 0};
  int cut[3] = {0, 0, 0};
  int emanating_corner = -1;
  int emanating = 0;
};

int side_size(const Topology& t, const EdgeOverlay& o, int h) {
  return static_cast<int>(o.crossings[t.halfedge_edge[h]].size());
}

/// Position i along halfedge h as an index into its edge's list.
int stored_index(const Topology& t, const EdgeOverlay& o, int h, int i) {
  const int e = t.halfedge_edge[h];
  return h == t.edge_halfedges(e, 0) ? i : static_cast<int>(o.crossings[e].size()) - 1 - i;
}

/// The crossing at position i along halfedge h, signed relative to the face of h: +(c + 1) when
/// curve c enters that face there.
int entry_along(const Topology& t, const EdgeOverlay& o, int h, int i) {
  const int e = t.halfedge_edge[h];
  const int stored = o.crossings[e][stored_index(t, o, h, i)];
  return h == t.edge_halfedges(e, 0) ? stored : -stored;
}

FaceCounts face_counts(const Topology& t, const EdgeOverlay& o, int f) {
  FaceCounts fc;
  for (int k = 0; k < 3; ++k) fc.n[k] = side_size(t, o, 3 * f + k);
  for (int k = 0; k < 3; ++k) {
    const int a = fc.n[(k + 1) % 3], b = fc.n[(k + 2) % 3];
    if (fc.n[k] > a + b) {
      fc.emanating_corner = k;
      fc.emanating = fc.n[k] - a - b;
      fc.cut[(k + 1) % 3] = b;
      fc.cut[(k + 2) % 3] = a;
      return fc;
    }
  }
  if ((fc.n[0] + fc.n[1] + fc.n[2]) % 2 != 0) {
    throw SolverError("edge overlay: face " + std::to_string(f) + " has crossing counts " +
                      std::to_string(fc.n[0]) + ", " + std::to_string(fc.n[1]) + ", " +
                      std::to_string(fc.n[2]) + ", which no set of disjoint arcs has");
  }
  for (int j = 0; j < 3; ++j) fc.cut[j] = (fc.n[(j + 1) % 3] + fc.n[(j + 2) % 3] - fc.n[j]) / 2;
  return fc;
}

/// The other end of the arc through position i of side s. Side s runs from corner s+1 to corner
/// s+2: its first cut[s+1] crossings cut corner s+1, its last cut[s+2] cut corner s+2, the ones
/// between come from corner s.
ArcEnd other_end(const FaceCounts& fc, int s, int i) {
  const int s1 = (s + 1) % 3, s2 = (s + 2) % 3;
  if (i < fc.cut[s1]) return {s2, fc.n[s2] - 1 - i, -1};
  if (i >= fc.n[s] - fc.cut[s2]) return {s1, fc.n[s] - 1 - i, -1};
  return {-1, -1, s};
}

int curve_of(int entry) {
  return std::abs(entry) - 1;
}

}  // namespace

EdgeOverlay identity_overlay(const Topology& host) {
  EdgeOverlay o;
  o.num_curves = host.num_edges;
  o.crossings.assign(static_cast<std::size_t>(host.num_edges), {});
  o.coincident.resize(static_cast<std::size_t>(host.num_edges));
  for (int e = 0; e < host.num_edges; ++e) o.coincident[e] = e + 1;
  return o;
}

std::vector<FaceArc> face_arcs(const Topology& t, const EdgeOverlay& o, int f) {
  const FaceCounts fc = face_counts(t, o, f);
  std::vector<FaceArc> arcs;
  auto oriented = [&](ArcEnd x, ArcEnd y) {
    // x is a side end; y a side end or a corner. The curve enters the face where its entry is
    // positive.
    const int ex = entry_along(t, o, 3 * f + x.side, x.index);
    FaceArc arc;
    arc.curve = curve_of(ex);
    if (!y.is_corner()) {
      const int ey = entry_along(t, o, 3 * f + y.side, y.index);
      if (curve_of(ey) != arc.curve || (ex > 0) == (ey > 0)) {
        throw SolverError("edge overlay: the arc of face " + std::to_string(f) + " joining sides " +
                          std::to_string(x.side) + " and " + std::to_string(y.side) +
                          " has inconsistent labels");
      }
    }
    arc.from = ex > 0 ? x : y;
    arc.to = ex > 0 ? y : x;
    arcs.push_back(arc);
  };
  for (int j = 0; j < 3; ++j) {
    const int sa = (j + 2) % 3, sb = (j + 1) % 3;
    for (int i = 0; i < fc.cut[j]; ++i) oriented({sa, i, -1}, {sb, fc.n[sb] - 1 - i, -1});
  }
  if (fc.emanating_corner >= 0) {
    const int k = fc.emanating_corner;
    const int first = fc.cut[(k + 1) % 3];
    for (int i = 0; i < fc.emanating; ++i) oriented({k, first + i, -1}, {-1, -1, k});
  }
  return arcs;
}

void flip_edge_with_overlay(Topology& t, EdgeOverlay& o, int e) {
  if (e < 0 || e >= t.num_edges || !can_flip_edge(t, e)) {
    throw InvalidInput("flip_edge_with_overlay: edge " + std::to_string(e) +
                       " does not exist or cannot be flipped");
  }
  const int h0 = t.edge_halfedges(e, 0), h1 = t.edge_halfedges(e, 1);
  const int f0 = h0 / 3, k0 = h0 % 3, f1 = h1 / 3, k1 = h1 % 3;
  // Face f0 is (c, a, b) from corner k0 and f1 is (d, b, a) from corner k1; h0 runs a -> b. The
  // quad's boundary, counter-clockwise from c: c -> a (f0), a -> d (f1), d -> b (f1), b -> c (f0).
  const int side_ca = (k0 + 2) % 3, side_bc = (k0 + 1) % 3;
  const int side_ad = (k1 + 1) % 3, side_db = (k1 + 2) % 3;
  const int n_ca = side_size(t, o, 3 * f0 + side_ca), n_bc = side_size(t, o, 3 * f0 + side_bc);
  const int n_ad = side_size(t, o, 3 * f1 + side_ad), n_db = side_size(t, o, 3 * f1 + side_db);
  const int m = static_cast<int>(o.crossings[e].size());
  const int pos_c = 0, pos_a = n_ca + 1, pos_d = pos_a + n_ad + 1, pos_b = pos_d + n_db + 1;
  const int num_positions = pos_b + n_bc + 1;

  // Quad positions are >= 0; a crossing of the diagonal at index i along a -> b is -1 - i.
  auto map0 = [&](ArcEnd x) {
    if (x.is_corner()) return x.corner == k0 ? pos_c : x.corner == (k0 + 1) % 3 ? pos_a : pos_b;
    if (x.side == k0) return -1 - x.index;
    return x.side == side_ca ? pos_c + 1 + x.index : pos_b + 1 + x.index;
  };
  auto map1 = [&](ArcEnd x) {
    if (x.is_corner()) return x.corner == k1 ? pos_d : x.corner == (k1 + 1) % 3 ? pos_b : pos_a;
    if (x.side == k1) return -1 - (m - 1 - x.index);
    return x.side == side_ad ? pos_a + 1 + x.index : pos_d + 1 + x.index;
  };
  struct QuadArc {
    int curve, from, to;
  };
  std::vector<QuadArc> quad_arcs;
  std::vector<QuadArc> arrive(static_cast<std::size_t>(m), {-1, 0, 0});
  std::vector<QuadArc> depart(static_cast<std::size_t>(m), {-1, 0, 0});
  auto collect = [&](const std::vector<FaceArc>& arcs, auto map) {
    for (const FaceArc& arc : arcs) {
      const int from = map(arc.from), to = map(arc.to);
      if (from < 0 && to < 0) {
        throw SolverError("flip_edge_with_overlay: an arc returns to the diagonal of edge " +
                          std::to_string(e));
      }
      if (to < 0) {
        arrive[-1 - to] = {arc.curve, from, 0};
      } else if (from < 0) {
        depart[-1 - from] = {arc.curve, 0, to};
      } else {
        quad_arcs.push_back({arc.curve, from, to});
      }
    }
  };
  collect(face_arcs(t, o, f0), map0);
  collect(face_arcs(t, o, f1), map1);
  for (int i = 0; i < m; ++i) {
    if (arrive[i].curve < 0 || arrive[i].curve != depart[i].curve) {
      throw SolverError("flip_edge_with_overlay: the crossings of edge " + std::to_string(e) +
                        " do not join the arcs of its two faces");
    }
    quad_arcs.push_back({arrive[i].curve, arrive[i].from, depart[i].to});
  }
  if (o.coincident[e] != 0) {
    const int c = curve_of(o.coincident[e]);
    quad_arcs.push_back(o.coincident[e] > 0 ? QuadArc{c, pos_a, pos_b} : QuadArc{c, pos_b, pos_a});
  }

  // The new diagonal runs from c to d; it crosses the arcs with one end on each of its sides.
  // Disjoint arcs separating c from d cross it in the order of their ends on the side through a
  // (nearest c first), ties at corner a broken by the ends on the side through b.
  auto on_a_side = [&](int p) { return p > pos_c && p < pos_d; };
  auto on_b_side = [&](int p) { return p > pos_d && p < num_positions; };
  struct NewCrossing {
    int key_a, key_b, entry;
  };
  std::vector<NewCrossing> crossings;
  int coincident = 0;
  for (const QuadArc& q : quad_arcs) {
    const bool ends_cd = (q.from == pos_c && q.to == pos_d) || (q.from == pos_d && q.to == pos_c);
    if (ends_cd) {
      // The new edge's halfedge 0 runs d -> c.
      coincident = q.from == pos_d ? q.curve + 1 : -(q.curve + 1);
    } else if (on_a_side(q.from) && on_b_side(q.to)) {
      // From the side of face (a, d, c), which is the face of the new halfedge 0, to the other.
      crossings.push_back({q.from, q.to, -(q.curve + 1)});
    } else if (on_b_side(q.from) && on_a_side(q.to)) {
      crossings.push_back({q.to, q.from, q.curve + 1});
    }
  }
  std::sort(crossings.begin(), crossings.end(), [](const NewCrossing& x, const NewCrossing& y) {
    return std::tie(x.key_a, y.key_b) < std::tie(y.key_a, x.key_b);
  });
  flip_edge(t, e);
  std::vector<int>& list = o.crossings[e];
  list.clear();
  // Stored from the tail of halfedge 0 (d) to its head (c): the reverse of the order from c.
  for (auto it = crossings.rbegin(); it != crossings.rend(); ++it) list.push_back(it->entry);
  o.coincident[e] = coincident;
}

std::vector<CurvePath> trace_curves(const Topology& t, const EdgeOverlay& o) {
  std::vector<CurvePath> paths(static_cast<std::size_t>(o.num_curves));
  for (int e = 0; e < t.num_edges; ++e) {
    if (o.coincident[e] == 0) continue;
    const int h = o.coincident[e] > 0 ? t.edge_halfedges(e, 0) : t.edge_halfedges(e, 1);
    if (h < 0) {
      throw SolverError("trace_curves: curve " + std::to_string(curve_of(o.coincident[e])) +
                        " runs against a boundary edge");
    }
    paths[curve_of(o.coincident[e])].coincident_halfedge = h;
  }
  std::vector<std::pair<int, int>> first(static_cast<std::size_t>(o.num_curves), {-1, -1});
  long total = 0;
  for (int e = 0; e < t.num_edges; ++e) {
    for (int j = 0; j < static_cast<int>(o.crossings[e].size()); ++j) {
      auto& f = first[curve_of(o.crossings[e][j])];
      if (f.first < 0) f = {e, j};
      ++total;
    }
  }
  auto fail = [](int c, const char* why) {
    throw SolverError("trace_curves: curve " + std::to_string(c) + " " + why);
  };
  for (int c = 0; c < o.num_curves; ++c) {
    CurvePath& path = paths[c];
    if (first[c].first < 0) {
      if (path.coincident_halfedge < 0) fail(c, "is neither an edge nor crosses any");
      continue;
    }
    // halfedge_pair(e, j): the halfedges the curve leaves and enters through at crossing j.
    auto enter_leave = [&](int e, int j) {
      const bool enters_h0 = o.crossings[e][j] > 0;
      const int a = t.edge_halfedges(e, 0), b = t.edge_halfedges(e, 1);
      return std::pair<int, int>{enters_h0 ? a : b, enters_h0 ? b : a};
    };
    auto position = [&](int h, int j) { return stored_index(t, o, h, j); };  // an involution
    long steps = 0;
    // From the first crossing to the corner the curve leaves (backward) or arrives at (forward),
    // appending the crossings passed on the way to `crossings`, each with the halfedge the curve
    // crosses it from; the corner as {face, corner}.
    auto walk = [&](bool forward, std::vector<CurveCrossing>& crossings) {
      int e = first[c].first, j = first[c].second;
      for (;;) {
        const auto [enter, leave] = enter_leave(e, j);
        const int h = forward ? enter : leave;
        if (h < 0) fail(c, "crosses a boundary edge");
        const int f = h / 3;
        const ArcEnd x = other_end(face_counts(t, o, f), h % 3, position(h, j));
        if (x.is_corner()) return std::pair<int, int>{f, x.corner};
        const int h2 = 3 * f + x.side;
        const int e2 = t.halfedge_edge[h2], j2 = stored_index(t, o, h2, x.index);
        const int along = entry_along(t, o, h2, x.index);
        if (curve_of(o.crossings[e2][j2]) != c || (forward ? along > 0 : along < 0)) {
          fail(c, forward ? "cannot be followed forward" : "cannot be followed backward");
        }
        crossings.push_back({e2, j2, forward ? h2 : t.halfedge_twin[h2]});
        e = e2;
        j = j2;
        if (++steps > total) fail(c, "loops");
      }
    };
    std::vector<CurveCrossing> backward, forward;
    std::tie(path.start_face, path.start_corner) = walk(false, backward);
    forward.push_back(
        {first[c].first, first[c].second, enter_leave(first[c].first, first[c].second).second});
    std::tie(path.end_face, path.end_corner) = walk(true, forward);
    path.crossings.assign(backward.rbegin(), backward.rend());
    path.crossings.insert(path.crossings.end(), forward.begin(), forward.end());
  }
  return paths;
}

EdgeOverlay transpose_overlay(const Topology& host, const EdgeOverlay& overlay,
                              const std::vector<CurvePath>& paths, const Topology& start) {
  EdgeOverlay result;
  result.num_curves = host.num_edges;
  result.crossings.assign(static_cast<std::size_t>(start.num_edges), {});
  result.coincident.assign(static_cast<std::size_t>(start.num_edges), 0);
  for (int c = 0; c < start.num_edges && c < static_cast<int>(paths.size()); ++c) {
    for (const CurveCrossing& x : paths[c].crossings) {
      // Curve c crosses host edge x.edge from the face of x.halfedge into its twin's: into the
      // face of the host edge's halfedge 0 exactly when x.halfedge is its halfedge 1, i.e. from
      // the host edge's right to its left. Seen from c the host edge then crosses from c's left
      // to its right.
      const bool host_crossed_right_to_left = x.halfedge == host.edge_halfedges(x.edge, 1);
      result.crossings[c].push_back(host_crossed_right_to_left ? -(x.edge + 1) : x.edge + 1);
    }
  }
  for (int e = 0; e < host.num_edges; ++e) {
    if (overlay.coincident[e] == 0) continue;
    const int c = curve_of(overlay.coincident[e]);
    result.coincident[c] = overlay.coincident[e] > 0 ? e + 1 : -(e + 1);
  }
  return result;
}

}  // namespace ricci
