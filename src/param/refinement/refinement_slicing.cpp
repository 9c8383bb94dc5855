// Slicing one Delaunay triangle along the input edges and the final edges that cross it: both
// are straight chords there (the input's in the flat metric, the final ones in the triangle's
// Klein model), so the cells are convex and the whole arrangement follows from the order of the
// chords' ends around the triangle.
#include <algorithm>
#include <array>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Geometry>

#include "param/refinement/detail/refinement_support.hpp"

namespace ricci::refinement_support {
namespace {

/// Below this |sum| the lines of two chords meet at infinity (parallel, which crossing chords are
/// only up to rounding) and their intersection is left unnormalised rather than divided by
/// (almost) zero; the value only guards that division, far below the sum of any real crossing.
constexpr double kParallelChords = 1e-300;

/// A point on the boundary of the Delaunay face: a corner, or a crossing of one of its sides.
struct Port {
  int vertex = -1;
  int corner = -1;  // 0..2 for a corner
  int side = -1, pos = -1;
  bool is_b = false;
  int e1 = -1, entry = -1;  // T1 edge and index in its A or B list
  Vec3 bary = Vec3::Zero();
};

/// A piece of an input edge (is_b false) or a final edge inside the face, oriented as its curve
/// runs.
struct Chord {
  bool is_b;
  int curve, p, q;
  std::vector<int> points;  // interior points from p to q
};

/// Where an input chord (alpha) crosses a final chord (beta).
struct Interior {
  int alpha, beta;
  double lambda_a = 0, lambda_b = 0;
  int vertex = -1;
  Vec3 bary = Vec3::Zero();
};

enum Kind { Boundary, InputChord, FinalChord };

/// A half-edge of the planar graph the chords cut the face into.
struct HalfEdge {
  int from, to, twin = -1;
  Kind kind;
  int index;     // side (Boundary) or chord
  bool forward;  // Boundary: counter-clockwise; chords: as the curve runs
  int edge_id;
};

/// A face of the planar graph (left of its half-edges) and the input and final faces holding it.
struct Cell {
  std::vector<int> half_edges;
  int input_face = -1, final_face = -1;
};

/// Everything the slicing of Delaunay face t builds, step by step.
struct FaceSlice {
  int t = -1;
  // The boundary: ports counter-clockwise from corner 0, per side the ports of its A and B
  // crossings in the order of the side's halfedge, the corners' ports, each side's edge and
  // whether the side runs along that edge's halfedge 0.
  std::vector<Port> ports;
  std::array<std::vector<int>, 3> a_port, b_port;
  std::array<int, 3> corner_port{};
  std::array<bool, 3> side_forward{};
  std::array<int, 3> side_edge{};
  int np = 0;
  std::vector<Chord> chords;  // the input chords, then the final ones
  int num_a = 0, num_chords = 0;
  std::vector<Interior> interior;
  // The planar graph: ports, then interior points; half-edges with their rotation
  // (counter-clockwise order of the half-edges leaving each vertex).
  std::vector<HalfEdge> he;
  std::vector<std::vector<int>> rotation;
  std::vector<int> rot_index;  // per half-edge, its place in its tail's rotation
  std::vector<Cell> cells;
  std::vector<int> cell_of;  // per half-edge

