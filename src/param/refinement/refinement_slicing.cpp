// Slicing one Delaunay triangle along the input edges and the final edges that cross it: both
// are straight chords there (the input's in the flat metric, the final ones in the triangle's
// Klein model), so the cells are convex and the whole arrangement follows from the order of the
// chords' ends around the triangle.
#include <algorithm>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Geometry>

#include "param/refinement/detail/refinement_support.hpp"

namespace ricci::refinement_support {

void slice_delaunay_face(Context& c, int t, std::vector<Piece>& out, CommonRefinement& result) {
  const Topology& t1 = c.t1;
  const int nv = c.mesh.num_vertices();
  struct Port {
    int vertex = -1;
    int corner = -1;  // 0..2 for a corner
    int side = -1, pos = -1;
    bool is_b = false;
    int e1 = -1, entry = -1;  // T1 edge and index in its A or B list
    Vec3 bary = Vec3::Zero();
  };
  std::vector<Port> ports;
  std::array<std::vector<int>, 3> a_port, b_port;
  std::array<int, 3> corner_port{};
  std::array<bool, 3> side_forward{};
  std::array<int, 3> side_edge{};
  for (int j = 0; j < 3; ++j) {
    corner_port[j] = static_cast<int>(ports.size());
    Port pc;
    pc.vertex = t1.triangles(t, j);
    pc.corner = j;
    pc.bary = Vec3::Unit(j);
    ports.push_back(pc);
    const int s = (j + 2) % 3, h = 3 * t + s, e1 = t1.halfedge_edge[h];
    const bool forward = h == t1.edge_halfedges(e1, 0);
    side_forward[s] = forward;
    side_edge[s] = e1;
    const auto& list = c.ports[e1];
    const int n = static_cast<int>(list.size());
    const int na = static_cast<int>(c.o01.crossings[e1].size());
    const int nb = static_cast<int>(c.oT.crossings[e1].size());
    a_port[s].assign(static_cast<std::size_t>(na), -1);
    b_port[s].assign(static_cast<std::size_t>(nb), -1);
    for (int i = 0; i < n; ++i) {
      const auto [is_b, entry] = list[forward ? i : n - 1 - i];
      Port p;
      p.side = s;
      p.pos = i;
      p.is_b = is_b;
      p.e1 = e1;
      p.entry = entry;
      const double stored = is_b ? c.b_s[e1][entry] : c.a_s[e1][entry];
      const double sigma = forward ? stored : 1 - stored;
      p.bary[(s + 1) % 3] = 1 - sigma;
      p.bary[(s + 2) % 3] = sigma;
      p.vertex = is_b ? c.b_vertex[e1][entry] : c.a_vertex[e1][entry];
      const int along = forward ? entry : (is_b ? nb : na) - 1 - entry;
      (is_b ? b_port : a_port)[s][along] = static_cast<int>(ports.size());
      ports.push_back(p);
    }
  }
  const int np = static_cast<int>(ports.size());

  // Chords, oriented as their curves run.
  struct Chord {
    bool is_b;
    int curve, p, q;
    std::vector<int> points;  // interior points from p to q
  };
  std::vector<Chord> chords;
  auto port_of = [&](const ArcEnd& x, bool is_b) {
    return x.is_corner() ? corner_port[x.corner] : (is_b ? b_port : a_port)[x.side][x.index];
  };
  for (const FaceArc& arc : face_arcs(t1, c.o01, t)) {
    chords.push_back({false, arc.curve, port_of(arc.from, false), port_of(arc.to, false), {}});
  }
  const int num_a = static_cast<int>(chords.size());
  for (const FaceArc& arc : c.b_arcs[t]) {
    chords.push_back({true, arc.curve, port_of(arc.from, true), port_of(arc.to, true), {}});
  }
  const int num_chords = static_cast<int>(chords.size());

  // Crossings of input chords with final chords, from the order of their ends around the face.
  auto dist = [np](int a, int b) { return ((b - a) % np + np) % np; };
  auto inside = [&](int x, int p, int q) {
    const int d = dist(p, x);
    return d > 0 && d < dist(p, q);
  };
  struct Interior {
    int alpha, beta;
    double lambda_a = 0, lambda_b = 0;
    int vertex = -1;
    Vec3 bary = Vec3::Zero();
  };
  std::vector<Interior> interior;
  std::vector<std::vector<std::tuple<int, int, int>>> order(static_cast<std::size_t>(num_chords));
  for (int i = 0; i < num_a; ++i) {
    for (int j = num_a; j < num_chords; ++j) {
      const Chord &a = chords[i], &b = chords[j];
      if (b.p == a.p || b.p == a.q || b.q == a.p || b.q == a.q) continue;
      const bool in_p = inside(b.p, a.p, a.q);
      if (in_p == inside(b.q, a.p, a.q)) continue;
      const int index = static_cast<int>(interior.size());
      interior.push_back({i, j});
      // Along a chord, crossing chords that are disjoint come in the order of their ends on
      // the arc from its start (nearest first), ties at a corner by their other ends.
      const int xa = in_p ? b.p : b.q, ya = in_p ? b.q : b.p;
      order[i].push_back({dist(a.p, xa), dist(ya, a.p), index});
      const bool a_in = inside(a.p, b.p, b.q);
      const int xb = a_in ? a.p : a.q, yb = a_in ? a.q : a.p;
      order[j].push_back({dist(b.p, xb), dist(yb, b.p), index});
    }
  }
  for (int i = 0; i < num_chords; ++i) {
    std::sort(order[i].begin(), order[i].end());
    for (const auto& o : order[i]) chords[i].points.push_back(std::get<2>(o));
  }
  // Where the chords meet: lines through barycentric points, by cross products.
  for (Interior& x : interior) {
    const Chord &a = chords[x.alpha], &b = chords[x.beta];
    const Vec3 &pa = ports[a.p].bary, &qa = ports[a.q].bary, &pb = ports[b.p].bary,
               &qb = ports[b.q].bary;
    Vec3 point = pa.cross(qa).cross(pb.cross(qb));
    if (std::abs(point.sum()) > 1e-300) point /= point.sum();
    auto fraction = [&](const Vec3& p, const Vec3& q) {
      const Vec3 d = q - p;
      const double dd = d.squaredNorm();
      return dd > 0 && point.allFinite() ? std::clamp((point - p).dot(d) / dd, 0.0, 1.0) : 0.5;
    };
    x.lambda_a = fraction(pa, qa);
    x.lambda_b = fraction(pb, qb);
  }
  for (int i = 0; i < num_chords; ++i) {
    std::vector<double*> lambdas;
    for (int k : chords[i].points) {
      lambdas.push_back(i < num_a ? &interior[k].lambda_a : &interior[k].lambda_b);
    }
    result.order_repairs += repair_order(lambdas);
  }
  auto port_tau = [&](int port, bool start) {
    const Port& p = ports[port];
    return p.corner >= 0 ? (start ? 0.0 : 1.0) : c.a_tau[p.e1][p.entry];
  };
  auto port_final = [&](int port, int edge, bool start) {
    const Port& p = ports[port];
    if (p.corner >= 0) return FinalEdgePoint{edge, start ? 0.0 : 1.0, -c.u[p.vertex]};
    return c.b_final[p.e1][p.entry];
  };
  for (Interior& x : interior) {
    const Chord &a = chords[x.alpha], &b = chords[x.beta];
    const double tau = (1 - x.lambda_a) * port_tau(a.p, true) + x.lambda_a * port_tau(a.q, false);
    const int h = c.t0.edge_halfedges(a.curve, 0);
    x.vertex = c.add_vertex({{c.t0.tail(h), 1 - tau}, {c.t0.head(h), tau}}, a.curve, 2);
    x.bary = (1 - x.lambda_a) * ports[a.p].bary + x.lambda_a * ports[a.q].bary;
    const FinalEdgePoint f0 = port_final(b.p, b.curve, true), f1 = port_final(b.q, b.curve, false);
    const FinalFacePoint mixed = homogeneous_lerp(Vec3(1 - f0.s, f0.s, 0), f0.log_w,
                                                  Vec3(1 - f1.s, f1.s, 0), f1.log_w, x.lambda_b);
    c.on_final_edge[x.vertex - nv] = {b.curve, mixed.bary[1], mixed.log_w};
  }

  // The planar graph: ports, then interior points; half-edges with their rotation (counter-
  // clockwise order of the half-edges leaving each vertex).
  const int nloc = np + static_cast<int>(interior.size());
  enum Kind { Boundary, InputChord, FinalChord };
  struct HalfEdge {
    int from, to, twin = -1;
    Kind kind;
    int index;     // side (Boundary) or chord
    bool forward;  // Boundary: counter-clockwise; chords: as the curve runs
    int edge_id;
  };
  std::vector<HalfEdge> he;
  std::vector<std::vector<int>> rotation(static_cast<std::size_t>(nloc));
  auto add_pair = [&](int a, int b, Kind kind, int index, int edge_id) {
    const int h = static_cast<int>(he.size());
    he.push_back({a, b, h + 1, kind, index, true, edge_id});
    he.push_back({b, a, h, kind, index, false, edge_id});
    return h;
  };
  std::vector<int> boundary_out(static_cast<std::size_t>(np)),
      boundary_back(static_cast<std::size_t>(np));
  for (int i = 0; i < np; ++i) {
    const Port& p = ports[i];
    const int s = p.corner >= 0 ? (p.corner + 2) % 3 : p.side;
    const int index = p.corner >= 0 ? 0 : p.pos + 1;
    const int e1 = side_edge[s];
    const int m = static_cast<int>(c.ports[e1].size());
    const int id = c.segment_offset[e1] + (side_forward[s] ? index : m - index);
    const int h = add_pair(i, (i + 1) % np, Boundary, s, id);
    boundary_out[i] = h;
    boundary_back[(i + 1) % np] = h + 1;
  }
  std::vector<std::vector<int>> chord_fwd(static_cast<std::size_t>(num_chords)),
      chord_rev(static_cast<std::size_t>(num_chords));
  for (int i = 0; i < num_chords; ++i) {
    std::vector<int> seq{chords[i].p};
    for (int k : chords[i].points) seq.push_back(np + k);
    seq.push_back(chords[i].q);
    for (std::size_t k = 0; k + 1 < seq.size(); ++k) {
      const int h =
          add_pair(seq[k], seq[k + 1], i < num_a ? InputChord : FinalChord, i, c.num_edge_ids++);
      chord_fwd[i].push_back(h);
      chord_rev[i].push_back(h + 1);
    }
  }
  // Rotations at the ports: forward along the boundary, the chords (at a corner in the order of
  // their far ends along the opposite side), back along the boundary.
  std::vector<std::vector<std::pair<int, int>>> at_port(static_cast<std::size_t>(np));
  for (int i = 0; i < num_chords; ++i) {
    at_port[chords[i].p].push_back({dist(chords[i].p, chords[i].q), chord_fwd[i].front()});
    at_port[chords[i].q].push_back({dist(chords[i].q, chords[i].p), chord_rev[i].back()});
  }
  for (int i = 0; i < np; ++i) {
    if (ports[i].corner < 0 && at_port[i].size() != 1) {
      internal_error("a crossing on a side of Delaunay face " + std::to_string(t) + " ends " +
                     std::to_string(at_port[i].size()) + " arcs");
    }
    std::sort(at_port[i].begin(), at_port[i].end());
    rotation[i].push_back(boundary_out[i]);
    for (const auto& [d, h] : at_port[i]) rotation[i].push_back(h);
    rotation[i].push_back(boundary_back[i]);
  }
  // At an interior point the input chord (start to end) has the arc of the boundary from its
  // start to its end on its right: forward, towards the final chord's end on the left, back,
  // towards the end on the right.
  for (int k = 0; k < static_cast<int>(interior.size()); ++k) {
    const Interior& x = interior[k];
    const Chord &a = chords[x.alpha], &b = chords[x.beta];
    const int ra =
        static_cast<int>(std::find(a.points.begin(), a.points.end(), k) - a.points.begin());
    const int rb =
        static_cast<int>(std::find(b.points.begin(), b.points.end(), k) - b.points.begin());
    const bool b_start_right = inside(b.p, a.p, a.q);
    const int b_towards_end = chord_fwd[x.beta][rb + 1], b_towards_start = chord_rev[x.beta][rb];
    rotation[np + k] = {chord_fwd[x.alpha][ra + 1], b_start_right ? b_towards_end : b_towards_start,
                        chord_rev[x.alpha][ra], b_start_right ? b_towards_start : b_towards_end};
  }
  std::vector<int> rot_index(he.size(), -1);
  for (int v = 0; v < nloc; ++v) {
    for (int r = 0; r < static_cast<int>(rotation[v].size()); ++r) rot_index[rotation[v][r]] = r;
  }
  auto next = [&](int h) {
    const auto& rot = rotation[he[h].to];
    const int r = rot_index[he[h].twin];
    return rot[(r + static_cast<int>(rot.size()) - 1) % rot.size()];
  };

  // The final corner of the sector just counter-clockwise of rotation entry r at corner port pc.
  auto wedge_after = [&](int pc, int r) {
    const int j = ports[pc].corner;
    std::pair<int, int> w = c.start_wedge(t, j);
    for (int k = 1; k <= r && k + 1 < static_cast<int>(rotation[pc].size()); ++k) {
      const HalfEdge& h = he[rotation[pc][k]];
      if (h.kind != FinalChord) continue;
      const int ep = chords[h.index].curve;
      const int hp = h.forward ? c.tp.edge_halfedges(ep, 0) : c.tp.edge_halfedges(ep, 1);
      w = {hp / 3, (hp % 3 + 1) % 3};
    }
    return w;
  };

  // Cells: faces of the planar graph left of the half-edges, the outside excluded.
  std::vector<char> visited(he.size(), 0);
  struct Cell {
    std::vector<int> half_edges;
    int input_face = -1, final_face = -1;
  };
  std::vector<Cell> cells;
  std::vector<int> cell_of(he.size(), -1);
  for (int h0 = 0; h0 < static_cast<int>(he.size()); ++h0) {
    if (visited[h0] || (he[h0].kind == Boundary && !he[h0].forward)) continue;
    Cell cell;
    int h = h0;
    do {
      if (visited[h] || (he[h].kind == Boundary && !he[h].forward) ||
          cell.half_edges.size() > he.size()) {
        internal_error("the cells of Delaunay face " + std::to_string(t) + " do not close");
      }
      visited[h] = 1;
      cell_of[h] = static_cast<int>(cells.size());
      cell.half_edges.push_back(h);
      h = next(h);
    } while (h != h0);
    cells.push_back(std::move(cell));
  }

  // The input and final faces of each cell, from its sides, corners and points.
  auto input_face_of = [&](int h) {
    const HalfEdge& x = he[h];
    int curve = -1;
    bool same = x.forward;
    if (x.kind == InputChord) {
      curve = chords[x.index].curve;
    } else if (x.kind == Boundary) {
      const int e1 = side_edge[x.index], co = c.o01.coincident[e1];
      if (co == 0) return -1;
      curve = std::abs(co) - 1;
      same = side_forward[x.index] == (co > 0);
    } else {
      return -1;
    }
    const int h0 = c.t0.edge_halfedges(curve, same ? 0 : 1);
    return h0 < 0 ? -1 : h0 / 3;
  };
  auto final_halfedge_of = [&](int h) {
    const HalfEdge& x = he[h];
    if (x.kind == FinalChord) {
      const int ep = chords[x.index].curve;
      return c.tp.edge_halfedges(ep, x.forward ? 0 : 1);
    }
    if (x.kind == Boundary) {
      const int e1 = side_edge[x.index], co = c.oT.coincident[e1];
      if (co == 0) return -1;
      const bool same = side_forward[x.index] == (co > 0);
      return c.tp.edge_halfedges(std::abs(co) - 1, same ? 0 : 1);
    }
    return -1;
  };
  auto agree = [&](int& slot, int value, const char* what) {
    if (value < 0) return;
    if (slot >= 0 && slot != value) {
      internal_error(std::string("a cell of Delaunay face ") + std::to_string(t) + " lies in two " +
                     what + " faces");
    }
    slot = value;
  };
  for (Cell& cell : cells) {
    for (int h : cell.half_edges) {
      agree(cell.input_face, input_face_of(h), "input");
      const int hp = final_halfedge_of(h);
      if (hp >= 0) agree(cell.final_face, hp / 3, "final");
      const HalfEdge& x = he[h];
      if (x.from < np && ports[x.from].corner >= 0) {
        agree(cell.final_face, wedge_after(x.from, rot_index[h]).first, "final");
      } else if (x.from < np) {
        const FinalFacePoint& in = c.in_final_face[ports[x.from].vertex - nv];
        if (in.face >= 0) agree(cell.final_face, in.face, "final");
      }
    }
  }
  // Cells that touch neither an input edge nor a final edge take their neighbours' faces.
  for (bool changed = true; changed;) {
    changed = false;
    for (Cell& cell : cells) {
      if (cell.input_face >= 0 && cell.final_face >= 0) continue;
      for (int h : cell.half_edges) {
        const int other = cell_of[he[h].twin];
        if (other < 0) continue;
        if (cell.input_face < 0 && he[h].kind != InputChord && cells[other].input_face >= 0) {
          cell.input_face = cells[other].input_face;
          changed = true;
        }
        if (cell.final_face < 0 && he[h].kind != FinalChord && cells[other].final_face >= 0) {
          cell.final_face = cells[other].final_face;
          changed = true;
        }
      }
    }
  }

  for (const Cell& cell : cells) {
    if (cell.input_face < 0 || cell.final_face < 0) {
      internal_error("a cell of Delaunay face " + std::to_string(t) +
                     " has no input or final face");
    }
    const int g = cell.final_face;
    const int n = static_cast<int>(cell.half_edges.size());
    // Per corner of the cell: Delaunay barycentric coordinates, final ones and log w.
    std::vector<Vec3> dbary(static_cast<std::size_t>(n)), fbary(static_cast<std::size_t>(n));
    std::vector<double> log_w(static_cast<std::size_t>(n));
    std::vector<int> vertex(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      const int h = cell.half_edges[i], prev = cell.half_edges[(i + n - 1) % n];
      const int lv = he[h].from;
      if (lv < np) {
        dbary[i] = ports[lv].bary;
        vertex[i] = ports[lv].vertex;
      } else {
        dbary[i] = interior[lv - np].bary;
        vertex[i] = interior[lv - np].vertex;
      }
      if (lv < np && ports[lv].corner >= 0) {
        const auto [wf, wk] = wedge_after(lv, rot_index[h]);
        if (wf != g) internal_error("corner wedge and cell disagree");
        fbary[i] = Vec3::Unit(wk);
        log_w[i] = -c.u[vertex[i]];
        continue;
      }
      const int gv = vertex[i] - nv;
      if (c.in_final_face[gv].face >= 0) {
        if (c.in_final_face[gv].face != g) internal_error("a point and its cell disagree");
        fbary[i] = c.in_final_face[gv].bary;
        log_w[i] = c.in_final_face[gv].log_w;
        continue;
      }
      const FinalEdgePoint& fe = c.on_final_edge[gv];
      int hp = final_halfedge_of(h);
      if (hp < 0 || c.tp.halfedge_edge[hp] != fe.edge) hp = final_halfedge_of(prev);
      if (hp < 0 || c.tp.halfedge_edge[hp] != fe.edge || hp / 3 != g) {
        internal_error("a point on final edge " + std::to_string(fe.edge) +
                       " has no side in its cell of Delaunay face " + std::to_string(t));
      }
      fbary[i] = bary_on_halfedge(c.tp, hp, fe.s);
      log_w[i] = fe.log_w;
    }
    // Fan from the first corner; the cell is convex.
    auto edge_info = [&](Piece& piece, int k, int h) {
      piece.edge_id[k] = he[h].edge_id;
      const HalfEdge& x = he[h];
      if (x.kind == InputChord) {
        piece.input_edge[k] = chords[x.index].curve;
      } else if (x.kind == Boundary && c.o01.coincident[side_edge[x.index]] != 0) {
        piece.input_edge[k] = std::abs(c.o01.coincident[side_edge[x.index]]) - 1;
      }
      piece.final_halfedge[k] = final_halfedge_of(h);
    };
    int diagonal = -1;
    for (int i = 1; i + 1 < n; ++i) {
      Piece piece;
      const int corners[3] = {0, i, i + 1};
      for (int k = 0; k < 3; ++k) {
        piece.vertex[k] = vertex[corners[k]];
        piece.delaunay_bary[k] = dbary[corners[k]];
        piece.final_bary[k] = fbary[corners[k]];
        piece.log_w[k] = log_w[corners[k]];
      }
      piece.input_face = cell.input_face;
      piece.delaunay_face = t;
      piece.final_face = g;
      edge_info(piece, 0, cell.half_edges[i]);
      if (i + 2 == n) {
        edge_info(piece, 1, cell.half_edges[n - 1]);
      } else {
        piece.edge_id[1] = c.num_edge_ids;
      }
      if (i == 1) {
        edge_info(piece, 2, cell.half_edges[0]);
      } else {
        piece.edge_id[2] = diagonal;
      }
      if (i + 2 != n) diagonal = c.num_edge_ids++;
      out.push_back(piece);
    }
  }
}

}  // namespace ricci::refinement_support
