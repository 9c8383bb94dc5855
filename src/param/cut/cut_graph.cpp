#include "ricci/param/cut/cut_graph.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>
#include <string>
#include <utility>
#include <vector>

#include "numerics/detail/parallel.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/build_counts.hpp"
#include "ricci/numerics/disjoint_sets.hpp"

namespace ricci {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// Vertex -> incident edges in compressed rows (edges of each vertex in ascending index order).
struct SortedVertexEdges {
  std::vector<int> offsets;  ///< #V + 1
  std::vector<int> edges;    ///< 2 #E

  explicit SortedVertexEdges(const Topology& topology) {
    const int nv = topology.num_vertices;
    const int ne = topology.num_edges;
    offsets.assign(nv + 1, 0);
    for (int e = 0; e < ne; ++e) {
      ++offsets[topology.edge_vertices(e, 0) + 1];
      ++offsets[topology.edge_vertices(e, 1) + 1];
    }
    for (int v = 0; v < nv; ++v) offsets[v + 1] += offsets[v];
    edges.resize(2 * static_cast<std::size_t>(ne));
    std::vector<int> fill(offsets.begin(), offsets.end() - 1);
    for (int e = 0; e < ne; ++e) {
      edges[fill[topology.edge_vertices(e, 0)]++] = e;
      edges[fill[topology.edge_vertices(e, 1)]++] = e;
    }
  }
  template <typename Visit>
  void for_each(int v, Visit&& visit) const {
    for (int i = offsets[v]; i < offsets[v + 1]; ++i) visit(edges[i]);
  }
};

/// The graph the trees and shortest paths run on: every boundary loop is contracted to one node
/// (equivalently, capped by a virtual vertex joined to the loop by zero-length spokes). Node v is
/// vertex v for interior vertices; node #V + i stands for boundary loop i. Only interior edges
/// join nodes; boundary edges and chords whose two ends lie on the same loop become self-loops.
/// Contracting the caps leaves a closed surface of the same genus, on which tree-cotree yields
/// exactly 2 g generators, and paths through a loop node continue along the (already open)
/// boundary, so nothing but real interior edges is ever cut.
struct ContractedGraph {
  const Topology& topology;
  const SortedVertexEdges& vertex_edges;
  /// #E or empty: edges the cut must not contain (CutGraphOptions::uncut_edges), left out of
  /// the graph, so that no tree and no path runs along them.
  const std::vector<char>& uncut;
  std::vector<int> node_of;     ///< #V: node of each vertex
  std::vector<int> loop_start;  ///< loop i's vertices are loop_vertices[loop_start[i] ...]
  std::vector<int> loop_vertices;
  int num_nodes = 0;

  ContractedGraph(const Topology& t, const SortedVertexEdges& ve,
                  const std::vector<char>& uncut_edges)
      : topology(t), vertex_edges(ve), uncut(uncut_edges) {
    const int nv = t.num_vertices;
    node_of.resize(nv);
    std::iota(node_of.begin(), node_of.end(), 0);
    loop_start.push_back(0);
    for (int i = 0; i < t.num_boundary_loops(); ++i) {
      for (const int v : t.boundary_loops[i]) {
        node_of[v] = nv + i;
        loop_vertices.push_back(v);
      }
      loop_start.push_back(static_cast<int>(loop_vertices.size()));
    }
    num_nodes = nv + t.num_boundary_loops();
  }

  bool is_loop(int node) const { return node >= topology.num_vertices; }

  bool is_uncut(int e) const { return !uncut.empty() && uncut[e] != 0; }

  /// Calls visit(edge, other node) for every interior edge leaving `node` that is no self-loop
  /// and not uncut.
  template <typename Visit>
  void for_each_neighbour(int node, Visit&& visit) const {
    auto from_vertex = [&](int v) {
      vertex_edges.for_each(v, [&](int e) {
        if (topology.is_boundary_edge[e] || is_uncut(e)) return;
        const int a = topology.edge_vertices(e, 0);
        const int other = node_of[a == v ? topology.edge_vertices(e, 1) : a];
        if (other != node) visit(e, other);
      });
    };
    if (!is_loop(node)) {
      from_vertex(node);
      return;
    }
    const int loop = node - topology.num_vertices;
    for (int i = loop_start[loop]; i < loop_start[loop + 1]; ++i) from_vertex(loop_vertices[i]);
  }

