#include "param/layout/detail/layout_support.hpp"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <queue>
#include <unordered_map>
#include <utility>

#include "numerics/detail/parallel.hpp"
#include "ricci/errors.hpp"

namespace ricci::layout_support {

namespace {

/// Per component of the cut mesh, the face farthest from its boundary in steps across edges of
/// the dual graph (a multi-source breadth-first search from every face on the boundary): the
/// root of the layout tree, so that the tree is shallow and rounding errors accumulate over as
/// few placements as possible.
std::vector<int> central_faces(const Topology& cut_topology) {
  const int nf = cut_topology.num_faces;
  std::vector<int> queue;
  queue.reserve(nf);
  std::vector<char> seen(nf, 0);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      if (cut_topology.halfedge_twin[3 * f + k] < 0) {
        seen[f] = 1;
        queue.push_back(f);
        break;
      }
    }
  }
  std::vector<int> roots(cut_topology.components.size(), -1);
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const int f = queue[head];
    roots[cut_topology.face_component[f]] = f;  // breadth-first: the last one is the farthest
    for (int k = 0; k < 3; ++k) {
      const int t = cut_topology.halfedge_twin[3 * f + k];
      if (t >= 0 && !seen[t / 3]) {
        seen[t / 3] = 1;
        queue.push_back(t / 3);
      }
    }
  }
  for (std::size_t c = 0; c < roots.size(); ++c) {
    if (roots[c] < 0) roots[c] = cut_topology.components[c].faces.front();  // closed component
  }
  return roots;
}

}  // namespace

void check_inputs(const char* who, const Topology& topology, const Eigen::VectorXd& lengths,
                  const CutGraph& cut, const CutMesh& cut_mesh, int root_face) {
  const std::string name = std::string(who) + ": ";
  const int nf = topology.num_faces;
  if (lengths.size() != topology.num_edges) {
    throw InvalidInput(name + "" + std::to_string(lengths.size()) + " lengths for " +
                       std::to_string(topology.num_edges) + " edges");
  }
  if (!cut.is_cut_edge.empty() && static_cast<int>(cut.is_cut_edge.size()) != topology.num_edges) {
    throw InvalidInput(name + "the cut flags " + std::to_string(cut.is_cut_edge.size()) +
                       " edges, the mesh has " + std::to_string(topology.num_edges));
  }
  if (cut_mesh.triangles.rows() != nf || cut_mesh.topology.num_faces != nf) {
    throw InvalidInput(name + "the cut mesh has " + std::to_string(cut_mesh.triangles.rows()) +
                       " faces, the mesh " + std::to_string(nf));
  }
  const int ncv = cut_mesh.topology.num_vertices;
  if (static_cast<int>(cut_mesh.to_original.size()) != ncv) {
    throw InvalidInput(name + "the cut mesh maps " + std::to_string(cut_mesh.to_original.size()) +
                       " of its " + std::to_string(ncv) + " vertices to the mesh");
  }
  auto corners_differ = [&](std::int64_t f) {
    for (int k = 0; k < 3; ++k) {
      const int v = cut_mesh.topology.triangles(f, k);
      if (v < 0 || v >= ncv || cut_mesh.to_original[v] != topology.triangles(f, k)) return true;
    }
    return false;
  };
  // Counted in parallel (an exact count); the first such face is looked for only when one is.
  if (parallel::count_if(nf, corners_differ) > 0) {
    for (int f = 0; f < nf; ++f) {
      if (corners_differ(f)) {
        throw InvalidInput(name + "face " + std::to_string(f) +
                           ": the cut mesh's corners do not copy the mesh's");
      }
    }
  }
  for (const Component& c : cut_mesh.topology.components) {
    if (c.euler_characteristic != 1) {
      throw InvalidInput(name +
                         "the cut mesh is not a union of topological disks: its component with "
                         "face " +
                         std::to_string(c.faces.front()) +
                         " has chi = " + std::to_string(c.euler_characteristic) + " and " +
                         std::to_string(c.num_boundary_loops) + " boundary loops");
    }
  }
  if (root_face < -1 || root_face >= nf) {
    throw InvalidInput(name + "root face " + std::to_string(root_face) + " out of range [0, " +
                       std::to_string(nf) + ")");
  }
  for (std::size_t s = 0; s < cut.segments.size(); ++s) {
    for (int v : cut.segments[s]) {
      if (v < 0 || v >= topology.num_vertices) {
        throw InvalidInput(name + "segment " + std::to_string(s) + " names vertex " +
                           std::to_string(v) + ", out of range");
      }
    }
  }
}

std::vector<int> root_faces(const Topology& cut_topology, int root_face, int& first_root) {
  std::vector<int> roots = central_faces(cut_topology);
  first_root = -1;
  if (root_face >= 0) {
    roots[cut_topology.face_component[root_face]] = root_face;
    first_root = root_face;
  } else if (!roots.empty()) {
    first_root = roots.front();
  }
  return roots;
}

