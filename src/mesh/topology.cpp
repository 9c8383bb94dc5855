#include "ricci/mesh/topology.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <string>

#include "mesh/detail/edge_name.hpp"
#include "numerics/detail/parallel.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/build_counts.hpp"
#include "ricci/numerics/disjoint_sets.hpp"

namespace ricci {
namespace {

using mesh_detail::edge_name;

}  // namespace

int Topology::euler_characteristic() const {
  return num_referenced_vertices() - num_edges + num_faces;
}

int Topology::num_referenced_vertices() const {
  int count = 0;
  for (int c : vertex_component) count += (c >= 0);
  return count;
}

Topology build_topology(const Triangles& triangles, int num_vertices) {
  const build_counting::Scope counted(build_counting::Kind::Topology);
  Topology t;
  const int nf = static_cast<int>(triangles.rows());
  t.num_vertices = num_vertices;
  t.num_faces = nf;
  t.triangles = triangles;

  // Checked in parallel (an exact count); the sequential pass below names the first bad face.
  const std::int64_t bad_faces = parallel::count_if(nf, [&](std::int64_t f) {
    const int a = triangles(f, 0), b = triangles(f, 1), c = triangles(f, 2);
    return a < 0 || a >= num_vertices || b < 0 || b >= num_vertices || c < 0 || c >= num_vertices ||
           a == b || b == c || a == c;
  });
  for (int f = 0; f < nf && bad_faces > 0; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = triangles(f, k);
      if (v < 0 || v >= num_vertices) {
        throw InvalidInput("build_topology: face " + std::to_string(f) + " uses vertex " +
                           std::to_string(v) + ", outside [0, " + std::to_string(num_vertices) +
                           ")");
      }
    }
    if (triangles(f, 0) == triangles(f, 1) || triangles(f, 1) == triangles(f, 2) ||
        triangles(f, 0) == triangles(f, 2)) {
      throw InvalidInput("build_topology: face " + std::to_string(f) + " uses a vertex twice");
    }
  }

  // Pair halfedges: bucket them by their smaller end (a counting sort, linear time), then sort
  // each small bucket by the larger end. Edges come out ordered by (smaller, larger) vertex.
  const int nh = 3 * nf;
  std::vector<int> bucket_start(num_vertices + 1, 0);
  // Halfedge 3 f + k runs from corner k + 1 to corner k + 2: face by face, the three halfedges
  // join (v1, v2), (v2, v0), (v0, v1).
  for (int f = 0; f < nf; ++f) {
    const int v0 = triangles(f, 0), v1 = triangles(f, 1), v2 = triangles(f, 2);
    ++bucket_start[std::min(v1, v2) + 1];
    ++bucket_start[std::min(v2, v0) + 1];
    ++bucket_start[std::min(v0, v1) + 1];
  }
  for (int v = 0; v < num_vertices; ++v) bucket_start[v + 1] += bucket_start[v];
  // Each entry holds (larger end << 32) | h, so that sorting a bucket's integers sorts its
  // halfedges by (larger end, index) with no look-up into the triangles.
  std::vector<std::uint64_t> bucket(nh);
  {
    std::vector<int> fill(bucket_start.begin(), bucket_start.end() - 1);
    auto put = [&](int a, int b, int h) {
      bucket[fill[std::min(a, b)]++] =
          (static_cast<std::uint64_t>(std::max(a, b)) << 32) | static_cast<std::uint32_t>(h);
    };
    for (int f = 0; f < nf; ++f) {
      const int v0 = triangles(f, 0), v1 = triangles(f, 1), v2 = triangles(f, 2);
      put(v1, v2, 3 * f);
      put(v2, v0, 3 * f + 1);
      put(v0, v1, 3 * f + 2);
    }
  }
  auto halfedge_of = [](std::uint64_t entry) { return static_cast<int>(entry & 0xffffffffu); };

