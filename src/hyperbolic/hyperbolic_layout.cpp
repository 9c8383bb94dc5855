#include "ricci/hyperbolic/hyperbolic_layout.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>

#include "param/layout/detail/layout_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/hyperbolic/hyperbolic_refinement.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/numerics/mobius.hpp"

namespace ricci {

namespace {

// Positions and deck transformations are computed in long double: near the rim of the disk
// (|z| = 0.998 on the shared genus-4 mesh) 1 - conj(p) z cancels to 1e-3 and a double layout
// loses three digits there, which the Fuchsian relation amplifies through long words.
using Wide = long double;
using WideComplex = std::complex<Wide>;

/// The recentring stops when the area-weighted centre is this close to the origin: far below
/// double resolution of the positions it moves (and the layout has converged long before).
constexpr Wide kCentred = 1e-12;  // the double 1e-12, widened

/// The orientation-preserving isometry taking z1 to w1 and the direction towards z2 to the
/// direction towards w2, in long double (the directions compared in the frames of z1 and w1).
WideMobius wide_isometry(WideComplex z1, WideComplex z2, WideComplex w1, WideComplex w2) {
  const Wide turn = std::arg(to_frame(w1, w2)) - std::arg(to_frame(z1, z2));
  WideMobius back = translation_to_origin<Wide>(w1);
  // Its inverse: a is real, so only b changes sign (inverse() would also conjugate a, turning
  // its imaginary 0 into -0).
  back.b = -back.b;
  return compose(back, compose(rotation<Wide>(turn), translation_to_origin<Wide>(z1)));
}

/// The deck transformation of one segment, fitted at two of its vertices far apart (the first
/// and the one farthest from it), checked at every end of its edges.
SegmentIsometry fit_segment(const Topology& topology, const Topology& cut_topology,
                            const Eigen::VectorXd& lengths, const std::vector<WideComplex>& uv,
                            const layout_support::SegmentEdges& segments, int s) {
  SegmentIsometry result;
  result.segment = s;
  const std::vector<int>& edges = segments.segment_edges[s];
  if (!edges.empty()) result.edge = edges.front();
  std::vector<WideComplex> from, to;
  std::vector<double> scale;
  for (int e : edges) {
    const int ha = segments.side_a_halfedge[e];
    if (ha < 0) continue;
    const int hb = topology.halfedge_twin[ha];
    // The same original vertex seen from both sides: tail(ha) = head(hb), head(ha) = tail(hb).
    from.insert(from.end(), {uv[cut_topology.head(hb)], uv[cut_topology.tail(hb)]});
    to.insert(to.end(), {uv[cut_topology.tail(ha)], uv[cut_topology.head(ha)]});
    scale.insert(scale.end(), {lengths[e], lengths[e]});
  }
  if (from.empty()) return result;
  std::size_t far = 1;
  for (std::size_t i = 1; i < from.size(); ++i) {
    if (std::abs(to_frame(from[0], from[i])) > std::abs(to_frame(from[0], from[far]))) far = i;
  }
  const WideMobius map = wide_isometry(from[0], from[far], to[0], to[far]);
  result.wide_map = map;
  // Normalised in long double before rounding to double: far out in the disk (high genus) |a|
  // and |b| agree to more digits than double has, so the determinant of the rounded map is
  // noise (0 or negative) and normalizing it there would fail.
  const Wide det = determinant(map);
  const WideMobius unit = det > 0 && std::isfinite(det) ? normalized(map) : map;
  result.map = mobius_cast<double>(unit);
  for (std::size_t i = 0; i < from.size(); ++i) {
    // Hyperbolic distance 2 atanh(|to_frame(a, b)|) of the image from its target.
    const Wide d = 2 * std::atanh(std::abs(to_frame(to[i], apply_mobius(map, from[i]))));
    result.mismatch = std::max(result.mismatch, static_cast<double>(d) / scale[i]);
  }
  // From the long double map, for the reason above.
  const Wide half_trace = std::abs(unit.a.real());
  result.translation_length =
      half_trace > 1 ? static_cast<double>(2 * std::acosh(half_trace)) : 0.0;
  return result;
}

/// The layout proper, from each edge's length and each corner's signed angle (angle(f, k) turns
/// the direction from corner k to corner k + 1 into the direction to corner k + 2; negative on a
/// face whose shape is reversed). \pre check_inputs passed
HyperbolicLayout layout_from_angles(const Topology& topology, const WideVector& lengths,
                                    const WideAngles& angles, const CutGraph& cut,
                                    const CutMesh& cut_mesh,
                                    const HyperbolicLayoutOptions& options) {
  const Eigen::VectorXd double_lengths = lengths.cast<double>();
  const Topology& cut_topology = cut_mesh.topology;
  const int nf = topology.num_faces;
  const int ncv = cut_topology.num_vertices;

  HyperbolicLayout layout;
  const std::vector<int> roots =
      layout_support::root_faces(cut_topology, options.root_face, layout.root_face);
  std::vector<WideComplex> uv(ncv, WideComplex{0});
  // A point at hyperbolic distance l from the centre is at Euclidean radius tanh(l / 2).
  auto radius = [&](int e) { return std::tanh(lengths[e] / 2); };
  for (int root : roots) {
    uv[cut_topology.triangles(root, 0)] = 0;
    uv[cut_topology.triangles(root, 1)] = radius(topology.face_edges(root, 2));
    uv[cut_topology.triangles(root, 2)] =
        std::polar(radius(topology.face_edges(root, 1)), angles(root, 0));
  }
  for (int t : layout_support::placement_order(topology, cut_topology, double_lengths, roots)) {
    const int g = t / 3, kg = t % 3, ki = (kg + 1) % 3;
    const int vi = cut_topology.triangles(g, ki), vj = cut_topology.triangles(g, (kg + 2) % 3);
    // In the frame where p_i is the centre, p_k is at tanh(l_ik / 2) in the direction of p_j
    // turned by theta_i counter-clockwise.
    const WideComplex k_in_frame = std::polar(radius(topology.face_edges(g, (kg + 2) % 3)),
                                              std::arg(to_frame(uv[vi], uv[vj])) + angles(g, ki));
    uv[cut_topology.triangles(g, kg)] = from_frame(uv[vi], k_in_frame);
  }
  if (options.recentre) {
    // Hyperbolic area (pi - angle sum) of every face: its weight in the centre.
    std::vector<Wide> area(nf);
    for (int f = 0; f < nf; ++f) {
      area[f] = std::numbers::pi_v<Wide> -
                (std::abs(angles(f, 0)) + std::abs(angles(f, 1)) + std::abs(angles(f, 2)));
    }
    for (int step = 0; step < 8; ++step) {
      WideComplex centre{0};
      Wide total = 0;
      for (int f = 0; f < nf; ++f) {
        const WideComplex c = (uv[cut_topology.triangles(f, 0)] + uv[cut_topology.triangles(f, 1)] +
                               uv[cut_topology.triangles(f, 2)]) /
                              Wide{3};
        centre += area[f] * c;
        total += area[f];
      }
      if (!(total > 0)) break;
      centre /= total;
      if (std::abs(centre) < kCentred) break;
      for (int v = 0; v < ncv; ++v) {
        if (cut_topology.vertex_component[v] >= 0) uv[v] = to_frame(centre, uv[v]);
      }
    }
  }

  for (int v = 0; v < ncv; ++v) {
    if (cut_topology.vertex_component[v] >= 0 && !(std::abs(uv[v]) < 1)) {
      // 1 - |z| of a point at hyperbolic distance d from the centre is about 2 e^-d: past
      // d ~ 44 long double cannot tell the point from the circle (a generated genus-50 plate:
      // its handles in a row put the far end hundreds of units away).
      throw InvalidInput(
          "layout_hyperbolic: the fundamental domain reaches too far from its centre for the "
          "Poincare disk in long double (a point lands on or past the unit circle); the "
          "hyperbolic metric itself is fine, only its disk layout cannot be represented");
    }
  }
  layout.uv.resize(ncv, 2);
  for (int v = 0; v < ncv; ++v) {
    layout.uv(v, 0) = static_cast<double>(uv[v].real());
    layout.uv(v, 1) = static_cast<double>(uv[v].imag());
    if (cut_topology.vertex_component[v] >= 0) {
      layout.max_radius = std::max(layout.max_radius, static_cast<double>(std::abs(uv[v])));
    }
  }
  for (int f = 0; f < nf; ++f) {
    WideComplex p[3];
    for (int k = 0; k < 3; ++k) p[k] = uv[cut_topology.triangles(f, k)];
    for (int k = 0; k < 3; ++k) {
      const double l = double_lengths[topology.face_edges(f, k)];
      const double d =
          static_cast<double>(2 * std::atanh(std::abs(to_frame(p[(k + 1) % 3], p[(k + 2) % 3]))));
      layout.max_length_relative_error =
          std::max(layout.max_length_relative_error, std::abs(d - l) / l);
    }
    // Geodesic triangles are convex: their orientation is that of the straight one.
    const WideComplex e1 = p[1] - p[0], e2 = p[2] - p[0];
    if (!(e1.real() * e2.imag() - e1.imag() * e2.real() > 0)) ++layout.num_flipped_faces;
  }

  if (cut.is_cut_edge.empty()) return layout;
  const layout_support::SegmentEdges segments =
      layout_support::segment_edges("layout_hyperbolic", topology, cut);
  for (std::size_t s = 0; s < cut.segments.size(); ++s) {
    layout.segment_maps.push_back(
        fit_segment(topology, cut_topology, double_lengths, uv, segments, static_cast<int>(s)));
  }

  // Words around the nodes: rotate around the node through its faces (outgoing halfedge h of
  // face f -> the outgoing halfedge twin(prev(h)) of the next face), noting each cut edge crossed.
  std::vector<int> outgoing(topology.num_vertices, -1);
  for (int h = 0; h < 3 * nf; ++h) {
    if (outgoing[topology.tail(h)] < 0) outgoing[topology.tail(h)] = h;
  }
  layout.node_words.resize(cut.nodes.size());
  for (std::size_t n = 0; n < cut.nodes.size(); ++n) {
    const int v = cut.nodes[n];
    if (topology.is_boundary_vertex[v] || outgoing[v] < 0) continue;
    std::vector<std::pair<int, int>>& word = layout.node_words[n];
    const int start = outgoing[v];
    int h = start;
    do {
      const int crossing = Topology::prev(h);  // edge from face h / 3 to the next face
      const int e = topology.halfedge_edge[crossing];
      const int s = segments.edge_segment[e];
      if (s >= 0 && segments.side_a_halfedge[e] >= 0) {
        const bool from_side_a = segments.side_a_halfedge[e] / 3 == h / 3;
        word.emplace_back(s, from_side_a ? 1 : -1);
      }
      h = topology.halfedge_twin[crossing];
    } while (h != start && h >= 0);
  }
  return layout;
}

}  // namespace

HyperbolicLayout layout_hyperbolic(const Topology& topology, const Eigen::VectorXd& lengths,
                                   const CutGraph& cut, const CutMesh& cut_mesh,
                                   const HyperbolicLayoutOptions& options) {
  return layout_hyperbolic(topology, WideVector(lengths.cast<long double>()), cut, cut_mesh,
                           options);
}

HyperbolicLayout layout_hyperbolic(const Topology& topology, const WideVector& lengths,
                                   const CutGraph& cut, const CutMesh& cut_mesh,
                                   const HyperbolicLayoutOptions& options) {
  const Eigen::VectorXd double_lengths = lengths.cast<double>();
  layout_support::check_inputs("layout_hyperbolic", topology, double_lengths, cut, cut_mesh,
                               options.root_face);
  WideAngles angles;
  const int bad = hyperbolic_corner_angles_wide(topology, lengths, angles).first_bad_face;
  if (bad >= 0) {
    throw InvalidInput("layout_hyperbolic: face " + std::to_string(bad) + ": its lengths " +
                       std::to_string(double_lengths[topology.face_edges(bad, 0)]) + ", " +
                       std::to_string(double_lengths[topology.face_edges(bad, 1)]) + ", " +
                       std::to_string(double_lengths[topology.face_edges(bad, 2)]) +
                       " break a triangle inequality");
  }
  return layout_from_angles(topology, lengths, angles, cut, cut_mesh, options);
}

HyperbolicLayout layout_hyperbolic(const Topology& topology, const WideFaceShapes& shapes,
                                   const CutGraph& cut, const CutMesh& cut_mesh,
                                   const HyperbolicLayoutOptions& options) {
  if (shapes.size() != static_cast<std::size_t>(topology.num_faces)) {
    throw InvalidInput("layout_hyperbolic: " + std::to_string(shapes.size()) + " face shapes for " +
                       std::to_string(topology.num_faces) + " faces");
  }
  // Each edge's length as its first face sees it (its other face agrees up to rounding), and
  // each corner's signed angle: in the frame that moves the corner to the centre, geodesics
  // through it are straight.
  WideVector lengths(topology.num_edges);
  for (int e = 0; e < topology.num_edges; ++e) {
    const int h = topology.edge_halfedges(e, 0);
    const auto& p = shapes[h / 3];
    lengths[e] = 2 * std::atanh(std::abs(to_frame(p[(h % 3 + 1) % 3], p[(h % 3 + 2) % 3])));
  }
  layout_support::check_inputs("layout_hyperbolic", topology, lengths.cast<double>(), cut, cut_mesh,
                               options.root_face);
  WideAngles angles(topology.num_faces, 3);
  for (int f = 0; f < topology.num_faces; ++f) {
    const auto& p = shapes[f];
    for (int k = 0; k < 3; ++k) {
      angles(f, k) = std::arg(to_frame(p[k], p[(k + 2) % 3]) / to_frame(p[k], p[(k + 1) % 3]));
    }
  }
  return layout_from_angles(topology, lengths, angles, cut, cut_mesh, options);
}

}  // namespace ricci