  /// The node at the other end of edge e from node `node`.
  int across(int e, int node) const {
    const int a = node_of[topology.edge_vertices(e, 0)];
    return a == node ? node_of[topology.edge_vertices(e, 1)] : a;
  }
};

/// Dijkstra over the contracted graph whose sources may grow while it runs (the join step): a
/// vertex whose distance drops after it was settled is simply queued again, so the settled set
/// stays exact for the current sources. Ties break on the node index, so runs are reproducible.
class ShortestPaths {
 public:
  ShortestPaths(const ContractedGraph& graph, const Eigen::VectorXd& lengths)
      : graph_(graph),
        lengths_(lengths),
        distance(graph.num_nodes, kInfinity),
        parent_edge(graph.num_nodes, -1) {}

  void add_source(int node) {
    if (distance[node] == 0 && parent_edge[node] == -1) return;
    distance[node] = 0;
    parent_edge[node] = -1;
    queue_.emplace(0.0, node);
  }

  /// Settles the next node; returns -1 when none is left.
  int settle_next() {
    while (!queue_.empty()) {
      const auto [d, node] = queue_.top();
      queue_.pop();
      if (d > distance[node]) continue;
      graph_.for_each_neighbour(node, [&, d = d](int e, int other) {
        const double candidate = d + lengths_[e];
        if (candidate < distance[other]) {
          distance[other] = candidate;
          parent_edge[other] = e;
          queue_.emplace(candidate, other);
        }
      });
      return node;
    }
    return -1;
  }

 private:
  using Entry = std::pair<double, int>;
  const ContractedGraph& graph_;
  const Eigen::VectorXd& lengths_;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue_;