  /// Steps from port a to port b counter-clockwise around the boundary.
  int dist(int a, int b) const { return ((b - a) % np + np) % np; }
  /// Whether port x lies strictly inside the boundary arc from p counter-clockwise to q.
  bool inside(int x, int p, int q) const {
    const int d = dist(p, x);
    return d > 0 && d < dist(p, q);
  }
};

/// The ports of face s.t: per corner, the corner and then the crossings of the side after it.
void collect_ports(const Context& c, FaceSlice& s) {
  const Topology& t1 = c.t1;
  const int t = s.t;
  for (int j = 0; j < 3; ++j) {
    s.corner_port[j] = static_cast<int>(s.ports.size());
    Port pc;
    pc.vertex = t1.triangles(t, j);
    pc.corner = j;
    pc.bary = Vec3::Unit(j);
    s.ports.push_back(pc);
    const int side = (j + 2) % 3, h = 3 * t + side, e1 = t1.halfedge_edge[h];
    const bool forward = h == t1.edge_halfedges(e1, 0);
    s.side_forward[side] = forward;
    s.side_edge[side] = e1;
    const auto& list = c.ports[e1];
    const int n = static_cast<int>(list.size());
    const int na = static_cast<int>(c.o01.crossings[e1].size());
    const int nb = static_cast<int>(c.oT.crossings[e1].size());
    s.a_port[side].assign(static_cast<std::size_t>(na), -1);
    s.b_port[side].assign(static_cast<std::size_t>(nb), -1);
    for (int i = 0; i < n; ++i) {
      const auto [is_b, entry] = list[forward ? i : n - 1 - i];
      Port p;
      p.side = side;
      p.pos = i;
      p.is_b = is_b;
      p.e1 = e1;
      p.entry = entry;
      const double stored = is_b ? c.b_s[e1][entry] : c.a_s[e1][entry];
      const double sigma = forward ? stored : 1 - stored;
      p.bary[(side + 1) % 3] = 1 - sigma;
      p.bary[(side + 2) % 3] = sigma;
      p.vertex = is_b ? c.b_vertex[e1][entry] : c.a_vertex[e1][entry];
      const int along = forward ? entry : (is_b ? nb : na) - 1 - entry;
      (is_b ? s.b_port : s.a_port)[side][along] = static_cast<int>(s.ports.size());
      s.ports.push_back(p);
    }
  }
  s.np = static_cast<int>(s.ports.size());
}

/// The chords: the input edges' arcs in the face, then the final edges'.
void collect_chords(const Context& c, FaceSlice& s) {
  auto port_of = [&](const ArcEnd& x, bool is_b) {
    return x.is_corner() ? s.corner_port[x.corner] : (is_b ? s.b_port : s.a_port)[x.side][x.index];
  };
  for (const FaceArc& arc : face_arcs(c.t1, c.o01, s.t)) {
    s.chords.push_back({false, arc.curve, port_of(arc.from, false), port_of(arc.to, false), {}});
  }
  s.num_a = static_cast<int>(s.chords.size());
  for (const FaceArc& arc : c.b_arcs[s.t]) {
    s.chords.push_back({true, arc.curve, port_of(arc.from, true), port_of(arc.to, true), {}});
  }
  s.num_chords = static_cast<int>(s.chords.size());
}

/// Crossings of input chords with final chords, from the order of their ends around the face;
/// each chord's points in order along it.
void find_chord_crossings(FaceSlice& s) {
  std::vector<std::vector<std::tuple<int, int, int>>> order(static_cast<std::size_t>(s.num_chords));
  for (int i = 0; i < s.num_a; ++i) {
    for (int j = s.num_a; j < s.num_chords; ++j) {
      const Chord &a = s.chords[i], &b = s.chords[j];
      if (b.p == a.p || b.p == a.q || b.q == a.p || b.q == a.q) continue;
      const bool in_p = s.inside(b.p, a.p, a.q);
      if (in_p == s.inside(b.q, a.p, a.q)) continue;
      const int index = static_cast<int>(s.interior.size());
      s.interior.push_back({i, j});
      // Along a chord, crossing chords that are disjoint come in the order of their ends on
      // the arc from its start (nearest first), ties at a corner by their other ends.
      const int xa = in_p ? b.p : b.q, ya = in_p ? b.q : b.p;
      order[i].push_back({s.dist(a.p, xa), s.dist(ya, a.p), index});
      const bool a_in = s.inside(a.p, b.p, b.q);
      const int xb = a_in ? a.p : a.q, yb = a_in ? a.q : a.p;
      order[j].push_back({s.dist(b.p, xb), s.dist(yb, b.p), index});
    }
  }
  for (int i = 0; i < s.num_chords; ++i) {
    std::sort(order[i].begin(), order[i].end());
    for (const auto& o : order[i]) s.chords[i].points.push_back(std::get<2>(o));
  }
}

/// Where the chords meet: lines through barycentric points, by cross products; the fractions
/// along both chords, then repaired into the order along each chord.
void intersect_chords(FaceSlice& s, CommonRefinement& result) {
  for (Interior& x : s.interior) {
    const Chord &a = s.chords[x.alpha], &b = s.chords[x.beta];
    const Vec3 &pa = s.ports[a.p].bary, &qa = s.ports[a.q].bary, &pb = s.ports[b.p].bary,
               &qb = s.ports[b.q].bary;
    Vec3 point = pa.cross(qa).cross(pb.cross(qb));
    if (std::abs(point.sum()) > kParallelChords) point /= point.sum();
    auto fraction = [&](const Vec3& p, const Vec3& q) {
      const Vec3 d = q - p;
      const double dd = d.squaredNorm();
      return dd > 0 && point.allFinite() ? std::clamp((point - p).dot(d) / dd, 0.0, 1.0) : 0.5;
    };
    x.lambda_a = fraction(pa, qa);
    x.lambda_b = fraction(pb, qb);
  }
  for (int i = 0; i < s.num_chords; ++i) {
    std::vector<double*> lambdas;
    for (int k : s.chords[i].points) {
      lambdas.push_back(i < s.num_a ? &s.interior[k].lambda_a : &s.interior[k].lambda_b);
    }
    result.order_repairs += repair_order(lambdas);
  }
}

/// The refinement vertices of the chord crossings: rows along the input edge, places on the
/// final edge.
void add_interior_vertices(Context& c, FaceSlice& s) {
  const int nv = c.mesh.num_vertices();
  auto port_tau = [&](int port, bool start) {
    const Port& p = s.ports[port];
    return p.corner >= 0 ? (start ? 0.0 : 1.0) : c.a_tau[p.e1][p.entry];
  };
  auto port_final = [&](int port, int edge, bool start) {
    const Port& p = s.ports[port];
    if (p.corner >= 0) return FinalEdgePoint{edge, start ? 0.0 : 1.0, -c.u[p.vertex]};
    return c.b_final[p.e1][p.entry];
  };
  for (Interior& x : s.interior) {
    const Chord &a = s.chords[x.alpha], &b = s.chords[x.beta];
    const double tau = (1 - x.lambda_a) * port_tau(a.p, true) + x.lambda_a * port_tau(a.q, false);
    const int h = c.t0.edge_halfedges(a.curve, 0);
    x.vertex = c.add_vertex({{c.t0.tail(h), 1 - tau}, {c.t0.head(h), tau}}, a.curve, 2);
    x.bary = (1 - x.lambda_a) * s.ports[a.p].bary + x.lambda_a * s.ports[a.q].bary;
    const FinalEdgePoint f0 = port_final(b.p, b.curve, true), f1 = port_final(b.q, b.curve, false);
    const FinalFacePoint mixed = homogeneous_lerp(Vec3(1 - f0.s, f0.s, 0), f0.log_w,
                                                  Vec3(1 - f1.s, f1.s, 0), f1.log_w, x.lambda_b);
    c.on_final_edge[x.vertex - nv] = {b.curve, mixed.bary[1], mixed.log_w};
  }
}

/// The planar graph's half-edges: the boundary segments (with their ids on the Delaunay edges)
/// and the chords' pieces between their points (new ids).
void add_graph_edges(Context& c, FaceSlice& s, std::vector<int>& boundary_out,
                     std::vector<int>& boundary_back, std::vector<std::vector<int>>& chord_fwd,
                     std::vector<std::vector<int>>& chord_rev) {
  auto add_pair = [&](int a, int b, Kind kind, int index, int edge_id) {
    const int h = static_cast<int>(s.he.size());
    s.he.push_back({a, b, h + 1, kind, index, true, edge_id});
    s.he.push_back({b, a, h, kind, index, false, edge_id});
    return h;
  };
  const int np = s.np;
  boundary_out.assign(static_cast<std::size_t>(np), 0);
  boundary_back.assign(static_cast<std::size_t>(np), 0);
  for (int i = 0; i < np; ++i) {
    const Port& p = s.ports[i];
    const int side = p.corner >= 0 ? (p.corner + 2) % 3 : p.side;
    const int index = p.corner >= 0 ? 0 : p.pos + 1;
    const int e1 = s.side_edge[side];
    const int m = static_cast<int>(c.ports[e1].size());
    const int id = c.segment_offset[e1] + (s.side_forward[side] ? index : m - index);
    const int h = add_pair(i, (i + 1) % np, Boundary, side, id);
    boundary_out[i] = h;
    boundary_back[(i + 1) % np] = h + 1;
  }
  chord_fwd.assign(static_cast<std::size_t>(s.num_chords), {});
  chord_rev.assign(static_cast<std::size_t>(s.num_chords), {});
  for (int i = 0; i < s.num_chords; ++i) {
    std::vector<int> seq{s.chords[i].p};
    for (int k : s.chords[i].points) seq.push_back(np + k);
    seq.push_back(s.chords[i].q);
    for (std::size_t k = 0; k + 1 < seq.size(); ++k) {
      const int h =
          add_pair(seq[k], seq[k + 1], i < s.num_a ? InputChord : FinalChord, i, c.num_edge_ids++);
      chord_fwd[i].push_back(h);
      chord_rev[i].push_back(h + 1);
    }
  }
}

/// The planar graph: its half-edges and the rotation at each of its vertices.
void build_planar_graph(Context& c, FaceSlice& s) {
  const int np = s.np;
  const int nloc = np + static_cast<int>(s.interior.size());
  s.rotation.assign(static_cast<std::size_t>(nloc), {});
  std::vector<int> boundary_out, boundary_back;
  std::vector<std::vector<int>> chord_fwd, chord_rev;
  add_graph_edges(c, s, boundary_out, boundary_back, chord_fwd, chord_rev);
  // Rotations at the ports: forward along the boundary, the chords (at a corner in the order of
  // their far ends along the opposite side), back along the boundary.
  std::vector<std::vector<std::pair<int, int>>> at_port(static_cast<std::size_t>(np));
  for (int i = 0; i < s.num_chords; ++i) {
    const Chord& chord = s.chords[i];
    at_port[chord.p].push_back({s.dist(chord.p, chord.q), chord_fwd[i].front()});
    at_port[chord.q].push_back({s.dist(chord.q, chord.p), chord_rev[i].back()});
  }
  for (int i = 0; i < np; ++i) {
    if (s.ports[i].corner < 0 && at_port[i].size() != 1) {
      internal_error("a crossing on a side of Delaunay face " + std::to_string(s.t) + " ends " +
                     std::to_string(at_port[i].size()) + " arcs");
    }
    std::sort(at_port[i].begin(), at_port[i].end());
    s.rotation[i].push_back(boundary_out[i]);
    for (const auto& [d, h] : at_port[i]) s.rotation[i].push_back(h);
    s.rotation[i].push_back(boundary_back[i]);
  }
  // At an interior point the input chord (start to end) has the arc of the boundary from its
  // start to its end on its right: forward, towards the final chord's end on the left, back,
  // towards the end on the right.
  for (int k = 0; k < static_cast<int>(s.interior.size()); ++k) {
    const Interior& x = s.interior[k];
    const Chord &a = s.chords[x.alpha], &b = s.chords[x.beta];
    const int ra =
        static_cast<int>(std::find(a.points.begin(), a.points.end(), k) - a.points.begin());
    const int rb =
        static_cast<int>(std::find(b.points.begin(), b.points.end(), k) - b.points.begin());
    const bool b_start_right = s.inside(b.p, a.p, a.q);
    const int b_towards_end = chord_fwd[x.beta][rb + 1], b_towards_start = chord_rev[x.beta][rb];
    s.rotation[np + k] = {chord_fwd[x.alpha][ra + 1],
                          b_start_right ? b_towards_end : b_towards_start, chord_rev[x.alpha][ra],
                          b_start_right ? b_towards_start : b_towards_end};
  }
  s.rot_index.assign(s.he.size(), -1);
  for (int v = 0; v < nloc; ++v) {
    for (int r = 0; r < static_cast<int>(s.rotation[v].size()); ++r) {
      s.rot_index[s.rotation[v][r]] = r;
    }
  }
}

/// The half-edge after h around the cell on its left.
int next_in_cell(const FaceSlice& s, int h) {
  const auto& rot = s.rotation[s.he[h].to];
  const int r = s.rot_index[s.he[h].twin];
  return rot[(r + static_cast<int>(rot.size()) - 1) % rot.size()];
}

/// The final corner of the sector just counter-clockwise of rotation entry r at corner port pc.
std::pair<int, int> wedge_after(Context& c, const FaceSlice& s, int pc, int r) {
  const int j = s.ports[pc].corner;
  std::pair<int, int> w = c.start_wedge(s.t, j);
  for (int k = 1; k <= r && k + 1 < static_cast<int>(s.rotation[pc].size()); ++k) {
    const HalfEdge& h = s.he[s.rotation[pc][k]];
    if (h.kind != FinalChord) continue;
    const int ep = s.chords[h.index].curve;
    const int hp = h.forward ? c.tp.edge_halfedges(ep, 0) : c.tp.edge_halfedges(ep, 1);
    w = {hp / 3, (hp % 3 + 1) % 3};
  }
  return w;
}

/// Cells: faces of the planar graph left of the half-edges, the outside excluded.
void trace_cells(FaceSlice& s) {
  std::vector<char> visited(s.he.size(), 0);
  s.cell_of.assign(s.he.size(), -1);
  for (int h0 = 0; h0 < static_cast<int>(s.he.size()); ++h0) {
    if (visited[h0] || (s.he[h0].kind == Boundary && !s.he[h0].forward)) continue;
    Cell cell;
    int h = h0;
    do {
      if (visited[h] || (s.he[h].kind == Boundary && !s.he[h].forward) ||
          cell.half_edges.size() > s.he.size()) {
        internal_error("the cells of Delaunay face " + std::to_string(s.t) + " do not close");
      }
      visited[h] = 1;
      s.cell_of[h] = static_cast<int>(s.cells.size());
      cell.half_edges.push_back(h);
      h = next_in_cell(s, h);
    } while (h != h0);
    s.cells.push_back(std::move(cell));
  }
}

/// The input face on the left of half-edge h, when h lies on an input edge; -1 otherwise.
int input_face_of(const Context& c, const FaceSlice& s, int h) {
  const HalfEdge& x = s.he[h];
  int curve = -1;
  bool same = x.forward;
  if (x.kind == InputChord) {
    curve = s.chords[x.index].curve;
  } else if (x.kind == Boundary) {
    const int e1 = s.side_edge[x.index], co = c.o01.coincident[e1];
    if (co == 0) return -1;
    curve = std::abs(co) - 1;
    same = s.side_forward[x.index] == (co > 0);
  } else {
    return -1;
  }
  const int h0 = c.t0.edge_halfedges(curve, same ? 0 : 1);
  return h0 < 0 ? -1 : h0 / 3;
}

/// The final halfedge under half-edge h (in the final face on its left), when h lies on a final
/// edge; -1 otherwise.
int final_halfedge_of(const Context& c, const FaceSlice& s, int h) {
  const HalfEdge& x = s.he[h];
  if (x.kind == FinalChord) {
    const int ep = s.chords[x.index].curve;
    return c.tp.edge_halfedges(ep, x.forward ? 0 : 1);
  }
  if (x.kind == Boundary) {
    const int e1 = s.side_edge[x.index], co = c.oT.coincident[e1];
    if (co == 0) return -1;
    const bool same = s.side_forward[x.index] == (co > 0);
    return c.tp.edge_halfedges(std::abs(co) - 1, same ? 0 : 1);
  }
  return -1;
}

/// The input and final faces of each cell, from its sides, corners and points; cells that touch
/// neither an input edge nor a final edge take their neighbours' faces.
void assign_cell_faces(Context& c, FaceSlice& s) {
  const int nv = c.mesh.num_vertices();
  auto agree = [&](int& slot, int value, const char* what) {
    if (value < 0) return;
    if (slot >= 0 && slot != value) {
      internal_error(std::string("a cell of Delaunay face ") + std::to_string(s.t) +
                     " lies in two " + what + " faces");
    }
    slot = value;
  };
  for (Cell& cell : s.cells) {
    for (int h : cell.half_edges) {
      agree(cell.input_face, input_face_of(c, s, h), "input");
      const int hp = final_halfedge_of(c, s, h);
      if (hp >= 0) agree(cell.final_face, hp / 3, "final");
      const HalfEdge& x = s.he[h];
      if (x.from < s.np && s.ports[x.from].corner >= 0) {
        agree(cell.final_face, wedge_after(c, s, x.from, s.rot_index[h]).first, "final");
      } else if (x.from < s.np) {
        const FinalFacePoint& in = c.in_final_face[s.ports[x.from].vertex - nv];
        if (in.face >= 0) agree(cell.final_face, in.face, "final");
      }
    }
  }
  for (bool changed = true; changed;) {
    changed = false;
    for (Cell& cell : s.cells) {
      if (cell.input_face >= 0 && cell.final_face >= 0) continue;
      for (int h : cell.half_edges) {
        const int other = s.cell_of[s.he[h].twin];
        if (other < 0) continue;
        if (cell.input_face < 0 && s.he[h].kind != InputChord && s.cells[other].input_face >= 0) {
          cell.input_face = s.cells[other].input_face;
          changed = true;
        }
        if (cell.final_face < 0 && s.he[h].kind != FinalChord && s.cells[other].final_face >= 0) {
          cell.final_face = s.cells[other].final_face;
          changed = true;
        }
      }
    }
  }
}

/// Per corner of a cell: its refinement vertex, Delaunay and final barycentric coordinates and
/// log w.
struct CellCorners {
  std::vector<Vec3> dbary, fbary;
  std::vector<double> log_w;
  std::vector<int> vertex;
};

CellCorners cell_corners(Context& c, const FaceSlice& s, const Cell& cell) {
  const int nv = c.mesh.num_vertices();
  const int g = cell.final_face;
  const int n = static_cast<int>(cell.half_edges.size());
  CellCorners out;
  out.dbary.resize(static_cast<std::size_t>(n));
  out.fbary.resize(static_cast<std::size_t>(n));
  out.log_w.resize(static_cast<std::size_t>(n));
  out.vertex.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const int h = cell.half_edges[i], prev = cell.half_edges[(i + n - 1) % n];
    const int lv = s.he[h].from;
    if (lv < s.np) {
      out.dbary[i] = s.ports[lv].bary;
      out.vertex[i] = s.ports[lv].vertex;
    } else {
      out.dbary[i] = s.interior[lv - s.np].bary;
      out.vertex[i] = s.interior[lv - s.np].vertex;
    }
    if (lv < s.np && s.ports[lv].corner >= 0) {
      const auto [wf, wk] = wedge_after(c, s, lv, s.rot_index[h]);
      if (wf != g) internal_error("corner wedge and cell disagree");
      out.fbary[i] = Vec3::Unit(wk);
      out.log_w[i] = -c.u[out.vertex[i]];
      continue;
    }
    const int gv = out.vertex[i] - nv;
    if (c.in_final_face[gv].face >= 0) {
      if (c.in_final_face[gv].face != g) internal_error("a point and its cell disagree");
      out.fbary[i] = c.in_final_face[gv].bary;
      out.log_w[i] = c.in_final_face[gv].log_w;
      continue;
    }
    const FinalEdgePoint& fe = c.on_final_edge[gv];
    int hp = final_halfedge_of(c, s, h);
    if (hp < 0 || c.tp.halfedge_edge[hp] != fe.edge) hp = final_halfedge_of(c, s, prev);
    if (hp < 0 || c.tp.halfedge_edge[hp] != fe.edge || hp / 3 != g) {
      internal_error("a point on final edge " + std::to_string(fe.edge) +
                     " has no side in its cell of Delaunay face " + std::to_string(s.t));
    }
    out.fbary[i] = bary_on_halfedge(c.tp, hp, fe.s);
    out.log_w[i] = fe.log_w;
  }
  return out;
}

/// Side k of a piece lying on half-edge h: its refinement edge id, input edge and final
/// halfedge.
void set_piece_side(const Context& c, const FaceSlice& s, Piece& piece, int k, int h) {
  piece.edge_id[k] = s.he[h].edge_id;
  const HalfEdge& x = s.he[h];
  if (x.kind == InputChord) {
    piece.input_edge[k] = s.chords[x.index].curve;
  } else if (x.kind == Boundary && c.o01.coincident[s.side_edge[x.index]] != 0) {
    piece.input_edge[k] = std::abs(c.o01.coincident[s.side_edge[x.index]]) - 1;
  }
  piece.final_halfedge[k] = final_halfedge_of(c, s, h);
}

/// Fans a cell from its first corner into pieces (the cell is convex); the fan's diagonals get
/// new edge ids.
void fan_cell(Context& c, const FaceSlice& s, const Cell& cell, std::vector<Piece>& out) {
  const CellCorners corners = cell_corners(c, s, cell);
  const int n = static_cast<int>(cell.half_edges.size());
  int diagonal = -1;
  for (int i = 1; i + 1 < n; ++i) {
    Piece piece;
    const int at[3] = {0, i, i + 1};
    for (int k = 0; k < 3; ++k) {
      piece.vertex[k] = corners.vertex[at[k]];
      piece.delaunay_bary[k] = corners.dbary[at[k]];
      piece.final_bary[k] = corners.fbary[at[k]];
      piece.log_w[k] = corners.log_w[at[k]];
    }
    piece.input_face = cell.input_face;
    piece.delaunay_face = s.t;
    piece.final_face = cell.final_face;
    set_piece_side(c, s, piece, 0, cell.half_edges[i]);
    if (i + 2 == n) {
      set_piece_side(c, s, piece, 1, cell.half_edges[n - 1]);
    } else {
      piece.edge_id[1] = c.num_edge_ids;
    }
    if (i == 1) {
      set_piece_side(c, s, piece, 2, cell.half_edges[0]);
    } else {
      piece.edge_id[2] = diagonal;
    }
    if (i + 2 != n) diagonal = c.num_edge_ids++;
    out.push_back(piece);
  }
}

}  // namespace

void slice_delaunay_face(Context& c, int t, std::vector<Piece>& out, CommonRefinement& result) {
  FaceSlice s;
  s.t = t;
  collect_ports(c, s);
  collect_chords(c, s);
  find_chord_crossings(s);
  intersect_chords(s, result);
  add_interior_vertices(c, s);
  build_planar_graph(c, s);
  trace_cells(s);
  assign_cell_faces(c, s);
  for (const Cell& cell : s.cells) {
    if (cell.input_face < 0 || cell.final_face < 0) {
      internal_error("a cell of Delaunay face " + std::to_string(t) +
                     " has no input or final face");
    }
    fan_cell(c, s, cell, out);
  }
}

}  // namespace ricci::refinement_support