  t.halfedge_twin.assign(nh, -1);
  t.halfedge_edge.assign(nh, -1);
  std::vector<std::pair<int, int>> edges;  // (halfedge, twin)
  edges.reserve(nh / 2 + 1);
  for (int v = 0; v < num_vertices; ++v) {
    std::uint64_t* first = bucket.data() + bucket_start[v];
    std::uint64_t* last = bucket.data() + bucket_start[v + 1];
    if (last - first > 16) {
      std::sort(first, last);
    } else {
      // Buckets hold a handful of halfedges (about the valence): insertion sort.
      for (std::uint64_t* i = first + 1; i < last; ++i) {
        const std::uint64_t x = *i;
        std::uint64_t* j = i;
        for (; j > first && *(j - 1) > x; --j) *j = *(j - 1);
        *j = x;
      }
    }
    for (std::uint64_t* i = first; i < last;) {
      std::uint64_t* j = i + 1;
      while (j < last && (*j >> 32) == (*i >> 32)) ++j;
      const int h0 = halfedge_of(*i);
      if (j - i > 2) {
        throw TopologyError("build_topology: non-manifold edge " +
                            edge_name(t.tail(h0), t.head(h0)) + " is shared by " +
                            std::to_string(j - i) + " faces (" + std::to_string(h0 / 3) + ", " +
                            std::to_string(halfedge_of(i[1]) / 3) + ", " +
                            std::to_string(halfedge_of(i[2]) / 3) + ", ...)");
      }
      const int e = static_cast<int>(edges.size());
      if (j - i == 2) {
        const int h1 = halfedge_of(i[1]);
        if (t.tail(h0) == t.tail(h1)) {
          throw TopologyError("build_topology: inconsistent orientation: faces " +
                              std::to_string(h0 / 3) + " and " + std::to_string(h1 / 3) +
                              " traverse edge " + edge_name(t.tail(h0), t.head(h0)) +
                              " in the same direction");
        }
        t.halfedge_twin[h0] = h1;
        t.halfedge_twin[h1] = h0;
        t.halfedge_edge[h1] = e;
        edges.emplace_back(h0, h1);
      } else {
        edges.emplace_back(h0, -1);
      }
      t.halfedge_edge[h0] = e;
      i = j;
    }
  }

  const int ne = static_cast<int>(edges.size());
  t.num_edges = ne;
  t.edge_vertices.resize(ne, 2);
  t.edge_halfedges.resize(ne, 2);
  t.is_boundary_edge.assign(ne, 0);
  t.vertex_degree.assign(num_vertices, 0);
  t.is_boundary_vertex.assign(num_vertices, 0);
  for (int e = 0; e < ne; ++e) {
    const int h = edges[e].first;
    const int a = t.tail(h), b = t.head(h);
    t.edge_vertices(e, 0) = std::min(a, b);
    t.edge_vertices(e, 1) = std::max(a, b);
    t.edge_halfedges(e, 0) = h;
    t.edge_halfedges(e, 1) = edges[e].second;
    ++t.vertex_degree[a];
    ++t.vertex_degree[b];
    if (edges[e].second < 0) {
      t.is_boundary_edge[e] = 1;
      t.is_boundary_vertex[a] = 1;
      t.is_boundary_vertex[b] = 1;
    }
  }
  t.face_edges.resize(nf, 3);
  parallel::for_each(nf, [&](std::int64_t f) {
    for (int k = 0; k < 3; ++k) t.face_edges(f, k) = t.halfedge_edge[3 * f + k];
  });