 public:
  std::vector<double> distance;  ///< per node
  std::vector<int> parent_edge;  ///< per node: edge to its parent, -1 at sources and unreached
};

void check_inputs(const Topology& topology, const Eigen::VectorXd& lengths,
                  const CutGraphOptions& options) {
  if (lengths.size() != topology.num_edges)
    throw InvalidInput("cut_graph: " + std::to_string(lengths.size()) + " edge lengths for " +
                       std::to_string(topology.num_edges) + " edges");
  for (int e = 0; e < topology.num_edges; ++e) {
    if (!(std::isfinite(lengths[e]) && lengths[e] >= 0))
      throw InvalidInput("cut_graph: edge " + std::to_string(e) + " has length " +
                         std::to_string(lengths[e]) + " (finite and >= 0 required)");
  }
  auto check_vertex = [&](int v, const std::string& what) {
    if (v < 0 || v >= topology.num_vertices)
      throw InvalidInput("cut_graph: " + what + " " + std::to_string(v) + " is out of range [0, " +
                         std::to_string(topology.num_vertices) + ")");
    if (topology.vertex_component[v] < 0)
      throw InvalidInput("cut_graph: " + what + " " + std::to_string(v) + " belongs to no face");
  };
  for (const int cone : options.cones) check_vertex(cone, "cone");
  if (options.root_vertex != -1) check_vertex(options.root_vertex, "root vertex");
  const std::vector<char>& uncut = options.uncut_edges;
  if (uncut.empty()) return;
  if (static_cast<int>(uncut.size()) != topology.num_edges) {
    throw InvalidInput("cut_graph: " + std::to_string(uncut.size()) + " uncut edge flags for " +
                       std::to_string(topology.num_edges) + " edges");
  }
  // The triangles joined across uncut edges must form trees (the cotree takes every uncut edge):
  // an uncut edge between two triangles already joined closes a loop, around which the surface
  // could not be cut open.
  DisjointSets joined(topology.num_faces);
  for (int e = 0; e < topology.num_edges; ++e) {
    const int h0 = topology.edge_halfedges(e, 0), h1 = topology.edge_halfedges(e, 1);
    if (!uncut[e] || h0 < 0 || h1 < 0) continue;
    if (!joined.unite(Topology::face_of(h0), Topology::face_of(h1))) {
      throw InvalidInput("cut_graph: the uncut edges join triangles in a loop (edge " +
                         std::to_string(e) + " closes it), which no cut could open");
    }
  }
}

int edge_component(const Topology& topology, int e) {
  return topology.face_component[topology.edge_halfedges(e, 0) / 3];
}

/// Per component, the vertex the primal tree grows from (only for components of genus >= 1).
std::vector<int> pick_roots(const Topology& topology, const Eigen::VectorXd& lengths,
                            const SortedVertexEdges& vertex_edges, const CutGraphOptions& options,
                            const std::vector<char>& is_cone) {
  const int nc = static_cast<int>(topology.components.size());
  std::vector<int> roots(nc, -1);
  // Distances are needed for a component of genus >= 1 whose root the options do not give (the
  // free seams' rounds give it: kitten, 9 ms of a 34 ms cut went on distances never read).
  bool needs_distances = false;
  const int given = options.root_vertex != -1 ? topology.vertex_component[options.root_vertex] : -1;
  for (int c = 0; c < nc; ++c) {
    const Component& component = topology.components[c];
    if (component.genus == 0) continue;
    roots[c] = c == given ? options.root_vertex : component.vertices.front();
    needs_distances = needs_distances || c != given;
  }
  if (!needs_distances) return roots;

  // The vertex farthest from the boundary and the cones: the tree paths then start away from
  // where the cut is joined anyway.
  const int nv = topology.num_vertices;
  std::vector<double> distance(nv, kInfinity);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  for (int v = 0; v < nv; ++v) {
    if (topology.is_boundary_vertex[v] || is_cone[v]) {
      distance[v] = 0;
      queue.emplace(0.0, v);
    }
  }
  if (queue.empty()) return roots;
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v]) continue;
    vertex_edges.for_each(v, [&, d = d, v = v](int e) {
      const int a = topology.edge_vertices(e, 0);
      const int w = a == v ? topology.edge_vertices(e, 1) : a;
      if (d + lengths[e] < distance[w]) {
        distance[w] = d + lengths[e];
        queue.emplace(distance[w], w);
      }
    });
  }
  for (int c = 0; c < nc; ++c) {
    if (roots[c] == -1) continue;
    if (options.root_vertex != -1 && topology.vertex_component[options.root_vertex] == c) continue;
    double farthest = -1;
    for (const int v : topology.components[c].vertices) {
      // Closed components without cones stay at infinity: their smallest vertex is kept.
      if (distance[v] > farthest) {
        farthest = distance[v];
        roots[c] = v;
      }
    }
  }
  return roots;
}

