#include "ricci/param/atlas/atlas.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "ricci/errors.hpp"

namespace ricci {

namespace {

using Complex = std::complex<double>;

/// Faces around each vertex of a mesh in compressed rows: the faces of vertex v are
/// face[start[v]] .. face[start[v + 1] - 1], each with the corner of v in it.
struct VertexFaces {
  std::vector<int> start, face, corner;
};

VertexFaces vertex_faces(const Topology& topology) {
  VertexFaces vf;
  vf.start.assign(topology.num_vertices + 1, 0);
  for (int f = 0; f < topology.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) ++vf.start[topology.triangles(f, k) + 1];
  }
  for (int v = 0; v < topology.num_vertices; ++v) vf.start[v + 1] += vf.start[v];
  vf.face.resize(3 * topology.num_faces);
  vf.corner.resize(3 * topology.num_faces);
  std::vector<int> fill(vf.start.begin(), vf.start.end() - 1);
  for (int f = 0; f < topology.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int slot = fill[topology.triangles(f, k)]++;
      vf.face[slot] = f;
      vf.corner[slot] = k;
    }
  }
  return vf;
}

/// The halfedge running v -> w, or -1 when v and w share no edge.
int halfedge_between(const Topology& topology, const VertexFaces& vf, int v, int w) {
  for (int slot = vf.start[v]; slot < vf.start[v + 1]; ++slot) {
    // In face f the corner k of v is the tail of halfedge 3 f + (k + 2) % 3.
    const int h = 3 * vf.face[slot] + (vf.corner[slot] + 2) % 3;
    if (topology.head(h) == w) return h;
  }
  return -1;
}

Complex uv_of(const Layout& layout, int v) {
  return {layout.uv(v, 0), layout.uv(v, 1)};
}

/// The faces a segment's chart takes, each once, with its side (0: A, 1: B): per face the last
/// segment that took it, so that one pass per segment needs no clearing.
struct SegmentFaces {
  std::vector<int>& stamp;
  int segment;
  std::vector<std::pair<int, char>> faces;  // (face, side)
  void take(int f, char side) {
    if (stamp[f] == segment) return;
    stamp[f] = segment;
    faces.emplace_back(f, side);
  }
};

/// Per vertex: its cut-mesh copies on the two sides of the segment being charted.
struct SideCopies {
  std::vector<int> a, b;
};

/// Per edge of segment s (path): its (side-A, side-B) halfedges. Side A is the side of
/// edge_halfedges(e, 0) of the first edge, the same side of the path for the others (as
/// layout_flat fits the segment's transition). The faces along the path are taken, and the
/// copies of the edges' ends on each side written.
/// \throw InvalidInput when the path steps across no interior edge
std::vector<std::pair<int, int>> segment_sides(const Topology& topology,
                                               const Topology& cut_topology, const VertexFaces& vf,
                                               const std::vector<int>& path, std::size_t s,
                                               SegmentFaces& faces, SideCopies& copies) {
  bool side_a_is_left = true;
  std::vector<std::pair<int, int>> sides;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const int forward = halfedge_between(topology, vf, path[i], path[i + 1]);
    const int backward = halfedge_between(topology, vf, path[i + 1], path[i]);
    if (forward < 0 || backward < 0) {
      throw InvalidInput("affine_atlas: segment " + std::to_string(s) + " steps from vertex " +
                         std::to_string(path[i]) + " to " + std::to_string(path[i + 1]) +
                         " across no interior edge");
    }
    if (i == 0) {
      side_a_is_left = topology.edge_halfedges(topology.halfedge_edge[forward], 0) == forward;
    }
    const int ha = side_a_is_left ? forward : backward, hb = side_a_is_left ? backward : forward;
    sides.emplace_back(ha, hb);
    faces.take(ha / 3, 0);
    faces.take(hb / 3, 1);
    copies.a[topology.tail(ha)] = cut_topology.tail(ha);
    copies.a[topology.head(ha)] = cut_topology.head(ha);
    copies.b[topology.tail(hb)] = cut_topology.tail(hb);
    copies.b[topology.head(hb)] = cut_topology.head(hb);
  }
  return sides;
}

/// Takes the one-rings of the segment's vertices that are not nodes: each has exactly two copies
/// in the cut mesh (two cut edges, no boundary edge), one per side, and a face's side is the copy
/// its corner uses.
/// \throw InvalidInput for such a vertex with another copy
void take_one_rings(const Topology& cut_topology, const VertexFaces& vf,
                    const std::vector<char>& is_node, const std::vector<int>& path, std::size_t s,
                    const SideCopies& copies, SegmentFaces& faces) {
  const bool closed = path.size() > 1 && path.front() == path.back();
  for (std::size_t i = 0; i < path.size(); ++i) {
    const int v = path[i];
    const bool end = i == 0 || i + 1 == path.size();
    if (is_node[v] || (end && !closed)) continue;
    for (int slot = vf.start[v]; slot < vf.start[v + 1]; ++slot) {
      const int f = vf.face[slot];
      const int copy = cut_topology.triangles(f, vf.corner[slot]);
      if (copy == copies.a[v]) {
        faces.take(f, 0);
      } else if (copy == copies.b[v]) {
        faces.take(f, 1);
      } else {
        throw InvalidInput("affine_atlas: vertex " + std::to_string(v) + " of segment " +
                           std::to_string(s) +
                           " has more than two copies in the cut mesh but is no node");
      }
    }
  }
}