  // Fans: corners around a vertex joined across interior edges. A manifold vertex has one fan.
  // Corner c = 3f + k sits at triangles(f, k); halfedge h runs tail -> head, so its tail corner
  // is next(h) and its head corner is prev(h). Walking around each vertex from one of its
  // corners (both ways when the boundary stops the walk) must reach all of its corners: checked
  // per vertex in parallel (an exact count); where it fails, the union-find of the corners below
  // names the first non-manifold vertex in corner order.
  std::vector<int> vertex_corners(num_vertices, 0), first_corner(num_vertices, -1);
  for (int f = nf - 1; f >= 0; --f) {
    for (int k = 2; k >= 0; --k) {
      const int v = triangles(f, k);
      ++vertex_corners[v];
      first_corner[v] = 3 * f + k;
    }
  }
  const std::int64_t several_fans = parallel::count_if(num_vertices, [&](std::int64_t v) {
    const int start = first_corner[v];
    if (start < 0) return false;
    int reached = 1;
    bool closed = false;
    // Forward: the halfedge into the corner (opposite corner k + 1), then its twin's tail corner.
    for (int c = start; reached <= vertex_corners[v];) {
      const int g = t.halfedge_twin[3 * (c / 3) + (c % 3 + 1) % 3];
      if (g < 0) break;
      c = Topology::next(g);
      if (c == start) {
        closed = true;
        break;
      }
      ++reached;
    }
    // Backward from the start: the halfedge out of the corner, then its twin's head corner.
    for (int c = start; !closed && reached <= vertex_corners[v];) {
      const int g = t.halfedge_twin[3 * (c / 3) + (c % 3 + 2) % 3];
      if (g < 0) break;
      c = Topology::prev(g);
      ++reached;
    }
    return reached != vertex_corners[v];
  });
  if (several_fans > 0) {
    DisjointSets fans(nh);
    for (int h = 0; h < nh; ++h) {
      const int g = t.halfedge_twin[h];
      if (g < h) continue;
      fans.unite(Topology::next(h), Topology::prev(g));  // corners at tail(h) == head(g)
      fans.unite(Topology::prev(h), Topology::next(g));  // corners at head(h) == tail(g)
    }
    std::vector<int> fan_of_vertex(num_vertices, -1);
    for (int c = 0; c < nh; ++c) {
      const int v = triangles(c / 3, c % 3);
      const int root = fans.find(c);
      if (fan_of_vertex[v] < 0) {
        fan_of_vertex[v] = root;
      } else if (fan_of_vertex[v] != root) {
        throw TopologyError("build_topology: non-manifold vertex " + std::to_string(v) +
                            ": its faces form more than one fan");
      }
    }
  }

  // Boundary loops: at a manifold vertex at most one boundary halfedge leaves.
  std::vector<int> outgoing_boundary(num_vertices, -1);
  for (int h = 0; h < nh; ++h) {
    if (t.halfedge_twin[h] < 0) outgoing_boundary[t.tail(h)] = h;
  }
  std::vector<char> visited(nh, 0);
  for (int h = 0; h < nh; ++h) {
    if (t.halfedge_twin[h] >= 0 || visited[h]) continue;
    std::vector<int> loop;
    int g = h;
    while (!visited[g]) {
      visited[g] = 1;
      loop.push_back(t.tail(g));
      g = outgoing_boundary[t.head(g)];
    }
    t.boundary_loops.push_back(std::move(loop));
  }

  // Connected components through interior edges.
  DisjointSets faces(std::max(nf, 1));
  for (int h = 0; h < nh; ++h) {
    if (t.halfedge_twin[h] > h) faces.unite(h / 3, t.halfedge_twin[h] / 3);
  }
  t.face_component.assign(nf, -1);
  std::vector<int> component_of_root(nf, -1);
  for (int f = 0; f < nf; ++f) {
    const int r = faces.find(f);
    if (component_of_root[r] < 0) {
      component_of_root[r] = static_cast<int>(t.components.size());
      t.components.emplace_back();
    }
    t.face_component[f] = component_of_root[r];
    t.components[t.face_component[f]].faces.push_back(f);
  }
  t.vertex_component.assign(num_vertices, -1);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) t.vertex_component[triangles(f, k)] = t.face_component[f];
  }
  for (int v = 0; v < num_vertices; ++v) {
    if (t.vertex_component[v] >= 0) t.components[t.vertex_component[v]].vertices.push_back(v);
  }
  for (int e = 0; e < ne; ++e) {
    ++t.components[t.face_component[t.edge_halfedges(e, 0) / 3]].num_edges;
  }
  for (const auto& loop : t.boundary_loops) {
    ++t.components[t.vertex_component[loop.front()]].num_boundary_loops;
  }
  for (auto& c : t.components) {
    c.euler_characteristic =
        static_cast<int>(c.vertices.size()) - c.num_edges + static_cast<int>(c.faces.size());
    c.genus = (2 - c.euler_characteristic - c.num_boundary_loops) / 2;
  }
  return t;
}

}  // namespace ricci