/// Tree-cotree on the contracted graph: marks the union of the generator loops as cut edges and
/// returns the number of generators.
int homology_generators(const Topology& topology, const Eigen::VectorXd& lengths,
                        const ContractedGraph& graph, const std::vector<int>& roots,
                        std::vector<char>& is_cut) {
  ShortestPaths tree(graph, lengths);
  bool any = false;
  for (const int root : roots) {
    if (root == -1) continue;
    tree.add_source(graph.node_of[root]);
    any = true;
  }
  if (!any) return 0;
  while (tree.settle_next() != -1) {
  }
  std::vector<char> in_tree(topology.num_edges, 0);
  for (int node = 0; node < graph.num_nodes; ++node) {
    if (tree.parent_edge[node] >= 0) in_tree[tree.parent_edge[node]] = 1;
  }

  // Cotree: breadth-first spanning tree of the faces across interior edges not in the tree.
  // A face reached brings the faces joined to it across uncut edges at once (a tree of them,
  // all unseen), so that the cotree holds every uncut edge and none closes a generator.
  const int nf = topology.num_faces;
  std::vector<char> face_seen(nf, 0), in_cotree(topology.num_edges, 0);
  std::vector<int> queue;
  queue.reserve(nf);
  auto reach = [&](int start) {
    face_seen[start] = 1;
    const std::size_t first = queue.size();
    queue.push_back(start);
    for (std::size_t i = first; i < queue.size() && !graph.uncut.empty(); ++i) {
      const int f = queue[i];
      for (int k = 0; k < 3; ++k) {
        const int twin = topology.halfedge_twin[3 * f + k];
        const int e = topology.halfedge_edge[3 * f + k];
        if (twin < 0 || !graph.is_uncut(e) || face_seen[twin / 3]) continue;
        face_seen[twin / 3] = 1;
        in_cotree[e] = 1;
        queue.push_back(twin / 3);
      }
    }
  };
  for (std::size_t c = 0; c < roots.size(); ++c) {
    if (roots[c] != -1) reach(topology.components[c].faces.front());
  }
  for (std::size_t i = 0; i < queue.size(); ++i) {
    const int f = queue[i];
    for (int k = 0; k < 3; ++k) {
      const int twin = topology.halfedge_twin[3 * f + k];
      if (twin < 0) continue;
      const int e = topology.halfedge_edge[3 * f + k];
      const int g = twin / 3;
      if (in_tree[e] || face_seen[g]) continue;
      in_cotree[e] = 1;
      reach(g);
    }
  }

  // Each interior edge in neither tree closes one generator: the edge and the tree paths of its
  // two ends back to the root. Their union is marked path by path, stopping where an earlier
  // path already went, so the whole pass is linear.
  std::vector<char> node_done(graph.num_nodes, 0);
  auto mark_to_root = [&](int node) {
    while (!node_done[node] && tree.parent_edge[node] >= 0) {
      node_done[node] = 1;
      const int e = tree.parent_edge[node];
      is_cut[e] = 1;
      node = graph.across(e, node);
    }
  };
  int generators = 0;
  for (int e = 0; e < topology.num_edges; ++e) {
    if (topology.is_boundary_edge[e] || in_tree[e] || in_cotree[e]) continue;
    if (roots[edge_component(topology, e)] == -1) continue;
    ++generators;
    is_cut[e] = 1;
    mark_to_root(graph.node_of[topology.edge_vertices(e, 0)]);
    mark_to_root(graph.node_of[topology.edge_vertices(e, 1)]);
  }
  return generators;
}

/// Removes cut edges with an end of cut-degree 1 that is neither a cone nor on a boundary,
/// repeatedly.
void prune(const Topology& topology, const SortedVertexEdges& vertex_edges,
           const std::vector<char>& is_cone, std::vector<char>& is_cut) {
  const int nv = topology.num_vertices;
  std::vector<int> degree(nv, 0);
  for (int e = 0; e < topology.num_edges; ++e) {
    if (!is_cut[e]) continue;
    ++degree[topology.edge_vertices(e, 0)];
    ++degree[topology.edge_vertices(e, 1)];
  }
  auto prunable = [&](int v) {
    return degree[v] == 1 && !is_cone[v] && !topology.is_boundary_vertex[v];
  };
  std::vector<int> stack;
  for (int v = nv - 1; v >= 0; --v) {
    if (prunable(v)) stack.push_back(v);
  }
  while (!stack.empty()) {
    const int v = stack.back();
    stack.pop_back();
    if (!prunable(v)) continue;
    int cut_edge = -1;
    vertex_edges.for_each(v, [&](int e) {
      if (is_cut[e]) cut_edge = e;
    });
    is_cut[cut_edge] = 0;
    const int a = topology.edge_vertices(cut_edge, 0);
    const int w = a == v ? topology.edge_vertices(cut_edge, 1) : a;
    --degree[v];
    --degree[w];
    if (prunable(w)) stack.push_back(w);
  }
}