/// The chart's faces (sorted), sides and corner uvs, side B moved by the transition.
void fill_chart_faces(const Topology& cut_topology, const Layout& layout,
                      std::vector<std::pair<int, char>> faces, BoundaryChart& chart) {
  std::sort(faces.begin(), faces.end());
  chart.faces.reserve(faces.size());
  chart.side.reserve(faces.size());
  chart.corner_uv.resize(static_cast<Eigen::Index>(faces.size()), 6);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const auto [f, side] = faces[i];
    chart.faces.push_back(f);
    chart.side.push_back(side);
    for (int k = 0; k < 3; ++k) {
      Complex z = uv_of(layout, cut_topology.triangles(f, k));
      if (side == 1) z = chart.rotation * z + chart.translation;
      chart.corner_uv(static_cast<Eigen::Index>(i), 2 * k) = z.real();
      chart.corner_uv(static_cast<Eigen::Index>(i), 2 * k + 1) = z.imag();
    }
  }
}

/// How well the two sides meet: each end of each segment edge, side B moved by the transition
/// against side A, relative to the edge's length in the layout; the largest.
double max_seam_gap(const Topology& cut_topology, const Layout& layout,
                    const std::vector<std::pair<int, int>>& sides, const BoundaryChart& chart) {
  double max_gap = chart.max_gap;
  for (const auto& [ha, hb] : sides) {
    const Complex a0 = uv_of(layout, cut_topology.tail(ha)),
                  a1 = uv_of(layout, cut_topology.head(ha));
    const Complex b0 = uv_of(layout, cut_topology.head(hb)),
                  b1 = uv_of(layout, cut_topology.tail(hb));
    const double length = std::abs(a1 - a0);
    const double gap = std::max(std::abs(chart.rotation * b0 + chart.translation - a0),
                                std::abs(chart.rotation * b1 + chart.translation - a1));
    max_gap = std::max(max_gap, gap / length);
  }
  return max_gap;
}

}  // namespace

AffineAtlas affine_atlas(const Topology& topology, const CutGraph& cut, const CutMesh& cut_mesh,
                         const Layout& layout) {
  if (layout.segment_transitions.size() != cut.segments.size()) {
    throw InvalidInput(
        "affine_atlas: the layout has " + std::to_string(layout.segment_transitions.size()) +
        " segment transitions for " + std::to_string(cut.segments.size()) + " cut segments");
  }
  if (cut_mesh.triangles.rows() != topology.num_faces ||
      layout.uv.rows() != cut_mesh.topology.num_vertices) {
    throw InvalidInput("affine_atlas: the cut mesh or the layout does not match the mesh");
  }
  const Topology& cut_topology = cut_mesh.topology;
  const VertexFaces vf = vertex_faces(topology);
  std::vector<char> is_node(topology.num_vertices, 0);
  for (int v : cut.nodes) {
    if (v >= 0 && v < topology.num_vertices) is_node[v] = 1;
  }

  AffineAtlas atlas;
  SideCopies copies{std::vector<int>(topology.num_vertices, -1),
                    std::vector<int>(topology.num_vertices, -1)};
  std::vector<int> face_stamp(topology.num_faces, -1);
  for (std::size_t s = 0; s < cut.segments.size(); ++s) {
    const std::vector<int>& path = cut.segments[s];
    const SeamTransition& transition = layout.segment_transitions[s];
    BoundaryChart chart;
    chart.segment = static_cast<int>(s);
    chart.rotation = transition.rotation;
    chart.translation = transition.translation;
    SegmentFaces faces{face_stamp, static_cast<int>(s), {}};
    const std::vector<std::pair<int, int>> sides =
        segment_sides(topology, cut_topology, vf, path, s, faces, copies);
    take_one_rings(cut_topology, vf, is_node, path, s, copies, faces);
    fill_chart_faces(cut_topology, layout, std::move(faces.faces), chart);
    chart.max_gap = max_seam_gap(cut_topology, layout, sides, chart);
    atlas.max_transition_error = std::max(atlas.max_transition_error, chart.max_gap);
    atlas.boundary_charts.push_back(std::move(chart));
  }
  return atlas;
}

}  // namespace ricci
