#include "ricci/param/refinement/common_refinement.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <complex>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>

#include <Eigen/Geometry>

#include "param/refinement/detail/refinement_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/intrinsic/edge_overlay.hpp"
#include "ricci/intrinsic/intrinsic_triangulation.hpp"
#include "ricci/metric/scheme.hpp"
#include "ricci/numerics/timer.hpp"

namespace ricci {

using namespace refinement_support;

namespace {

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

/// Develops each final edge over the Delaunay triangles it crosses in the light cone: lifts of
/// the corners carried from triangle to triangle by v_d = alpha v_a + beta v_b + gamma v_c, the
/// edge the plane of its two ends' lifts.
void place_final_crossings(Context& c, const std::vector<CurvePath>& paths) {
  const Topology& t1 = c.t1;
  // Coordinates are kept as a direction (largest entry 1) and a log scale.
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
  // Crossing of halfedge g (in face F, apex c at corner k, a -> b) into its twin's face (apex d
  // at corner k2): the coefficients of v_d over v_a, v_b, v_c and of v_c over v_a, v_b, v_d.
  struct Transition {
    int k, k2;
    double alpha, beta, gamma;     // v_d = alpha v_a + beta v_b + gamma v_c
    double alpha2, beta2, gamma2;  // v_c = alpha2 v_a + beta2 v_b + gamma2 v_d
  };
  auto transition = [&](int g) {
    const int f = g / 3, k = g % 3, twin = t1.halfedge_twin[g], f2 = twin / 3, k2 = twin % 3;
    const double ab = c.l1[t1.halfedge_edge[g]];
    const double ac = c.l1[t1.face_edges(f, (k + 2) % 3)], bc = c.l1[t1.face_edges(f, (k + 1) % 3)];
    const double ad = c.l1[t1.face_edges(f2, (k2 + 1) % 3)],
                 bd = c.l1[t1.face_edges(f2, (k2 + 2) % 3)];
    const double cd = (ac * bd + ad * bc) / ab;
    return Transition{k,
                      k2,
                      bd * cd / (ac * ab),
                      ad * cd / (bc * ab),
                      -ad * bd / (ac * bc),
                      bc * cd / (ad * ab),
                      ac * cd / (bd * ab),
                      -ac * bc / (ad * bd)};
  };
  for (int e = 0; e < c.tp.num_edges; ++e) {
    const CurvePath& p = paths[e];
    if (p.coincident_halfedge >= 0) continue;
    const int m = static_cast<int>(p.crossings.size());
    std::vector<Transition> steps;
    steps.reserve(m);
    for (const CurveCrossing& x : p.crossings) steps.push_back(transition(x.halfedge));
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
      const double lambda = std::max(-Q.x[k], 1e-300), mu = std::max(P.x[k], 1e-300);
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
                                    log_sum_exp(lp, lq) - std::log(std::max(xa + xb, 1e-300))};
    }
  }
}
/// The flow the refinement replays: the mesh parameterized with the whole-mesh flip log, or,
/// when the flow ran on the mesh glued to its mirror image (ComponentFlow::doubled), that
/// doubled surface with its own log; its first front_faces faces are the mesh's.
struct FlowInput {
  Mesh mesh;
  Topology base_topology;  // the mesh's connectivity before any flip
  std::vector<int> flipped_edges;
  std::vector<char> flip_is_isometric;
  Topology final_topology;
  Eigen::VectorXd final_lengths, u;
  int front_faces = 0;
  bool doubled = false;
};

FlowInput flow_input(const ParamResult& param) {
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

}  // namespace

CommonRefinement common_refinement(const MeshParamResult& param,
                                   const CommonRefinementOptions& options) {
  if (!param.components.empty()) {
    throw InvalidInput(
        "common_refinement: the parameterization covers " +
        std::to_string(param.components.size()) +
        " components; take the refinement of each one's own result (components[c].param)");
  }
  return common_refinement(static_cast<const ParamResult&>(param), options);
}

