#include "ricci/mesh/topology.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "mesh/detail/edge_name.hpp"
#include "numerics/detail/bucket_sort.hpp"
#include "numerics/detail/parallel.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/build_counts.hpp"
#include "ricci/numerics/disjoint_sets.hpp"

namespace ricci {
namespace {

using mesh_detail::edge_name;

/// Throws InvalidInput naming the first face with a vertex out of range or used twice.
void check_faces(const Triangles& triangles, int num_vertices) {
  const int nf = static_cast<int>(triangles.rows());
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
}

/// The halfedges bucketed by their smaller end (a counting sort, linear time): bucket v holds
/// entries[start[v], start[v + 1]), each (larger end << 32) | h, so that sorting a bucket's
/// integers sorts its halfedges by (larger end, index) with no look-up into the triangles.
struct HalfedgeBuckets {
  std::vector<int> start;              // #V + 1
  std::vector<std::uint64_t> entries;  // 3#F
  static int halfedge_of(std::uint64_t entry) { return static_cast<int>(entry & 0xffffffffu); }
};

HalfedgeBuckets bucket_halfedges(const Triangles& triangles, int num_vertices) {
  const int nf = static_cast<int>(triangles.rows());
  HalfedgeBuckets b;
  b.start.assign(num_vertices + 1, 0);
  // Halfedge 3 f + k runs from corner k + 1 to corner k + 2: face by face, the three halfedges
  // join (v1, v2), (v2, v0), (v0, v1).
  for (int f = 0; f < nf; ++f) {
    const int v0 = triangles(f, 0), v1 = triangles(f, 1), v2 = triangles(f, 2);
    ++b.start[std::min(v1, v2) + 1];
    ++b.start[std::min(v2, v0) + 1];
    ++b.start[std::min(v0, v1) + 1];
  }
  for (int v = 0; v < num_vertices; ++v) b.start[v + 1] += b.start[v];
  b.entries.resize(3 * nf);
  std::vector<int> fill(b.start.begin(), b.start.end() - 1);
  auto put = [&](int a, int c, int h) {
    b.entries[fill[std::min(a, c)]++] =
        (static_cast<std::uint64_t>(std::max(a, c)) << 32) | static_cast<std::uint32_t>(h);
  };
  for (int f = 0; f < nf; ++f) {
    const int v0 = triangles(f, 0), v1 = triangles(f, 1), v2 = triangles(f, 2);
    put(v1, v2, 3 * f);
    put(v2, v0, 3 * f + 1);
    put(v0, v1, 3 * f + 2);
  }
  return b;
}

/// Throws TopologyError when the halfedges [first, last) joining one pair of vertices do not
/// make a manifold, consistently oriented edge: more than two faces, or two faces traversing it
/// in the same direction.
void check_edge(const Topology& t, const std::uint64_t* first, const std::uint64_t* last) {
  const int h0 = HalfedgeBuckets::halfedge_of(*first);
  if (last - first > 2) {
    throw TopologyError("build_topology: non-manifold edge " + edge_name(t.tail(h0), t.head(h0)) +
                        " is shared by " + std::to_string(last - first) + " faces (" +
                        std::to_string(h0 / 3) + ", " +
                        std::to_string(HalfedgeBuckets::halfedge_of(first[1]) / 3) + ", " +
                        std::to_string(HalfedgeBuckets::halfedge_of(first[2]) / 3) + ", ...)");
  }
  if (last - first == 2) {
    const int h1 = HalfedgeBuckets::halfedge_of(first[1]);
    if (t.tail(h0) == t.tail(h1)) {
      throw TopologyError("build_topology: inconsistent orientation: faces " +
                          std::to_string(h0 / 3) + " and " + std::to_string(h1 / 3) +
                          " traverse edge " + edge_name(t.tail(h0), t.head(h0)) +
                          " in the same direction");
    }
  }
}

/// Pairs the halfedges into edges (t.halfedge_twin, t.halfedge_edge) and returns each edge's
/// (halfedge, twin or -1), edges ordered by (smaller, larger) vertex.
std::vector<std::pair<int, int>> pair_halfedges(Topology& t) {
  const int nh = 3 * t.num_faces;
  HalfedgeBuckets buckets = bucket_halfedges(t.triangles, t.num_vertices);
  t.halfedge_twin.assign(nh, -1);
  t.halfedge_edge.assign(nh, -1);
  std::vector<std::pair<int, int>> edges;  // (halfedge, twin)
  edges.reserve(nh / 2 + 1);
  for (int v = 0; v < t.num_vertices; ++v) {
    std::uint64_t* first = buckets.entries.data() + buckets.start[v];
    std::uint64_t* last = buckets.entries.data() + buckets.start[v + 1];
    numerics_detail::sort_small(first, last);
    for (std::uint64_t* i = first; i < last;) {
      std::uint64_t* j = i + 1;
      while (j < last && (*j >> 32) == (*i >> 32)) ++j;
      check_edge(t, i, j);
      const int h0 = HalfedgeBuckets::halfedge_of(*i);
      const int e = static_cast<int>(edges.size());
      if (j - i == 2) {
        const int h1 = HalfedgeBuckets::halfedge_of(i[1]);
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
  return edges;
}

/// The per-edge arrays from the paired halfedges, the vertex degrees, the boundary flags and
/// face_edges.
void build_edges(Topology& t, const std::vector<std::pair<int, int>>& edges) {
  const int ne = static_cast<int>(edges.size());
  t.num_edges = ne;
  t.edge_vertices.resize(ne, 2);
  t.edge_halfedges.resize(ne, 2);
  t.is_boundary_edge.assign(ne, 0);
  t.vertex_degree.assign(t.num_vertices, 0);
  t.is_boundary_vertex.assign(t.num_vertices, 0);
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
  t.face_edges.resize(t.num_faces, 3);
  parallel::for_each(t.num_faces, [&](std::int64_t f) {
    for (int k = 0; k < 3; ++k) t.face_edges(f, k) = t.halfedge_edge[3 * f + k];
  });
}

/// Throws TopologyError naming the first non-manifold vertex in corner order: one whose faces
/// form more than one fan (corners around a vertex joined across interior edges).
void check_vertex_fans(const Topology& t) {
  const Triangles& triangles = t.triangles;
  const int nf = t.num_faces, nh = 3 * nf, num_vertices = t.num_vertices;
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
  if (several_fans == 0) return;
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

/// t.boundary_loops, each in the order of its halfedges, loops in the order of their first
/// halfedge.
void build_boundary_loops(Topology& t) {
  const int nh = 3 * t.num_faces;
  // At a manifold vertex at most one boundary halfedge leaves.
  std::vector<int> outgoing_boundary(t.num_vertices, -1);
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
}

/// The connected components through interior edges (face_component, vertex_component,
/// components) with their counts, Euler characteristic and genus.
void build_components(Topology& t) {
  const int nf = t.num_faces, nh = 3 * nf;
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
  t.vertex_component.assign(t.num_vertices, -1);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) t.vertex_component[t.triangles(f, k)] = t.face_component[f];
  }
  for (int v = 0; v < t.num_vertices; ++v) {
    if (t.vertex_component[v] >= 0) t.components[t.vertex_component[v]].vertices.push_back(v);
  }
  for (int e = 0; e < t.num_edges; ++e) {
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
}

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
  t.num_vertices = num_vertices;
  t.num_faces = static_cast<int>(triangles.rows());
  t.triangles = triangles;
  check_faces(triangles, num_vertices);
  build_edges(t, pair_halfedges(t));
  check_vertex_fans(t);
  build_boundary_loops(t);
  build_components(t);
  return t;
}

Topology build_topology(const Triangles& triangles, int num_vertices,
                        const std::vector<char>& first_halfedge) {
  if (first_halfedge.size() != 3 * static_cast<std::size_t>(triangles.rows())) {
    throw InvalidInput("build_topology: expected 3 * " + std::to_string(triangles.rows()) +
                       " first-halfedge flags, got " + std::to_string(first_halfedge.size()));
  }
  Topology t = build_topology(triangles, num_vertices);
  for (int e = 0; e < t.num_edges; ++e) {
    const int h0 = t.edge_halfedges(e, 0), h1 = t.edge_halfedges(e, 1);
    if (h1 >= 0 && !first_halfedge[h0] && first_halfedge[h1]) {
      std::swap(t.edge_halfedges(e, 0), t.edge_halfedges(e, 1));
    }
  }
  return t;
}

}  // namespace ricci
