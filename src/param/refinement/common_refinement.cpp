#include "ricci/param/refinement/common_refinement.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "param/refinement/detail/refinement_stages.hpp"
#include "param/refinement/detail/refinement_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/intrinsic/edge_overlay.hpp"
#include "ricci/intrinsic/intrinsic_triangulation.hpp"
#include "ricci/metric/scheme.hpp"
#include "ricci/numerics/complex.hpp"
#include "ricci/numerics/timer.hpp"

namespace ricci {

using namespace refinement_support;

namespace {

/// The smallest weight (and denominator) the light-cone arithmetic of a final-edge crossing
/// takes: a crossing at a corner of a Delaunay edge would otherwise take the log of 0. Far below
/// any weight a real crossing has (they are products of length ratios), far above underflow.
constexpr double kTinyWeight = 1e-300;

/// Develops each input edge over the Delaunay triangles it crosses (the flat metric): where it
/// crosses each Delaunay edge, along both.
void place_input_crossings(Context& c, const std::vector<CurvePath>& paths,
                           CommonRefinement& result) {
  const FaceShapes shapes = face_shapes_from_lengths(c.t1, c.l1);
  for (int curve = 0; curve < c.t0.num_edges; ++curve) {
    const CurvePath& p = paths[curve];
    if (p.coincident_halfedge >= 0) continue;
    std::array<Complex, 3> face = shapes[p.start_face];
    const Complex start = face[p.start_corner];
    std::vector<std::pair<Complex, Complex>> sides;
    sides.reserve(p.crossings.size());
    for (const CurveCrossing& x : p.crossings) {
      const int k = x.halfedge % 3;
      const Complex a = face[(k + 1) % 3], b = face[(k + 2) % 3];
      sides.emplace_back(a, b);
      const int twin = c.t1.halfedge_twin[x.halfedge], k2 = twin % 3;
      const auto& next = shapes[twin / 3];
      const Rigid m = segment_motion(next[(k2 + 2) % 3], next[(k2 + 1) % 3], a, b);
      for (int j = 0; j < 3; ++j) face[j] = m(next[j]);
    }
    const Complex end = face[p.end_corner];
    result.max_development_error = std::max(
        result.max_development_error, std::abs(std::abs(end - start) - c.l0[curve]) / c.l0[curve]);
    for (std::size_t i = 0; i < sides.size(); ++i) {
      const auto [a, b] = sides[i];
      const double denominator = cross(b - a, end - start);
      double s = denominator != 0 ? cross(start - a, end - start) / denominator : 0.5;
      double tau = denominator != 0 ? cross(start - a, b - a) / denominator : 0.5;
      s = std::clamp(s, 0.0, 1.0);
      tau = std::clamp(tau, 0.0, 1.0);
      const CurveCrossing& x = p.crossings[i];
      const bool forward = x.halfedge == c.t1.edge_halfedges(x.edge, 0);
      c.a_s[x.edge][x.index] = forward ? s : 1 - s;
      c.a_tau[x.edge][x.index] = tau;
    }
  }
}

/// Light-cone coordinates kept as a direction (largest entry 1) and a log scale.
struct Lift {
  Vec3 x;
  double log_scale = 0;
  void normalize() {
    const double m = x.cwiseAbs().maxCoeff();
    if (m > 0) {
      x /= m;
      log_scale += std::log(m);
    }
  }
};

/// Crossing of halfedge g (in face F, apex c at corner k, a -> b) into its twin's face (apex d
/// at corner k2): the coefficients of v_d over v_a, v_b, v_c and of v_c over v_a, v_b, v_d.
struct Transition {
  int k, k2;
  double alpha, beta, gamma;     // v_d = alpha v_a + beta v_b + gamma v_c
  double alpha2, beta2, gamma2;  // v_c = alpha2 v_a + beta2 v_b + gamma2 v_d
};

/// The transition across Delaunay halfedge g: its quad read and l_cd given by the flips' own
/// kernel (quad_lengths, ptolemy_diagonal), the refinement being Euclidean.
Transition transition(const Context& c, int g) {
  const int k = g % 3, k2 = c.t1.halfedge_twin[g] % 3;
  const QuadLengths q = quad_lengths(c.t1, c.l1, g);
  const double ab = q.ab, ac = q.ca, bc = q.cb, ad = q.da, bd = q.db;
  const double cd = ptolemy_diagonal(q, Geometry::Euclidean);
  return Transition{k,
                    k2,
                    bd * cd / (ac * ab),
                    ad * cd / (bc * ab),
                    -ad * bd / (ac * bc),
                    bc * cd / (ad * ab),
                    ac * cd / (bd * ab),
                    -ac * bc / (ad * bd)};
}

/// Develops final edge e over the Delaunay triangles it crosses in the light cone: lifts of the
/// corners carried from triangle to triangle by v_d = alpha v_a + beta v_b + gamma v_c, the edge
/// the plane of its two ends' lifts.
void place_final_crossings_of(Context& c, int e, const CurvePath& p) {
  const Topology& t1 = c.t1;
  const int m = static_cast<int>(p.crossings.size());
  std::vector<Transition> steps;
  steps.reserve(m);
  for (const CurveCrossing& x : p.crossings) steps.push_back(transition(c, x.halfedge));
  // Forward: the start's lift in each face's basis (face i is before crossing i).
  std::vector<Lift> start(static_cast<std::size_t>(m + 1)), end(static_cast<std::size_t>(m + 1));
  start[0].x = Vec3::Unit(p.start_corner);
  for (int i = 0; i < m; ++i) {
    const Transition& s = steps[i];
    const Vec3& x = start[i].x;
    Vec3 y;
    y[(s.k2 + 2) % 3] = x[(s.k + 1) % 3] + s.alpha2 * x[s.k];
    y[(s.k2 + 1) % 3] = x[(s.k + 2) % 3] + s.beta2 * x[s.k];
    y[s.k2] = s.gamma2 * x[s.k];
    start[i + 1] = {y, start[i].log_scale};
    start[i + 1].normalize();
  }
  end[m].x = Vec3::Unit(p.end_corner);
  for (int i = m - 1; i >= 0; --i) {
    const Transition& s = steps[i];
    const Vec3& y = end[i + 1].x;
    Vec3 x;
    x[(s.k + 1) % 3] = y[(s.k2 + 2) % 3] + s.alpha * y[s.k2];
    x[(s.k + 2) % 3] = y[(s.k2 + 1) % 3] + s.beta * y[s.k2];
    x[s.k] = s.gamma * y[s.k2];
    end[i] = {x, end[i + 1].log_scale};
    end[i].normalize();
  }
  const int v_start = c.tp.tail(c.tp.edge_halfedges(e, 0));
  const int v_end = c.tp.head(c.tp.edge_halfedges(e, 0));
  for (int i = 0; i < m; ++i) {
    const int k = steps[i].k;
    const Lift& P = start[i];
    const Lift& Q = end[i];
    // The crossing X = lambda P + mu Q has no c coordinate; P is on c's side, Q across.
    const double lambda = std::max(-Q.x[k], kTinyWeight), mu = std::max(P.x[k], kTinyWeight);
    const Vec3 X = lambda * P.x + mu * Q.x;
    const double xa = std::max(X[(k + 1) % 3], 0.0), xb = std::max(X[(k + 2) % 3], 0.0);
    const double along = xa + xb > 0 ? xb / (xa + xb) : 0.5;
    // In the final metric the ends' lifts are e^{u} times these.
    const double lp = std::log(lambda) - P.log_scale - c.u[v_start];
    const double lq = std::log(mu) - Q.log_scale - c.u[v_end];
    const CurveCrossing& x = p.crossings[i];
    const bool forward = x.halfedge == t1.edge_halfedges(x.edge, 0);
    c.b_s[x.edge][x.index] = forward ? along : 1 - along;
    c.b_final[x.edge][x.index] = {e, 1 / (1 + std::exp(lp - lq)),
                                  log_sum_exp(lp, lq) - std::log(std::max(xa + xb, kTinyWeight))};
  }
}

/// Sizes the per-Delaunay-edge crossing lists to the overlays' normal coordinates.
void allocate_crossings(Context& c) {
  const int ne1 = c.t1.num_edges;
  c.a_s.resize(ne1);
  c.a_tau.resize(ne1);
  c.b_s.resize(ne1);
  c.b_final.resize(ne1);
  c.a_vertex.resize(ne1);
  c.b_vertex.resize(ne1);
  for (int e = 0; e < ne1; ++e) {
    const std::size_t na = c.o01.crossings[e].size(), nb = c.oT.crossings[e].size();
    c.a_s[e].assign(na, 0);
    c.a_tau[e].assign(na, 0);
    c.a_vertex[e].assign(na, -1);
    c.b_s[e].assign(nb, 0);
    c.b_final[e].assign(nb, {});
    c.b_vertex[e].assign(nb, -1);
  }
}

/// Moves the crossing parameters back into the order the combinatorics fix: along each Delaunay
/// edge, along each input edge and along each final edge.
void repair_crossing_order(Context& c, const RefinementPaths& paths, CommonRefinement& result) {
  for (int e = 0; e < c.t1.num_edges; ++e) {
    std::vector<double*> a, b;
    for (double& s : c.a_s[e]) a.push_back(&s);
    for (double& s : c.b_s[e]) b.push_back(&s);
    result.order_repairs += repair_order(a) + repair_order(b);
  }
  for (const CurvePath& p : paths.input) {
    std::vector<double*> taus;
    for (const CurveCrossing& x : p.crossings) taus.push_back(&c.a_tau[x.edge][x.index]);
    result.order_repairs += repair_order(taus);
  }
  for (const CurvePath& p : paths.final) {
    std::vector<double*> s;
    for (const CurveCrossing& x : p.crossings) s.push_back(&c.b_final[x.edge][x.index].s);
    result.order_repairs += repair_order(s);
  }
}

/// Merges the input-edge and final-edge crossings of each Delaunay edge into one list in order
/// along its halfedge 0 (c.ports), and numbers the segments between them (c.segment_offset).
void order_edge_points(Context& c) {
  const int ne1 = c.t1.num_edges;
  c.ports.resize(ne1);
  c.segment_offset.resize(ne1);
  int segments = 0;
  for (int e = 0; e < ne1; ++e) {
    const int na = static_cast<int>(c.a_s[e].size()), nb = static_cast<int>(c.b_s[e].size());
    auto& list = c.ports[e];
    for (int ia = 0, ib = 0; ia < na || ib < nb;) {
      if (ia < na && (ib >= nb || c.a_s[e][ia] <= c.b_s[e][ib])) {
        list.push_back({false, ia++});
      } else {
        list.push_back({true, ib++});
      }
    }
    c.segment_offset[e] = segments;
    segments += static_cast<int>(list.size()) + 1;
  }
  c.num_edge_ids = segments;
}

/// The rows over the input of the points on Delaunay edge e (s: their parameters, in c.ports
/// order): input-edge crossings directly; final-edge crossings between their neighbours among
/// the corners and input-edge crossings (one input face holds the stretch between those).
std::vector<Row> edge_point_rows(const Context& c, int e, const std::vector<double>& s) {
  const auto& list = c.ports[e];
  const int h0 = c.t1.edge_halfedges(e, 0);
  const int tail = c.t1.tail(h0), head = c.t1.head(h0);
  std::vector<Row> rows(list.size());
  for (std::size_t i = 0; i < list.size(); ++i) {
    const auto [is_b, j] = list[i];
    if (!is_b) {
      const int curve = std::abs(c.o01.crossings[e][j]) - 1;
      const int hc = c.t0.edge_halfedges(curve, 0);
      const double tau = c.a_tau[e][j];
      rows[i] = {{c.t0.tail(hc), 1 - tau}, {c.t0.head(hc), tau}};
    }
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (!list[i].first) continue;
    double s0 = 0, s1 = 1;
    Row r0{{tail, 1.0}}, r1{{head, 1.0}};
    for (std::size_t k = i; k-- > 0;) {
      if (!list[k].first) {
        s0 = s[k];
        r0 = rows[k];
        break;
      }
    }
    for (std::size_t k = i + 1; k < list.size(); ++k) {
      if (!list[k].first) {
        s1 = s[k];
        r1 = rows[k];
        break;
      }
    }
    rows[i] = lerp_rows(r0, r1, s1 > s0 ? (s[i] - s0) / (s1 - s0) : 0.0);
  }
  return rows;
}

/// A point of a Delaunay edge whose place in the final triangulation is known: its parameter,
/// and its homogeneous coordinates in the final faces ahead of it and behind it along the edge.
struct KnownPoint {
  double s;
  FinalFacePoint ahead, behind;
};

/// The known points of Delaunay edge e that is no final edge: its ends (in the final corners
/// holding them) and its final-edge crossings, in order (s: the parameters in c.ports order).
std::vector<KnownPoint> known_final_points(Context& c, int e, const std::vector<double>& s) {
  const auto& list = c.ports[e];
  const int h0 = c.t1.edge_halfedges(e, 0), h1 = c.t1.edge_halfedges(e, 1);
  const int tail = c.t1.tail(h0), head = c.t1.head(h0);
  auto corner_point = [&](std::pair<int, int> w, int v) {
    return FinalFacePoint{w.first, Vec3::Unit(w.second), -c.u[v]};
  };
  std::vector<KnownPoint> known;
  known.push_back({0, corner_point(c.wedge_of_halfedge(h0), tail), {}});
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (!list[i].first) continue;
    const int j = list[i].second;
    const int entry = c.oT.crossings[e][j], ep = std::abs(entry) - 1;
    const FinalEdgePoint& fe = c.b_final[e][j];
    // A final edge crossing from the right of this edge to its left has the stretch ahead
    // on its right (the face of its halfedge 1).
    const int ahead = c.tp.edge_halfedges(ep, entry > 0 ? 1 : 0);
    const int behind = c.tp.edge_halfedges(ep, entry > 0 ? 0 : 1);
    known.push_back({s[i],
                     {ahead / 3, bary_on_halfedge(c.tp, ahead, fe.s), fe.log_w},
                     {behind / 3, bary_on_halfedge(c.tp, behind, fe.s), fe.log_w}});
  }
  if (h1 < 0) internal_error("a boundary Delaunay edge that is no final edge");
  known.push_back({1, {}, corner_point(c.wedge_of_halfedge(h1), head)});
  return known;
}

/// The refinement vertices of the points on Delaunay edge e, with their rows and their places in
/// the final triangulation: homogeneous final coordinates of the input-edge crossings on the
/// final edge this Delaunay edge is, or between the neighbouring corners and final-edge
/// crossings.
void place_points_on_edge(Context& c, int e) {
  const auto& list = c.ports[e];
  if (list.empty()) return;
  const int nv = c.mesh.num_vertices();
  const int input_edge = c.o01.coincident[e] != 0 ? std::abs(c.o01.coincident[e]) - 1 : -1;
  std::vector<double> s(list.size());
  for (std::size_t i = 0; i < list.size(); ++i) {
    const auto [is_b, j] = list[i];
    s[i] = is_b ? c.b_s[e][j] : c.a_s[e][j];
  }
  const std::vector<Row> rows = edge_point_rows(c, e, s);
  const int coincident_final = c.oT.coincident[e];
  const std::vector<KnownPoint> known =
      coincident_final == 0 ? known_final_points(c, e, s) : std::vector<KnownPoint>{};
  std::size_t next_known = 1;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const auto [is_b, j] = list[i];
    const int vertex = c.add_vertex(
        rows[i], is_b ? input_edge : std::abs(c.o01.crossings[e][j]) - 1, is_b ? 1 : 0);
    const int gv = vertex - nv;
    if (is_b) {
      c.b_vertex[e][j] = vertex;
      c.on_final_edge[gv] = c.b_final[e][j];
      ++next_known;
      continue;
    }
    c.a_vertex[e][j] = vertex;
    if (coincident_final != 0) {
      // This Delaunay edge is a final edge: the projective map along it has weights e^{-u}.
      const int ep = std::abs(coincident_final) - 1;
      const double sigma = coincident_final > 0 ? s[i] : 1 - s[i];
      const int hp = c.tp.edge_halfedges(ep, 0);
      const double lt = -c.u[c.tp.tail(hp)], lh = -c.u[c.tp.head(hp)];
      const FinalFacePoint m = homogeneous_lerp(Vec3(1, 0, 0), lt, Vec3(0, 1, 0), lh, sigma);
      c.on_final_edge[gv] = {ep, m.bary[1], m.log_w};
      continue;
    }
    const KnownPoint &k0 = known[next_known - 1], &k1 = known[next_known];
    if (k0.ahead.face != k1.behind.face) {
      internal_error("Delaunay edge " + std::to_string(e) + " leaves a final face unannounced");
    }
    const double fraction = k1.s > k0.s ? (s[i] - k0.s) / (k1.s - k0.s) : 0.0;
    c.in_final_face[gv] =
        homogeneous_lerp(k0.ahead.bary, k0.ahead.log_w, k1.behind.bary, k1.behind.log_w, fraction);
    c.in_final_face[gv].face = k0.ahead.face;
  }
}