CommonRefinement common_refinement(const ParamResult& param,
                                   const CommonRefinementOptions& options) {
  const auto started = Clock::now();
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
  const FlowInput flow = flow_input(param);
  const Mesh& mesh = flow.mesh;
  const int nv = mesh.num_vertices();            // the surface flowed
  const int nv_out = param.mesh.num_vertices();  // the mesh parameterized
  const int front = flow.front_faces;
  Context c(mesh, param, flow.u);
  c.t0 = flow.base_topology;
  c.l0 = input_edge_lengths(mesh, c.t0);
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

  // 1. The flip log split: isometric flips (T0 -> T1) come first in each component.
  std::vector<int> isometric, ptolemy;
  std::vector<char> had_ptolemy(c.t0.components.size(), 0);
  for (std::size_t i = 0; i < flow.flipped_edges.size(); ++i) {
    const int e = flow.flipped_edges[i];
    if (e < 0 || e >= c.t0.num_edges || c.t0.edge_halfedges(e, 0) < 0) {
      throw InvalidInput("common_refinement: flip " + std::to_string(i) + " names edge " +
                         std::to_string(e) + ", which does not exist");
    }
    const int component = c.t0.face_component[c.t0.edge_halfedges(e, 0) / 3];
    if (flow.flip_is_isometric[i]) {
      if (had_ptolemy[component]) {
        throw InvalidInput("common_refinement: isometric flip " + std::to_string(i) +
                           " comes after a Ptolemy flip of its component");
      }
      isometric.push_back(e);
    } else {
      had_ptolemy[component] = 1;
      ptolemy.push_back(e);
    }
  }
  result.isometric_flips = static_cast<int>(isometric.size());
  result.ptolemy_flips = static_cast<int>(ptolemy.size());

  // 2. Replay with labelled normal coordinates: T0 over T1, then T1 over T'.
  c.t1 = c.t0;
  c.o01 = identity_overlay(c.t1);
  c.l1 = c.l0;
  for (int e : isometric) {
    if (!can_flip_edge(c.t1, e)) {
      throw InvalidInput("common_refinement: the flip log flips edge " + std::to_string(e) +
                         ", which cannot be flipped there");
    }
    const QuadLengths q = quad_lengths(c.t1, c.l1, e);
    const double diagonal = euclidean_diagonal(q.ab, q.ca, q.cb, q.da, q.db);
    flip_edge_with_overlay(c.t1, c.o01, e);
    c.l1[e] = diagonal;
  }
  c.tp = c.t1;
  EdgeOverlay o1p = identity_overlay(c.tp);
  Eigen::VectorXd ptolemy_lengths = c.l1;
  for (int e : ptolemy) {
    if (!can_flip_edge(c.tp, e)) {
      throw InvalidInput("common_refinement: the flip log flips edge " + std::to_string(e) +
                         ", which cannot be flipped there");
    }
    const QuadLengths q = quad_lengths(c.tp, ptolemy_lengths, e);
    flip_edge_with_overlay(c.tp, o1p, e);
    ptolemy_lengths[e] = (q.ca * q.db + q.da * q.cb) / q.ab;
  }
  if (c.tp.triangles != flow.final_topology.triangles ||
      c.tp.face_edges != flow.final_topology.face_edges) {
    throw InvalidInput(
        "common_refinement: the flip log does not reproduce the flow's final triangulation");
  }
  const Eigen::VectorXd& final_lengths = flow.final_lengths;
  for (int e = 0; e < c.tp.num_edges; ++e) {
    const double expected =
        ptolemy_lengths[e] *
        std::exp(0.5 * (c.u[c.tp.edge_vertices(e, 0)] + c.u[c.tp.edge_vertices(e, 1)]));
    result.max_metric_mismatch = std::max(result.max_metric_mismatch,
                                          std::abs(expected - final_lengths[e]) / final_lengths[e]);
  }
  c.final_shapes = face_shapes_from_lengths(c.tp, final_lengths);

  const std::vector<CurvePath> paths01 = trace_curves(c.t1, c.o01);
  const std::vector<CurvePath> paths1p = trace_curves(c.tp, o1p);
  c.oT = transpose_overlay(c.tp, o1p, paths1p, c.t1);
  const std::vector<CurvePath> pathsT = trace_curves(c.t1, c.oT);
  for (int e = 0; e < c.tp.num_edges; ++e) {
    for (int i = 0; i < static_cast<int>(pathsT[e].crossings.size()); ++i) {
      const CurveCrossing& x = pathsT[e].crossings[i];
      const CurveCrossing& y = paths1p[x.edge].crossings[x.index];
      if (y.edge != e || y.index != i) internal_error("the two overlays disagree");
    }
  }

  // 3. Geometry of the crossings on the Delaunay edges.
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
  place_input_crossings(c, paths01, result);
  place_final_crossings(c, pathsT);
  for (int e = 0; e < ne1; ++e) {
    std::vector<double*> a, b;
    for (double& s : c.a_s[e]) a.push_back(&s);
    for (double& s : c.b_s[e]) b.push_back(&s);
    result.order_repairs += repair_order(a) + repair_order(b);
  }
  for (const CurvePath& p : paths01) {
    std::vector<double*> taus;
    for (const CurveCrossing& x : p.crossings) taus.push_back(&c.a_tau[x.edge][x.index]);
    result.order_repairs += repair_order(taus);
  }
  for (const CurvePath& p : pathsT) {
    std::vector<double*> s;
    for (const CurveCrossing& x : p.crossings) s.push_back(&c.b_final[x.edge][x.index].s);
    result.order_repairs += repair_order(s);
  }

  // 4. Where the final edges leave each vertex, per Delaunay corner.
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

  // 5. The points on the Delaunay edges, in order along each: vertices, their rows over the
  // input, where they sit in the final triangulation.
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
  for (int e = 0; e < ne1; ++e) {
    const auto& list = c.ports[e];
    if (list.empty()) continue;
    const int h0 = c.t1.edge_halfedges(e, 0), h1 = c.t1.edge_halfedges(e, 1);
    const int tail = c.t1.tail(h0), head = c.t1.head(h0);
    const int input_edge = c.o01.coincident[e] != 0 ? std::abs(c.o01.coincident[e]) - 1 : -1;
    // Rows: input-edge crossings directly; final-edge crossings between their neighbours among
    // the corners and input-edge crossings (one input face holds the stretch between those).
    std::vector<Row> rows(list.size());
    std::vector<double> s(list.size());
    for (std::size_t i = 0; i < list.size(); ++i) {
      const auto [is_b, j] = list[i];
      s[i] = is_b ? c.b_s[e][j] : c.a_s[e][j];
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
    // Homogeneous final coordinates of the input-edge crossings: on the final edge this Delaunay
    // edge is, or between the neighbouring corners and final-edge crossings.
    struct Known {
      double s;
      FinalFacePoint ahead, behind;
    };
    std::vector<Known> known;
    const int coincident_final = c.oT.coincident[e];
    if (coincident_final == 0) {
      auto corner_point = [&](std::pair<int, int> w, int v) {
        return FinalFacePoint{w.first, Vec3::Unit(w.second), -c.u[v]};
      };
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
    }
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
      const Known &k0 = known[next_known - 1], &k1 = known[next_known];
      if (k0.ahead.face != k1.behind.face) {
        internal_error("Delaunay edge " + std::to_string(e) + " leaves a final face unannounced");
      }
      const double fraction = k1.s > k0.s ? (s[i] - k0.s) / (k1.s - k0.s) : 0.0;
      c.in_final_face[gv] = homogeneous_lerp(k0.ahead.bary, k0.ahead.log_w, k1.behind.bary,
                                             k1.behind.log_w, fraction);
      c.in_final_face[gv].face = k0.ahead.face;
    }
  }

  // 6. Slice every Delaunay face; of a doubled surface keep the pieces of the front half.
  std::vector<Piece> pieces;
  for (int t = 0; t < nf1; ++t) slice_delaunay_face(c, t, pieces, result);
  // Refinement edges along each final edge, all of them and those kept (figures, step 9).
  std::vector<int> on_final_all(static_cast<std::size_t>(c.tp.num_edges), 0);
  for (const Piece& piece : pieces) {
    for (int hp : piece.final_halfedge) {
      if (hp >= 0 && hp == c.tp.edge_halfedges(c.tp.halfedge_edge[hp], 0)) {
        ++on_final_all[c.tp.halfedge_edge[hp]];
      }
    }
  }
  pieces.erase(std::remove_if(pieces.begin(), pieces.end(),
                              [front](const Piece& p) { return p.input_face >= front; }),
               pieces.end());
  const int nt = static_cast<int>(pieces.size());

  // 7. Vertices (the mesh's, then the crossing points the pieces use, in the order they were
  // made), positions and the interpolation matrix.
  std::vector<int> out_index(static_cast<std::size_t>(nv) + c.rows.size(), -1);
  for (int v = 0; v < nv_out; ++v) out_index[v] = v;
  for (Piece& piece : pieces) {
    for (int v : piece.vertex) {
      if (v >= nv_out && v < nv) internal_error("a front piece uses a mirror vertex");
      if (v >= nv) out_index[v] = 0;  // used; numbered below
    }
  }
  std::vector<int> raw_of;  // output vertex -> raw index
  raw_of.reserve(out_index.size());
  for (int v = 0; v < nv_out; ++v) raw_of.push_back(v);
  for (int r = nv; r < static_cast<int>(out_index.size()); ++r) {
    if (out_index[r] < 0) continue;
    out_index[r] = static_cast<int>(raw_of.size());
    raw_of.push_back(r);
    const char kind = c.kind[r - nv];
    ++(kind == 0   ? result.input_delaunay_points
       : kind == 1 ? result.delaunay_intrinsic_points
                   : result.interior_points);
  }
  for (Piece& piece : pieces) {
    for (int& v : piece.vertex) v = out_index[v];
  }
  const int nr = static_cast<int>(raw_of.size());
  auto row_of = [&](int out) -> const Row& { return c.rows[raw_of[out] - nv]; };
  result.positions.resize(nr, 3);
  result.positions.topRows(nv_out) = param.mesh.positions;
  for (int r = nv_out; r < nr; ++r) {
    Eigen::RowVector3d p = Eigen::RowVector3d::Zero();
    for (const auto& [v, w] : row_of(r)) p += w * mesh.positions.row(v);
    result.positions.row(r) = p;
  }
  if (options.interpolation_matrix) {
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(nv_out);
    for (int v = 0; v < nv_out; ++v) triplets.emplace_back(v, v, 1.0);
    for (int r = nv_out; r < nr; ++r) {
      for (const auto& [v, w] : row_of(r)) {
        if (v >= nv_out) internal_error("a front point leans on a mirror vertex");
        if (w != 0) triplets.emplace_back(r, v, w);
      }
    }
    result.interpolation.resize(nr, nv_out);
    result.interpolation.setFromTriplets(triplets.begin(), triplets.end());
  }
  result.input_vertex.resize(nv_out);
  for (int v = 0; v < nv_out; ++v) result.input_vertex[v] = v;
  // Input edges of the surface flowed -> the mesh's (the front faces' halfedges are the mesh's).
  const Topology mesh_topology = build_topology(param.mesh.triangles, nv_out);
  std::vector<int> mesh_edge(static_cast<std::size_t>(c.t0.num_edges), -1);
  for (int h = 0; h < 3 * front; ++h)
    mesh_edge[c.t0.halfedge_edge[h]] = mesh_topology.halfedge_edge[h];
  result.triangles.resize(nt, 3);
  result.input_face.resize(nt);
  result.delaunay_face.resize(nt);
  result.intrinsic_face.resize(nt);
  result.delaunay_barycentric.resize(3 * nt, 3);
  result.intrinsic_barycentric.resize(3 * nt, 3);
  for (int p = 0; p < nt; ++p) {
    const Piece& piece = pieces[p];
    for (int k = 0; k < 3; ++k) {
      result.triangles(p, k) = piece.vertex[k];
      result.delaunay_barycentric.row(3 * p + k) = piece.delaunay_bary[k].transpose();
      result.intrinsic_barycentric.row(3 * p + k) = piece.final_bary[k].transpose();
    }
    result.input_face[p] = piece.input_face;
    result.delaunay_face[p] = piece.delaunay_face;
    result.intrinsic_face[p] = piece.final_face;
  }

  // 8. Texture coordinates, input face by input face: its pieces laid out in the final metric
  // (rigid motions across the final edges inside it), fitted onto its corners in the layout.
  std::vector<std::array<int, 2>> edge_pieces(static_cast<std::size_t>(c.num_edge_ids), {-1, -1});
  for (int p = 0; p < nt; ++p) {
    for (int k = 0; k < 3; ++k) {
      auto& slot = edge_pieces[pieces[p].edge_id[k]];
      (slot[0] < 0 ? slot[0] : slot[1]) = 3 * p + k;
    }
  }
  std::vector<std::vector<int>> by_face(static_cast<std::size_t>(front));
  for (int p = 0; p < nt; ++p) by_face[pieces[p].input_face].push_back(p);
  auto final_position = [&](const Piece& piece, int k) {
    const auto& shape = c.final_shapes[piece.final_face];
    const Vec3& b = piece.final_bary[k];
    return b[0] * shape[0] + b[1] * shape[1] + b[2] * shape[2];
  };
  auto halfedge_ends = [&](int g, int h) {
    const auto& shape = c.final_shapes[g];
    return std::pair<Complex, Complex>{shape[(h % 3 + 1) % 3], shape[(h % 3 + 2) % 3]};
  };
  std::vector<Rigid> motion(static_cast<std::size_t>(nt));
  std::vector<char> placed(static_cast<std::size_t>(nt), 0);
  std::vector<std::array<Complex, 3>> corner_uv(static_cast<std::size_t>(nt));
  for (int f = 0; f < front; ++f) {
    const auto& list = by_face[f];
    if (list.empty()) internal_error("input face " + std::to_string(f) + " has no pieces");
    std::vector<int> queue{list.front()};
    placed[list.front()] = 1;
    motion[list.front()] = {};
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const int p = queue[head];
      for (int k = 0; k < 3; ++k) {
        if (pieces[p].input_edge[k] >= 0) continue;
        const auto& slot = edge_pieces[pieces[p].edge_id[k]];
        const int other = slot[0] == 3 * p + k ? slot[1] : slot[0];
        if (other < 0 || placed[other / 3]) continue;
        const int q = other / 3, kq = other % 3;
        const int hp = pieces[p].final_halfedge[k], hq = pieces[q].final_halfedge[kq];
        if (hp >= 0) {
          if (hq < 0 || c.tp.halfedge_twin[hp] != hq) internal_error("final edge sides disagree");
          const auto [p_tail, p_head] = halfedge_ends(pieces[p].final_face, hp);
          const auto [q_tail, q_head] = halfedge_ends(pieces[q].final_face, hq);
          motion[q] = compose(motion[p], segment_motion(q_tail, q_head, p_head, p_tail));
        } else {
          if (pieces[q].final_face != pieces[p].final_face) {
            internal_error("pieces of two final faces meet off a final edge");
          }
          motion[q] = motion[p];
        }
        placed[q] = 1;
        queue.push_back(q);
      }
    }
    if (queue.size() != list.size()) {
      internal_error("the pieces of input face " + std::to_string(f) + " are not connected");
    }
    // Fit: the developed corners onto the layout's.
    std::array<Complex, 3> developed{}, target{};
    std::array<int, 3> found{0, 0, 0};
    for (int p : list) {
      for (int k = 0; k < 3; ++k) {
        const int v = pieces[p].vertex[k];
        for (int j = 0; j < 3; ++j) {
          if (v == c.t0.triangles(f, j) && !found[j]) {
            developed[j] = motion[p](final_position(pieces[p], k));
            found[j] = 1;
          }
        }
      }
    }
    double longest = 0;
    for (int j = 0; j < 3; ++j) {
      if (!found[j]) internal_error("input face " + std::to_string(f) + " misses a corner");
      const int cv = param.cut_mesh.triangles(f, j);
      target[j] = {exact_uv(cv, 0), exact_uv(cv, 1)};
    }
    for (int j = 0; j < 3; ++j)
      longest = std::max(longest, std::abs(target[(j + 1) % 3] - target[j]));
    const Complex cd = (developed[0] + developed[1] + developed[2]) / 3.0;
    const Complex ct = (target[0] + target[1] + target[2]) / 3.0;
    Complex rot = 0;
    for (int j = 0; j < 3; ++j) rot += std::conj(developed[j] - cd) * (target[j] - ct);
    rot = std::abs(rot) > 0 ? rot / std::abs(rot) : Complex(1);
    const Rigid fit{rot, ct - rot * cd};
    for (int j = 0; j < 3; ++j) {
      result.max_corner_mismatch =
          std::max(result.max_corner_mismatch, std::abs(fit(developed[j]) - target[j]) / longest);
    }
    for (int p : list) {
      for (int k = 0; k < 3; ++k) corner_uv[p][k] = fit(motion[p](final_position(pieces[p], k)));
    }
  }
  // Indices: the input vertices' copies are the layout's; points on a cut input edge get one
  // copy per side; others one.
  const int base = static_cast<int>(param.uv.rows());
  std::vector<Eigen::Vector2d> extra;
  std::unordered_map<long long, int> key_index;
  result.uv_triangles.resize(nt, 3);
  for (int f = 0; f < front; ++f) {
    for (int p : by_face[f]) {
      for (int k = 0; k < 3; ++k) {
        const int v = pieces[p].vertex[k];
        if (v < nv_out) {
          int j = 0;
          while (j < 3 && c.t0.triangles(f, j) != v) ++j;
          result.uv_triangles(p, k) = param.cut_mesh.triangles(f, j);
          continue;
        }
        const int ie =
            c.on_input_edge[raw_of[v] - nv] < 0 ? -1 : mesh_edge[c.on_input_edge[raw_of[v] - nv]];
        const bool seam = ie >= 0 && !param.cut.is_cut_edge.empty() && param.cut.is_cut_edge[ie];
        const long long key = static_cast<long long>(v) * (front + 1) + (seam ? f + 1 : 0);
        auto [it, inserted] = key_index.emplace(key, base + static_cast<int>(extra.size()));
        if (inserted) {
          const Complex z = corner_uv[p][k];
          extra.emplace_back((Eigen::Vector2d(z.real(), z.imag()) - param.uv_offset) *
                             param.uv_scale);
        }
        result.uv_triangles(p, k) = it->second;
      }
    }
  }
  result.uv.resize(base + static_cast<int>(extra.size()), 2);
  if (polished) {
    result.uv.topRows(base) = (exact_uv.rowwise() - param.uv_offset.transpose()) * param.uv_scale;
  } else {
    result.uv.topRows(base) = param.uv;
  }
  for (std::size_t i = 0; i < extra.size(); ++i)
    result.uv.row(base + static_cast<int>(i)) = extra[i].transpose();
  result.projective_uv.resize(3 * nt, 3);
  for (int p = 0; p < nt; ++p) {
    const auto& lw = pieces[p].log_w;
    const double top = std::max({lw[0], lw[1], lw[2]});
    for (int k = 0; k < 3; ++k) {
      const double w = std::exp(lw[k] - top);
      const auto uv = result.uv.row(result.uv_triangles(p, k));
      result.projective_uv.row(3 * p + k) << w * uv[0], w * uv[1], w;
    }
  }

  // 9. Figures.
  std::vector<double> along(static_cast<std::size_t>(c.tp.num_edges), 0.0);
  std::vector<int> on_final_kept(static_cast<std::size_t>(c.tp.num_edges), 0);
  for (int p = 0; p < nt; ++p) {
    const Eigen::RowVector3d a = result.positions.row(result.triangles(p, 0));
    const Eigen::RowVector3d b = result.positions.row(result.triangles(p, 1));
    const Eigen::RowVector3d d = result.positions.row(result.triangles(p, 2));
    const double longest =
        std::max({(b - a).squaredNorm(), (d - b).squaredNorm(), (a - d).squaredNorm()});
    const double area = (b - a).cross(d - a).norm();
    const auto u0 = result.uv.row(result.uv_triangles(p, 0));
    const auto u1 = result.uv.row(result.uv_triangles(p, 1));
    const auto u2 = result.uv.row(result.uv_triangles(p, 2));
    const double uv_area = (u1[0] - u0[0]) * (u2[1] - u0[1]) - (u2[0] - u0[0]) * (u1[1] - u0[1]);
    if (area <= 1e-14 * longest) {
      ++result.degenerate_triangles;
    } else if (uv_area <= 0) {
      ++result.inverted_triangles;
    }
    for (int k = 0; k < 3; ++k) {
      const int hp = pieces[p].final_halfedge[k];
      if (hp < 0) continue;
      const int ep = c.tp.halfedge_edge[hp];
      if (hp != c.tp.edge_halfedges(ep, 0)) continue;
      ++on_final_kept[ep];
      along[ep] += (result.uv.row(result.uv_triangles(p, (k + 1) % 3)) -
                    result.uv.row(result.uv_triangles(p, (k + 2) % 3)))
                       .norm() /
                   param.uv_scale;
    }
  }
  for (int e = 0; e < c.tp.num_edges; ++e) {
    // Final edges of a doubled surface that reach into the mirror half are not all laid out.
    if (on_final_kept[e] != on_final_all[e]) continue;
    result.max_intrinsic_length_error =
        std::max(result.max_intrinsic_length_error,
                 std::abs(along[e] - final_lengths[e]) / final_lengths[e]);
  }
  result.delaunay_topology = std::move(c.t1);
  result.delaunay_lengths = std::move(c.l1);
  result.seconds = std::chrono::duration<double>(Clock::now() - started).count();
  return result;
}

}  // namespace ricci
