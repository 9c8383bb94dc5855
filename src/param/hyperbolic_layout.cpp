#include "ricci/param/hyperbolic_layout.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>

#include "layout_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/metric/angles.hpp"

namespace ricci {

namespace {

using Complex = std::complex<double>;

double cross(Complex a, Complex b) {
  return a.real() * b.imag() - a.imag() * b.real();
}

/// The deck transformation of one segment, fitted at two of its vertices far apart (the first
/// and the one farthest from it), checked at every end of its edges.
SegmentIsometry fit_segment(const Topology& topology, const Topology& cut_topology,
                            const Eigen::VectorXd& lengths, const std::vector<Complex>& uv,
                            const layout_support::SegmentEdges& segments, int s) {
  SegmentIsometry result;
  result.segment = s;
  const std::vector<int>& edges = segments.segment_edges[s];
  if (!edges.empty()) result.edge = edges.front();
  std::vector<Complex> from, to;
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
    if (disk_distance(from[0], from[i]) > disk_distance(from[0], from[far])) far = i;
  }
  result.map = disk_isometry(from[0], from[far], to[0], to[far]);
  for (std::size_t i = 0; i < from.size(); ++i) {
    result.mismatch =
        std::max(result.mismatch, disk_distance(apply_mobius(result.map, from[i]), to[i]) / scale[i]);
  }
  result.translation_length = translation_length(result.map);
  return result;
}

}  // namespace

HyperbolicLayout layout_hyperbolic(const Topology& topology, const Eigen::VectorXd& lengths,
                                   const CutGraph& cut, const CutMesh& cut_mesh,
                                   const HyperbolicLayoutOptions& options) {
  layout_support::check_inputs("layout_hyperbolic", topology, lengths, cut, cut_mesh,
                               options.root_face);
  const Topology& cut_topology = cut_mesh.topology;
  const int nf = topology.num_faces;
  const int ncv = cut_topology.num_vertices;
  CornerAngles angles;
  const int bad = corner_angles(topology, lengths, angles, Geometry::Hyperbolic);
  if (bad >= 0) {
    throw InvalidInput("layout_hyperbolic: face " + std::to_string(bad) + ": its lengths " +
                       std::to_string(lengths[topology.face_edges(bad, 0)]) + ", " +
                       std::to_string(lengths[topology.face_edges(bad, 1)]) + ", " +
                       std::to_string(lengths[topology.face_edges(bad, 2)]) +
                       " break a triangle inequality");
  }

  HyperbolicLayout layout;
  const std::vector<int> roots =
      layout_support::root_faces(cut_topology, options.root_face, layout.root_face);
  std::vector<Complex> uv(ncv, Complex{0});
  // A point at hyperbolic distance l from the centre is at Euclidean radius tanh(l / 2).
  for (int root : roots) {
    uv[cut_topology.triangles(root, 0)] = 0;
    uv[cut_topology.triangles(root, 1)] = std::tanh(0.5 * lengths[topology.face_edges(root, 2)]);
    uv[cut_topology.triangles(root, 2)] =
        std::polar(std::tanh(0.5 * lengths[topology.face_edges(root, 1)]), angles(root, 0));
  }
  for (int t : layout_support::placement_order(topology, cut_topology, lengths, roots)) {
    const int g = t / 3, kg = t % 3, ki = (kg + 1) % 3;
    const int vi = cut_topology.triangles(g, ki), vj = cut_topology.triangles(g, (kg + 2) % 3);
    // In the frame where p_i is the centre, p_k is at tanh(l_ik / 2) in the direction of p_j
    // turned by theta_i counter-clockwise.
    const Mobius to_frame = translation_to_origin(uv[vi]);
    const Complex j_in_frame = apply_mobius(to_frame, uv[vj]);
    const Complex k_in_frame =
        std::polar(std::tanh(0.5 * lengths[topology.face_edges(g, (kg + 2) % 3)]),
                   std::arg(j_in_frame) + angles(g, ki));
    uv[cut_topology.triangles(g, kg)] = apply_mobius(inverse(to_frame), k_in_frame);
  }

  layout.uv.resize(ncv, 2);
  for (int v = 0; v < ncv; ++v) {
    layout.uv(v, 0) = uv[v].real();
    layout.uv(v, 1) = uv[v].imag();
    if (cut_topology.vertex_component[v] >= 0) {
      layout.max_radius = std::max(layout.max_radius, std::abs(uv[v]));
    }
  }
  for (int f = 0; f < nf; ++f) {
    Complex p[3];
    for (int k = 0; k < 3; ++k) p[k] = uv[cut_topology.triangles(f, k)];
    for (int k = 0; k < 3; ++k) {
      const double l = lengths[topology.face_edges(f, k)];
      const double d = disk_distance(p[(k + 1) % 3], p[(k + 2) % 3]);
      layout.max_length_relative_error =
          std::max(layout.max_length_relative_error, std::abs(d - l) / l);
    }
    // Geodesic triangles are convex: their orientation is that of the straight one.
    if (!(cross(p[1] - p[0], p[2] - p[0]) > 0)) ++layout.num_flipped_faces;
  }

  if (cut.is_cut_edge.empty()) return layout;
  const layout_support::SegmentEdges segments =
      layout_support::segment_edges("layout_hyperbolic", topology, cut);
  for (std::size_t s = 0; s < cut.segments.size(); ++s) {
    layout.segment_maps.push_back(
        fit_segment(topology, cut_topology, lengths, uv, segments, static_cast<int>(s)));
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

}  // namespace ricci