std::vector<int> placement_order(const Topology& topology, const Topology& cut_topology,
                                 const Eigen::VectorXd& lengths, const std::vector<int>& roots) {
  const int nf = topology.num_faces;
  const int ncv = cut_topology.num_vertices;
  std::vector<int> order;
  std::vector<char> placed(ncv, 0);
  std::vector<char> expanded(nf, 0);
  std::vector<double> magnification(ncv, 0.0);
  // Vertex -> faces of the cut mesh, compressed rows.
  std::vector<int> corner_start(ncv + 1, 0), corner_face(3 * static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) ++corner_start[cut_topology.triangles(f, k) + 1];
  }
  for (int v = 0; v < ncv; ++v) corner_start[v + 1] += corner_start[v];
  {
    std::vector<int> fill(corner_start.begin(), corner_start.end() - 1);
    for (int f = 0; f < nf; ++f) {
      for (int k = 0; k < 3; ++k) corner_face[fill[cut_topology.triangles(f, k)]++] = f;
    }
  }
  using Candidate = std::pair<double, int>;  // (error growth, halfedge of the target face)
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<>> candidates;
  auto expand = [&](int f) {
    if (expanded[f]) return;
    expanded[f] = 1;
    for (int k = 0; k < 3; ++k) {
      const int t = cut_topology.halfedge_twin[3 * f + k];
      if (t < 0) continue;
      const int g = t / 3, kg = t % 3;
      if (placed[cut_topology.triangles(g, kg)]) continue;
      const int vi = cut_topology.triangles(g, (kg + 1) % 3);
      const int vj = cut_topology.triangles(g, (kg + 2) % 3);
      const double base = lengths[topology.face_edges(g, kg)];
      const double side = std::max(lengths[topology.face_edges(g, (kg + 1) % 3)],
                                   lengths[topology.face_edges(g, (kg + 2) % 3)]);
      candidates.emplace(std::max(magnification[vi], magnification[vj]) + side / base, t);
    }
  };
  auto expand_around = [&](int v) {
    for (int c = corner_start[v]; c < corner_start[v + 1]; ++c) {
      const int f = corner_face[c];
      if (placed[cut_topology.triangles(f, 0)] && placed[cut_topology.triangles(f, 1)] &&
          placed[cut_topology.triangles(f, 2)]) {
        expand(f);
      }
    }
  };
  for (int root : roots) {
    const int a = cut_topology.triangles(root, 0), b = cut_topology.triangles(root, 1),
              c = cut_topology.triangles(root, 2);
    placed[a] = placed[b] = placed[c] = 1;
    expand(root);
  }
  while (!candidates.empty()) {
    const auto [amount, t] = candidates.top();
    candidates.pop();
    const int g = t / 3, kg = t % 3;
    const int vk = cut_topology.triangles(g, kg);
    if (placed[vk]) continue;
    order.push_back(t);
    placed[vk] = 1;
    magnification[vk] = amount;
    expand_around(vk);
  }

  return order;
}

SegmentEdges segment_edges(const char* who, const Topology& topology, const CutGraph& cut) {
  SegmentEdges result;
  std::vector<int>& edge_segment = result.edge_segment;
  edge_segment.assign(topology.num_edges, -1);
  std::vector<std::vector<int>>& segment_edges = result.segment_edges;
  segment_edges.resize(cut.segments.size());
  {
    std::unordered_map<std::uint64_t, int> cut_edge_of;
    auto key = [](int v, int w) {
      if (v > w) std::swap(v, w);
      return (static_cast<std::uint64_t>(v) << 32) | static_cast<std::uint32_t>(w);
    };
    for (int e = 0; e < topology.num_edges; ++e) {
      if (cut.is_cut_edge[e]) {
        cut_edge_of.emplace(key(topology.edge_vertices(e, 0), topology.edge_vertices(e, 1)), e);
      }
    }
    for (std::size_t s = 0; s < cut.segments.size(); ++s) {
      const std::vector<int>& path = cut.segments[s];
      for (std::size_t i = 0; i + 1 < path.size(); ++i) {
        const auto it = cut_edge_of.find(key(path[i], path[i + 1]));
        if (it == cut_edge_of.end()) {
          throw InvalidInput(std::string(who) + ": segment " + std::to_string(s) +
                             " steps from vertex " + std::to_string(path[i]) + " to " +
                             std::to_string(path[i + 1]) + ", which is not a cut edge");
        }
        edge_segment[it->second] = static_cast<int>(s);
        segment_edges[s].push_back(it->second);
      }
    }
  }

  result.side_a_halfedge.assign(topology.num_edges, -1);
  for (std::size_t s = 0; s < cut.segments.size(); ++s) {
    const std::vector<int>& path = cut.segments[s];
    bool side_a_is_left = true;
    for (std::size_t i = 0; i < segment_edges[s].size(); ++i) {
      const int e = segment_edges[s][i];
      int forward = topology.edge_halfedges(e, 0), backward = topology.edge_halfedges(e, 1);
      if (forward < 0 || backward < 0) continue;
      const bool first_is_forward = topology.tail(forward) == path[i];
      if (!first_is_forward) std::swap(forward, backward);
      if (i == 0) side_a_is_left = first_is_forward;
      result.side_a_halfedge[e] = side_a_is_left ? forward : backward;
    }
  }
  return result;
}

}  // namespace ricci::layout_support