/// Joins every interior cone and boundary loop to the cut by shortest paths, nearest first.
/// Start: the current cut (with the loops it touches) on components of genus >= 1; the first
/// boundary loop on genus-0 components with boundary; the smallest cone on closed genus-0 ones.
void join(const Topology& topology, const Eigen::VectorXd& lengths, const ContractedGraph& graph,
          const std::vector<int>& cones, std::vector<char>& is_cut) {
  const int nc = static_cast<int>(topology.components.size());
  std::vector<char> is_target(graph.num_nodes, 0), is_source(graph.num_nodes, 0);
  std::vector<char> component_has_cut(nc, 0);
  for (int e = 0; e < topology.num_edges; ++e) {
    if (!is_cut[e]) continue;
    component_has_cut[edge_component(topology, e)] = 1;
    is_source[graph.node_of[topology.edge_vertices(e, 0)]] = 1;
    is_source[graph.node_of[topology.edge_vertices(e, 1)]] = 1;
  }
  std::vector<int> component_seed(nc, -1);
  for (int i = 0; i < topology.num_boundary_loops(); ++i) {
    const int c = topology.vertex_component[topology.boundary_loops[i].front()];
    if (!component_has_cut[c] && component_seed[c] == -1)
      component_seed[c] = topology.num_vertices + i;
  }
  for (const int cone : cones) {  // ascending
    const int c = topology.vertex_component[cone];
    if (!component_has_cut[c] && component_seed[c] == -1) component_seed[c] = cone;
  }
  for (const int seed : component_seed) {
    if (seed != -1) is_source[seed] = 1;
  }

  int targets = 0;
  for (int i = 0; i < topology.num_boundary_loops(); ++i) {
    const int node = topology.num_vertices + i;
    if (!is_source[node]) {
      is_target[node] = 1;
      ++targets;
    }
  }
  for (const int cone : cones) {
    const int node = graph.node_of[cone];
    if (!is_source[node] && !is_target[node]) {
      is_target[node] = 1;
      ++targets;
    }
  }
  if (targets == 0) return;

  ShortestPaths paths(graph, lengths);
  for (int node = 0; node < graph.num_nodes; ++node) {
    if (is_source[node]) paths.add_source(node);
  }
  while (targets > 0) {
    const int node = paths.settle_next();
    if (node == -1) break;
    if (!is_target[node]) continue;
    is_target[node] = 0;
    --targets;
    // The path back to the connected set joins the cut; its nodes become sources.
    int x = node;
    while (!is_source[x]) {
      is_source[x] = 1;
      const int e = paths.parent_edge[x];
      paths.add_source(x);
      is_cut[e] = 1;
      x = graph.across(e, x);
    }
  }
}

/// On a closed genus-0 component whose cut is one edge between two cones, slicing could not open
/// it (both ends keep a single copy, so the two sides would be glued again): the edge is replaced
/// by the other edges of its cheaper face (the other two of a triangle; with uncut edges the rest
/// of the boundary of the triangles joined to it across them: the rest of its polygon).
void widen_single_edge_cuts(const Topology& topology, const Eigen::VectorXd& lengths,
                            const ContractedGraph& graph, std::vector<char>& is_cut) {
  const int nc = static_cast<int>(topology.components.size());
  std::vector<int> count(nc, 0), edge(nc, -1);
  for (int e = 0; e < topology.num_edges; ++e) {
    if (!is_cut[e]) continue;
    const int c = edge_component(topology, e);
    ++count[c];
    edge[c] = e;
  }
  for (int c = 0; c < nc; ++c) {
    const Component& component = topology.components[c];
    if (count[c] != 1 || component.genus != 0 || component.num_boundary_loops != 0) continue;
    const int e = edge[c];
    std::vector<int> best_path, path;
    double best = kInfinity;
    for (int side = 0; side < 2; ++side) {
      // Around the face from h's head back to its tail, stepping over uncut edges.
      const int h = topology.edge_halfedges(e, side);
      path.clear();
      double through = 0;
      for (int x = Topology::next(h); x != h;) {
        const int edge_x = topology.halfedge_edge[x];
        if (graph.is_uncut(edge_x) && topology.halfedge_twin[x] >= 0) {
          x = Topology::next(topology.halfedge_twin[x]);
          continue;
        }
        path.push_back(edge_x);
        through += lengths[edge_x];
        x = Topology::next(x);
      }
      if (through < best) {
        best = through;
        best_path = path;
      }
    }
    is_cut[e] = 0;
    for (const int replacement : best_path) is_cut[replacement] = 1;
  }
}