/// Checks what common_refinement can refine: converged, vertex scaling in the plane (one
/// component: the MeshParamResult overload checks that).
void check_refinable(const Parameterization& param) {
  if (!param.converged) {
    throw InvalidInput("common_refinement: the parameterization did not converge" +
                       (param.message.empty() ? std::string() : ": " + param.message));
  }
  const ConformalStructure& structure = param.flow.structure.structure;
  if (!scheme_traits(structure.scheme).ptolemy_flips || (structure.epsilon.array() != 0.0).any() ||
      structure.geometry != Geometry::Euclidean) {
    throw InvalidInput(
        "common_refinement: the exact map is that of vertex scaling (Ptolemy flips keep its "
        "conformal class); this parameterization used " +
        std::string(scheme_name(structure.scheme)));
  }
}

}  // namespace

namespace refinement_support {

FlowInput flow_input(const Parameterization& param) {
  const MeshFlowResult& flow = param.flow;
  FlowInput in;
  in.front_faces = param.mesh.num_faces();
  const ComponentFlow* doubled = nullptr;
  for (const ComponentFlow& component : flow.components) {
    if (component.doubled) doubled = &component;
  }
  if (doubled == nullptr) {
    in.mesh = param.mesh;
    in.base_topology = build_topology(in.mesh.triangles, in.mesh.num_vertices());
    in.flipped_edges = flow.intrinsic.flipped_edges();
    in.flip_is_isometric = flow.intrinsic.flip_is_isometric();
    in.final_topology = flow.intrinsic.topology();
    in.final_lengths = flow.lengths;
    in.u = flow.u;
    return in;
  }
  if (flow.components.size() != 1) {
    throw InvalidInput(
        "common_refinement: a component flowed on its double in a mesh of several components");
  }
  const FlowResult& f = doubled->flow;
  const int n = static_cast<int>(doubled->doubled_vertex_original.size());
  in.doubled = true;
  in.mesh.positions.resize(n, 3);
  for (int v = 0; v < n; ++v) {
    const int local = doubled->doubled_vertex_original[v];
    const int whole = doubled->vertices.empty() ? local : doubled->vertices[local];
    in.mesh.positions.row(v) = param.mesh.positions.row(whole);
  }
  in.mesh.triangles = doubled->doubled_triangles;
  in.base_topology = f.intrinsic.input();
  in.flipped_edges = f.intrinsic.flipped_edges();
  in.flip_is_isometric = f.intrinsic.flip_is_isometric();
  in.final_topology = f.intrinsic.topology();
  in.final_lengths = f.lengths;
  in.u = f.u;
  return in;
}

FlipLogSplit split_flip_log(const Topology& t0, const std::vector<int>& flipped_edges,
                            const std::vector<char>& flip_is_isometric) {
  FlipLogSplit log;
  std::vector<char> had_ptolemy(t0.components.size(), 0);
  for (std::size_t i = 0; i < flipped_edges.size(); ++i) {
    const int e = flipped_edges[i];
    if (e < 0 || e >= t0.num_edges || t0.edge_halfedges(e, 0) < 0) {
      throw InvalidInput("common_refinement: flip " + std::to_string(i) + " names edge " +
                         std::to_string(e) + ", which does not exist");
    }
    const int component = t0.face_component[t0.edge_halfedges(e, 0) / 3];
    if (flip_is_isometric[i]) {
      if (had_ptolemy[component]) {
        throw InvalidInput("common_refinement: isometric flip " + std::to_string(i) +
                           " comes after a Ptolemy flip of its component");
      }
      log.isometric.push_back(e);
    } else {
      had_ptolemy[component] = 1;
      log.ptolemy.push_back(e);
    }
  }
  return log;
}

EdgeOverlay replay_flip_log(Context& c, const FlipLogSplit& log, const Topology& final_topology,
                            const Eigen::VectorXd& final_lengths, CommonRefinement& result) {
  OverlaidReplay delaunay =
      replay_flips_with_overlay(c.t0, c.l0, log.isometric, FlipLength::Isometric);
  c.t1 = std::move(delaunay.topology);
  c.o01 = std::move(delaunay.overlay);
  c.l1 = std::move(delaunay.lengths);
  OverlaidReplay final = replay_flips_with_overlay(c.t1, c.l1, log.ptolemy, FlipLength::Ptolemy);
  c.tp = std::move(final.topology);
  if (c.tp.triangles != final_topology.triangles || c.tp.face_edges != final_topology.face_edges) {
    throw InvalidInput(
        "common_refinement: the flip log does not reproduce the flow's final triangulation");
  }
  const Eigen::VectorXd& ptolemy_lengths = final.lengths;
  for (int e = 0; e < c.tp.num_edges; ++e) {
    const double expected =
        ptolemy_lengths[e] *
        std::exp(0.5 * (c.u[c.tp.edge_vertices(e, 0)] + c.u[c.tp.edge_vertices(e, 1)]));
    result.max_metric_mismatch = std::max(result.max_metric_mismatch,
                                          std::abs(expected - final_lengths[e]) / final_lengths[e]);
  }
  c.final_shapes = face_shapes_from_lengths(c.tp, final_lengths);
  return std::move(final.overlay);
}

RefinementPaths trace_overlays(Context& c, const EdgeOverlay& delaunay_over_final) {
  RefinementPaths paths;
  paths.input = trace_curves(c.t1, c.o01);
  const std::vector<CurvePath> paths1p = trace_curves(c.tp, delaunay_over_final);
  c.oT = transpose_overlay(c.tp, delaunay_over_final, paths1p, c.t1);
  paths.final = trace_curves(c.t1, c.oT);
  for (int e = 0; e < c.tp.num_edges; ++e) {
    for (int i = 0; i < static_cast<int>(paths.final[e].crossings.size()); ++i) {
      const CurveCrossing& x = paths.final[e].crossings[i];
      const CurveCrossing& y = paths1p[x.edge].crossings[x.index];
      if (y.edge != e || y.index != i) internal_error("the two overlays disagree");
    }
  }
  return paths;
}

void place_crossings(Context& c, const RefinementPaths& paths, CommonRefinement& result) {
  allocate_crossings(c);
  place_input_crossings(c, paths.input, result);
  for (int e = 0; e < c.tp.num_edges; ++e) {
    if (paths.final[e].coincident_halfedge >= 0) continue;
    place_final_crossings_of(c, e, paths.final[e]);
  }
  repair_crossing_order(c, paths, result);
}

void find_departures(Context& c) {
  const int nf1 = c.t1.num_faces;
  c.b_arcs.resize(nf1);
  c.departures.assign(3 * static_cast<std::size_t>(nf1), {});
  c.start_wedge_cache.assign(3 * static_cast<std::size_t>(nf1), {-1, -1});
  for (int t = 0; t < nf1; ++t) {
    c.b_arcs[t] = face_arcs(c.t1, c.oT, t);
    std::vector<std::vector<std::pair<int, std::pair<int, int>>>> keyed(3);
    for (const FaceArc& arc : c.b_arcs[t]) {
      if (!arc.from.is_corner() && !arc.to.is_corner()) continue;
      const bool leaves = arc.from.is_corner();
      const int corner = leaves ? arc.from.corner : arc.to.corner;
      const int hp = c.tp.edge_halfedges(arc.curve, leaves ? 0 : 1);
      keyed[corner].push_back({leaves ? arc.to.index : arc.from.index, {hp / 3, (hp % 3 + 1) % 3}});
    }
    for (int k = 0; k < 3; ++k) {
      std::sort(keyed[k].begin(), keyed[k].end());
      for (const auto& entry : keyed[k]) c.departures[3 * t + k].push_back(entry.second);
    }
  }
}

void place_edge_points(Context& c) {
  order_edge_points(c);
  for (int e = 0; e < c.t1.num_edges; ++e) place_points_on_edge(c, e);
}

SlicedFaces slice_faces(Context& c, int front_faces, CommonRefinement& result) {
  SlicedFaces sliced;
  std::vector<Piece>& pieces = sliced.pieces;
  for (int t = 0; t < c.t1.num_faces; ++t) slice_delaunay_face(c, t, pieces, result);
  sliced.on_final_all.assign(static_cast<std::size_t>(c.tp.num_edges), 0);
  for (const Piece& piece : pieces) {
    for (int hp : piece.final_halfedge) {
      if (hp >= 0 && hp == c.tp.edge_halfedges(c.tp.halfedge_edge[hp], 0)) {
        ++sliced.on_final_all[c.tp.halfedge_edge[hp]];
      }
    }
  }
  pieces.erase(
      std::remove_if(pieces.begin(), pieces.end(),
                     [front_faces](const Piece& p) { return p.input_face >= front_faces; }),
      pieces.end());
  return sliced;
}

}  // namespace refinement_support