/// Nodes and segments of a finished cut.
void split_into_segments(const Topology& topology, const SortedVertexEdges& vertex_edges,
                         const std::vector<int>& cones, CutGraph& cut) {
  const int nv = topology.num_vertices;
  std::vector<int> cut_degree(nv, 0), boundary_degree(nv, 0);
  for (int e = 0; e < topology.num_edges; ++e) {
    const int a = topology.edge_vertices(e, 0), b = topology.edge_vertices(e, 1);
    if (cut.is_cut_edge[e]) {
      ++cut_degree[a];
      ++cut_degree[b];
    } else if (topology.is_boundary_edge[e]) {
      ++boundary_degree[a];
      ++boundary_degree[b];
    }
  }
  std::vector<char> is_node(nv, 0);
  for (const int cone : cones) is_node[cone] = 1;
  for (int v = 0; v < nv; ++v) {
    if (cut_degree[v] > 0 && cut_degree[v] + boundary_degree[v] != 2) is_node[v] = 1;
  }
  for (int v = 0; v < nv; ++v) {
    if (is_node[v]) cut.nodes.push_back(v);
  }

  std::vector<char> used(topology.num_edges, 0);
  auto other_end = [&](int e, int v) {
    const int a = topology.edge_vertices(e, 0);
    return a == v ? topology.edge_vertices(e, 1) : a;
  };
  auto unused_cut_edge = [&](int v) {
    int found = -1;
    vertex_edges.for_each(v, [&](int e) {
      if (found == -1 && cut.is_cut_edge[e] && !used[e]) found = e;
    });
    return found;
  };
  // Follows the cut from `start` along edge e until a node, or back to `start`.
  auto walk = [&](int start, int e) {
    std::vector<int> segment{start};
    int v = start;
    while (true) {
      used[e] = 1;
      v = other_end(e, v);
      segment.push_back(v);
      if (is_node[v] || v == start) break;
      e = unused_cut_edge(v);
      if (e == -1) break;  // unreachable: a non-node cut vertex has two cut edges
    }
    cut.segments.push_back(std::move(segment));
  };
  for (const int node : cut.nodes) {
    for (int e = unused_cut_edge(node); e != -1; e = unused_cut_edge(node)) walk(node, e);
  }
  // Closed loops through no node.
  for (int e = 0; e < topology.num_edges; ++e) {
    if (cut.is_cut_edge[e] && !used[e]) walk(topology.edge_vertices(e, 0), e);
  }
}

}  // namespace

CutGraph cut_graph(const Topology& topology, const Eigen::VectorXd& lengths,
                   const CutGraphOptions& options) {
  check_inputs(topology, lengths, options);
  std::vector<int> cones = options.cones;
  std::sort(cones.begin(), cones.end());
  cones.erase(std::unique(cones.begin(), cones.end()), cones.end());
  std::vector<char> is_cone(topology.num_vertices, 0);
  for (const int cone : cones) is_cone[cone] = 1;

  const SortedVertexEdges vertex_edges(topology);
  const ContractedGraph graph(topology, vertex_edges, options.uncut_edges);

  CutGraph cut;
  cut.is_cut_edge.assign(topology.num_edges, 0);
  const std::vector<int> roots = pick_roots(topology, lengths, vertex_edges, options, is_cone);
  cut.num_generators = homology_generators(topology, lengths, graph, roots, cut.is_cut_edge);
  prune(topology, vertex_edges, is_cone, cut.is_cut_edge);

  // Cones on a boundary are on the disk's boundary already; only interior ones need a path.
  std::vector<int> interior_cones;
  for (const int cone : cones) {
    if (!topology.is_boundary_vertex[cone]) interior_cones.push_back(cone);
  }
  join(topology, lengths, graph, interior_cones, cut.is_cut_edge);
  prune(topology, vertex_edges, is_cone, cut.is_cut_edge);
  widen_single_edge_cuts(topology, lengths, graph, cut.is_cut_edge);

  for (int e = 0; e < topology.num_edges; ++e) {
    if (cut.is_cut_edge[e]) cut.length += lengths[e];
  }
  split_into_segments(topology, vertex_edges, cones, cut);
  return cut;
}