CommonRefinement common_refinement(const MeshParamResult& param,
                                   const CommonRefinementOptions& options) {
  if (!param.components.empty()) {
    throw InvalidInput(
        "common_refinement: the parameterization covers " +
        std::to_string(param.components.size()) +
        " components; take the refinement of each one's own result (components[c].param)");
  }
  return common_refinement(static_cast<const Parameterization&>(param), options);
}

CommonRefinement common_refinement(const Parameterization& param,
                                   const CommonRefinementOptions& options) {
  const auto started = Clock::now();
  check_refinable(param);
  const FlowInput flow = flow_input(param);
  const int nv = flow.mesh.num_vertices();  // the surface flowed
  const int front = flow.front_faces;
  Context c(flow.mesh, param, flow.u);
  c.t0 = flow.base_topology;
  c.l0 = input_edge_lengths(flow.mesh, c.t0);
  if (flow.u.size() != nv || flow.final_lengths.size() != c.t0.num_edges ||
      flow.flip_is_isometric.size() != flow.flipped_edges.size() ||
      param.cut_mesh.triangles.rows() != front || param.uv.rows() != param.layout.uv.rows()) {
    throw InvalidInput("common_refinement: the parameterization's arrays do not fit its mesh");
  }
  // A polished layout moved interior vertices off the flat metric's positions: the refinement
  // is the exact map, so it reads the positions from before the polish.
  const bool polished = param.polish.moved_vertices > 0;
  const Eigen::Matrix<double, Eigen::Dynamic, 2>& exact_uv =
      polished ? param.polish.uv : param.layout.uv;
  if (exact_uv.rows() != param.layout.uv.rows()) {
    throw InvalidInput(
        "common_refinement: the layout was polished and the flat metric's own positions "
        "(ParamResult::polish.uv) are not kept; parameterize with polish.enabled = false");
  }
  CommonRefinement result;
  result.doubled = flow.doubled;

  const FlipLogSplit log = split_flip_log(c.t0, flow.flipped_edges, flow.flip_is_isometric);
  result.isometric_flips = static_cast<int>(log.isometric.size());
  result.ptolemy_flips = static_cast<int>(log.ptolemy.size());
  const EdgeOverlay delaunay_over_final =
      replay_flip_log(c, log, flow.final_topology, flow.final_lengths, result);
  const RefinementPaths paths = trace_overlays(c, delaunay_over_final);
  place_crossings(c, paths, result);
  find_departures(c);
  place_edge_points(c);
  SlicedFaces sliced = slice_faces(c, front, result);
  const std::vector<int> raw_of = number_vertices(c, sliced.pieces, result);
  write_vertices_and_pieces(c, raw_of, sliced.pieces, options, result);
  const std::vector<std::array<Complex, 3>> corner_uv =
      lay_out_pieces(c, sliced.pieces, front, exact_uv, result);
  write_texture_coordinates(c, sliced.pieces, raw_of, corner_uv, front, polished, exact_uv, result);
  measure_refinement(c, sliced.pieces, sliced.on_final_all, flow.final_lengths, result);
  result.delaunay_topology = std::move(c.t1);
  result.delaunay_lengths = std::move(c.l1);
  result.seconds = seconds_since(started);
  return result;
}

}  // namespace ricci