namespace {

/// Whether build_topology(topology.triangles) would number the edges as `topology` does: edges
/// in increasing (smaller, larger) vertex order, each with its smaller halfedge first. It then
/// gives a copy of `topology` (the rest follows from the same triangles and twins).
bool edges_as_built(const Topology& topology) {
  const int ne = topology.num_edges;
  const std::int64_t out_of_order = parallel::count_if(ne, [&](std::int64_t e) {
    const int h0 = topology.edge_halfedges(e, 0), h1 = topology.edge_halfedges(e, 1);
    if (h1 >= 0 && h1 < h0) return true;
    if (topology.edge_vertices(e, 0) >= topology.edge_vertices(e, 1)) return true;
    if (e == 0) return false;
    const int a0 = topology.edge_vertices(e - 1, 0), a1 = topology.edge_vertices(e - 1, 1);
    const int b0 = topology.edge_vertices(e, 0), b1 = topology.edge_vertices(e, 1);
    return !(a0 < b0 || (a0 == b0 && a1 < b1));
  });
  return out_of_order == 0;
}

}  // namespace

std::vector<char> cut_vertices(const Topology& topology, const CutGraph& cut) {
  std::vector<char> on_cut(topology.num_vertices, 0);
  for (int e = 0; e < topology.num_edges; ++e) {
    if (cut.is_cut_edge[e])
      on_cut[topology.edge_vertices(e, 0)] = on_cut[topology.edge_vertices(e, 1)] = 1;
  }
  return on_cut;
}

CutMesh slice(const Topology& topology, const CutGraph& cut) {
  if (static_cast<int>(cut.is_cut_edge.size()) != topology.num_edges)
    throw InvalidInput("slice: cut has " + std::to_string(cut.is_cut_edge.size()) +
                       " edge flags for " + std::to_string(topology.num_edges) + " edges");
  // Without cut edges every vertex keeps one copy (a manifold vertex's corners form one fan),
  // and the cut mesh is the mesh: its connectivity is a copy, when the mesh's edges are numbered
  // as build_topology numbers them.
  if (std::none_of(cut.is_cut_edge.begin(), cut.is_cut_edge.end(), [](char c) { return c != 0; }) &&
      edges_as_built(topology)) {
    CutMesh out;
    out.triangles = topology.triangles;
    out.to_original.resize(topology.num_vertices);
    std::iota(out.to_original.begin(), out.to_original.end(), 0);
    out.topology = topology;
    return out;
  }
  // Corners around a vertex that meet across an interior edge not on the cut share a copy:
  // union-find over corners, the smallest corner of each class its root.
  const int nc = 3 * topology.num_faces;
  DisjointSets corners(nc);
  for (int h = 0; h < nc; ++h) {
    const int g = topology.halfedge_twin[h];
    if (g < h || cut.is_cut_edge[topology.halfedge_edge[h]]) continue;  // each pair once
    // h runs a -> b in its face, g runs b -> a in the other; corner 3f + k sits at triangles(f, k)
    // and halfedge 3f + j runs from corner (j+1)%3 to corner (j+2)%3.
    const int fh = h - h % 3, jh = h % 3, fg = g - g % 3, jg = g % 3;
    corners.unite(fh + (jh + 1) % 3, fg + (jg + 2) % 3);  // a
    corners.unite(fh + (jh + 2) % 3, fg + (jg + 1) % 3);  // b
  }

  // The first copy of every vertex keeps its index; further copies are numbered from #V on, in
  // the order of their smallest corner.
  const int nv = topology.num_vertices;
  CutMesh out;
  out.to_original.resize(nv);
  std::iota(out.to_original.begin(), out.to_original.end(), 0);
  std::vector<char> has_copy(nv, 0);
  std::vector<int> corner_vertex(nc);
  for (int c = 0; c < nc; ++c) {
    const int root = corners.find(c);
    if (root != c) {
      corner_vertex[c] = corner_vertex[root];
      continue;
    }
    const int v = topology.triangles(c / 3, c % 3);
    if (!has_copy[v]) {
      has_copy[v] = 1;
      corner_vertex[c] = v;
    } else {
      corner_vertex[c] = static_cast<int>(out.to_original.size());
      out.to_original.push_back(v);
    }
  }
  out.triangles.resize(topology.num_faces, 3);
  for (int c = 0; c < nc; ++c) out.triangles(c / 3, c % 3) = corner_vertex[c];
  const build_counting::Scope counted(build_counting::Kind::CutMesh);
  out.topology = build_topology(out.triangles, static_cast<int>(out.to_original.size()));
  return out;
}

}  // namespace ricci
