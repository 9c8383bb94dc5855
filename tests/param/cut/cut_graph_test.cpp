// Cut graph and slicing: on generated meshes of every genus, with holes, several components and
// cones, and on every manifold mesh of ../shared/meshes, the sliced mesh must be one topological
// disk per component, with the cones on its boundary, every boundary loop reached, no dangling
// branch, and segments that partition the cut. Every property is recomputed here from the
// topology, independently of the implementation.
#include "ricci/param/cut/cut_graph.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/metric/scheme.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

struct Case {
  Mesh mesh;
  Topology topology;
  Eigen::VectorXd lengths;
};

Case make_case(Mesh mesh) {
  Case c;
  c.topology = build_topology(mesh.triangles, mesh.num_vertices());
  c.lengths = input_edge_lengths(mesh, c.topology);
  c.mesh = std::move(mesh);
  return c;
}

/// k vertices spread over the index range (generated meshes number their vertices by position).
std::vector<int> spread_cones(int num_vertices, int k) {
  std::vector<int> cones;
  cones.reserve(k);
  for (int i = 0; i < k; ++i)
    cones.push_back(static_cast<int>((static_cast<long long>(2 * i + 1) * num_vertices) / (2 * k)));
  return cones;
}

/// The disjoint union of meshes.
Mesh concatenate(const std::vector<Mesh>& meshes) {
  Mesh out;
  int nv = 0, nf = 0;
  for (const Mesh& m : meshes) {
    nv += m.num_vertices();
    nf += m.num_faces();
  }
  out.positions.resize(nv, 3);
  out.triangles.resize(nf, 3);
  nv = nf = 0;
  for (const Mesh& m : meshes) {
    out.positions.middleRows(nv, m.num_vertices()) = m.positions;
    out.triangles.middleRows(nf, m.num_faces()) = m.triangles.array() + nv;
    nv += m.num_vertices();
    nf += m.num_faces();
  }
  return out;
}

int expected_generators(const Topology& t) {
  int g = 0;
  for (const Component& c : t.components) g += 2 * c.genus;
  return g;
}

/// Checks every property of a cut and of its slice.
void expect_valid_cut(const Case& c, const CutGraphOptions& options, const CutGraph& cut,
                      const std::string& what) {
  const Topology& t = c.topology;
  const int nv = t.num_vertices, ne = t.num_edges;
  EXPECT_EQ(static_cast<int>(cut.is_cut_edge.size()), ne) << what;
  if (static_cast<int>(cut.is_cut_edge.size()) != ne) return;
  EXPECT_EQ(cut.num_generators, expected_generators(t)) << what;

  std::vector<char> is_cone(nv, 0);
  for (const int v : options.cones) is_cone[v] = 1;
  std::vector<int> cut_degree(nv, 0), boundary_degree(nv, 0);
  std::vector<int> component_cut_edges(t.components.size(), 0);
  double length = 0;
  for (int e = 0; e < ne; ++e) {
    const int a = t.edge_vertices(e, 0), b = t.edge_vertices(e, 1);
    if (t.is_boundary_edge[e]) {
      EXPECT_FALSE(cut.is_cut_edge[e]) << what << ": boundary edge " << e << " is cut";
      ++boundary_degree[a];
      ++boundary_degree[b];
      continue;
    }
    if (!cut.is_cut_edge[e]) continue;
    ++cut_degree[a];
    ++cut_degree[b];
    length += c.lengths[e];
    ++component_cut_edges[t.vertex_component[a]];
  }
  EXPECT_NEAR(cut.length, length, 1e-12 * std::max(1.0, length)) << what;

  // No dangling branch.
  for (int v = 0; v < nv; ++v) {
    if (cut_degree[v] == 1) {
      EXPECT_TRUE(is_cone[v] || t.is_boundary_vertex[v]) << what << ": dangling vertex " << v;
    }
  }

  // Nodes, recomputed.
  std::vector<int> nodes;
  for (int v = 0; v < nv; ++v) {
    if (is_cone[v] || (cut_degree[v] > 0 && cut_degree[v] + boundary_degree[v] != 2))
      nodes.push_back(v);
  }
  EXPECT_EQ(cut.nodes, nodes) << what;
  const std::set<int> node_set(nodes.begin(), nodes.end());

  // Segments partition the cut edges, run node to node (or round a loop), nodes only at ends.
  std::map<std::pair<int, int>, int> edge_of_pair;
  for (int e = 0; e < ne; ++e) edge_of_pair[{t.edge_vertices(e, 0), t.edge_vertices(e, 1)}] = e;
  auto find_edge = [&](int a, int b) {
    const auto found = edge_of_pair.find({a, b});
    return found == edge_of_pair.end() ? -1 : found->second;
  };
  std::vector<int> segment_uses(ne, 0);
  for (const std::vector<int>& segment : cut.segments) {
    EXPECT_GE(segment.size(), 2u) << what;
    if (segment.size() < 2) continue;
    const bool closed = segment.front() == segment.back();
    if (!closed || node_set.count(segment.front())) {
      EXPECT_TRUE(node_set.count(segment.front())) << what;
      EXPECT_TRUE(node_set.count(segment.back())) << what;
    }
    for (std::size_t i = 1; i + 1 < segment.size(); ++i)
      EXPECT_FALSE(node_set.count(segment[i])) << what << ": node inside a segment";
    for (std::size_t i = 0; i + 1 < segment.size(); ++i) {
      int e = find_edge(segment[i], segment[i + 1]);
      if (e == -1) e = find_edge(segment[i + 1], segment[i]);
      EXPECT_NE(e, -1) << what << ": segment step is no edge";
      if (e == -1) continue;
      EXPECT_TRUE(cut.is_cut_edge[e]) << what << ": segment edge " << e << " is not cut";
      ++segment_uses[e];
    }
  }
  for (int e = 0; e < ne; ++e)
    EXPECT_EQ(segment_uses[e], cut.is_cut_edge[e] ? 1 : 0) << what << ": edge " << e;

  // Every boundary loop touches the cut unless its component is a disk without interior cones.
  for (const std::vector<int>& loop : t.boundary_loops) {
    const Component& component = t.components[t.vertex_component[loop.front()]];
    bool interior_cone = false;
    for (const int v : component.vertices) interior_cone |= is_cone[v] && !t.is_boundary_vertex[v];
    if (component.genus == 0 && component.num_boundary_loops == 1 && !interior_cone) continue;
    bool touches = false;
    for (const int v : loop) touches |= cut_degree[v] > 0;
    EXPECT_TRUE(touches) << what << ": a boundary loop misses the cut";
  }

  // The slice: same faces mapped back, one disk per component (or the sphere exception).
  CutMesh sliced = slice(t, cut);
  const Topology& s = sliced.topology;
  EXPECT_EQ(sliced.triangles.rows(), t.num_faces) << what;
  EXPECT_GE(static_cast<int>(sliced.to_original.size()), nv) << what;
  for (int v = 0; v < nv; ++v) EXPECT_EQ(sliced.to_original[v], v) << what;
  for (int f = 0; f < t.num_faces; ++f) {
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(sliced.to_original[sliced.triangles(f, k)], t.triangles(f, k)) << what;
  }
  // Copies per vertex: one per wedge between cut and boundary edges.
  std::vector<int> copies(nv, 0);
  for (const int v : sliced.to_original) ++copies[v];
  for (int v = 0; v < nv; ++v) {
    if (t.vertex_component[v] < 0) continue;
    const int wedges = t.is_boundary_vertex[v] ? cut_degree[v] + 1 : std::max(1, cut_degree[v]);
    EXPECT_EQ(copies[v], wedges) << what << ": vertex " << v;
  }
  EXPECT_EQ(s.components.size(), t.components.size()) << what;
  for (std::size_t i = 0; i < t.components.size() && i < s.components.size(); ++i) {
    const Component& original = t.components[i];
    const Component& cut_component = s.components[i];  // both ordered by smallest face
    int cones = 0;
    for (const int v : original.vertices) cones += is_cone[v];
    if (original.genus == 0 && original.num_boundary_loops == 0 && cones < 2) {
      EXPECT_EQ(component_cut_edges[i], 0) << what;
      EXPECT_EQ(cut_component.euler_characteristic, 2) << what;
      EXPECT_EQ(cut_component.num_boundary_loops, 0) << what;
      continue;
    }
    EXPECT_EQ(cut_component.euler_characteristic, 1) << what << ": component " << i;
    EXPECT_EQ(cut_component.num_boundary_loops, 1) << what << ": component " << i;
    // Every cone of a sliced component lies on the disk's boundary.
    for (int w = 0; w < static_cast<int>(sliced.to_original.size()); ++w) {
      const int v = sliced.to_original[w];
      if (is_cone[v] && s.vertex_component[w] == static_cast<int>(i)) {
        EXPECT_TRUE(s.is_boundary_vertex[w]) << what << ": cone " << v << " inside the disk";
      }
    }
  }
  // Every cone is a node, and interior cones not alone on a sphere are on the cut.
  for (const int v : options.cones) {
    EXPECT_TRUE(node_set.count(v)) << what;
    const Component& component = t.components[t.vertex_component[v]];
    int cones = 0;
    for (const int w : component.vertices) cones += is_cone[w];
    const bool lone_sphere_cone =
        component.genus == 0 && component.num_boundary_loops == 0 && cones < 2;
    if (!t.is_boundary_vertex[v] && !lone_sphere_cone) {
      EXPECT_GT(cut_degree[v], 0) << what << ": cone " << v << " off the cut";
    }
  }
}

CutGraph check(const Case& c, const CutGraphOptions& options, const std::string& what) {
  CutGraph cut = cut_graph(c.topology, c.lengths, options);
  expect_valid_cut(c, options, cut, what);
  return cut;
}

void check_with_cones(const Case& c, const std::string& what) {
  for (const int k : {0, 1, 2, 4, 8}) {
    CutGraphOptions options;
    options.cones = spread_cones(c.topology.num_vertices, k);
    check(c, options, what + " with " + std::to_string(k) + " cones");
  }
}

int count_cut_edges(const CutGraph& cut) {
  return static_cast<int>(std::count(cut.is_cut_edge.begin(), cut.is_cut_edge.end(), 1));
}

TEST(CutGraph, SphereWithoutConesHasEmptyCut) {
  const Case c = make_case(make_icosphere(2));
  const CutGraph cut = check(c, {}, "icosphere");
  EXPECT_EQ(count_cut_edges(cut), 0);
  EXPECT_EQ(cut.num_generators, 0);
  EXPECT_TRUE(cut.nodes.empty());
  EXPECT_TRUE(cut.segments.empty());
  EXPECT_EQ(cut.length, 0);
  const CutMesh sliced = slice(c.topology, cut);
  EXPECT_EQ(static_cast<int>(sliced.to_original.size()), c.topology.num_vertices);
  EXPECT_EQ(sliced.triangles, c.topology.triangles);
}

TEST(CutGraph, SphereWithOneConeHasEmptyCutAndTheConeAsNode) {
  const Case c = make_case(make_icosphere(2));
  CutGraphOptions options;
  options.cones = {17};
  const CutGraph cut = check(c, options, "icosphere, one cone");
  EXPECT_EQ(count_cut_edges(cut), 0);
  EXPECT_EQ(cut.nodes, std::vector<int>{17});
  EXPECT_TRUE(cut.segments.empty());
}

TEST(CutGraph, SphereConesAreJoinedByATree) {
  const Case c = make_case(make_icosphere(3));
  for (const int k : {2, 3, 4, 8}) {
    CutGraphOptions options;
    options.cones = spread_cones(c.topology.num_vertices, k);
    const CutGraph cut = check(c, options, "icosphere, " + std::to_string(k) + " cones");
    // A tree: one edge fewer than its vertices.
    std::set<int> vertices;
    for (int e = 0; e < c.topology.num_edges; ++e) {
      if (!cut.is_cut_edge[e]) continue;
      vertices.insert(c.topology.edge_vertices(e, 0));
      vertices.insert(c.topology.edge_vertices(e, 1));
    }
    EXPECT_EQ(count_cut_edges(cut), static_cast<int>(vertices.size()) - 1) << k;
  }
}

TEST(CutGraph, TwoAdjacentConesOnASphereAreCutThroughAThirdVertex) {
  const Case c = make_case(make_icosphere(1));
  CutGraphOptions options;
  options.cones = {c.topology.edge_vertices(0, 0), c.topology.edge_vertices(0, 1)};
  const CutGraph cut = check(c, options, "icosphere, adjacent cones");
  EXPECT_EQ(count_cut_edges(cut), 2);
  EXPECT_FALSE(cut.is_cut_edge[0]);
  ASSERT_EQ(cut.segments.size(), 1u);
  EXPECT_EQ(cut.segments[0].size(), 3u);
}

TEST(CutGraph, DiskWithoutInteriorConesHasEmptyCut) {
  const Case c = make_case(make_disk(6, 0.3));
  const CutGraph cut = check(c, {}, "disk");
  EXPECT_EQ(count_cut_edges(cut), 0);
  CutGraphOptions options;
  options.cones = {c.topology.boundary_loops[0][0], c.topology.boundary_loops[0][5]};
  const CutGraph boundary_cones = check(c, options, "disk, boundary cones");
  EXPECT_EQ(count_cut_edges(boundary_cones), 0);
  EXPECT_EQ(boundary_cones.nodes, (std::vector<int>{std::min(options.cones[0], options.cones[1]),
                                                    std::max(options.cones[0], options.cones[1])}));
}

TEST(CutGraph, DiskConesAreJoinedToTheBoundary) {
  const Case c = make_case(make_disk(8, 0.3));
  check_with_cones(c, "disk");
  // The centre alone: the shortest path is a radius of 8 rings.
  CutGraphOptions options;
  options.cones = {0};
  const CutGraph cut = check(c, options, "disk, centre cone");
  EXPECT_EQ(count_cut_edges(cut), 8);
}

TEST(CutGraph, TorusHasTwoGenerators) {
  const Case c = make_case(make_torus(30, 20));
  check_with_cones(c, "torus");
  const CutGraph cut = cut_graph(c.topology, c.lengths);
  EXPECT_EQ(cut.num_generators, 2);
  // Two loops meeting in one node of cut-degree 4, or a theta graph with two nodes of degree 3.
  EXPECT_TRUE(cut.nodes.size() == 1 || cut.nodes.size() == 2) << cut.nodes.size();
  EXPECT_TRUE(cut.segments.size() == 2 || cut.segments.size() == 3) << cut.segments.size();
}

TEST(CutGraph, ClosedSurfacesOfHigherGenus) {
  for (const int genus : {1, 2, 3}) {
    const Case c = make_case(make_closed_surface(genus, 3 * (2 * genus + 1)));
    check_with_cones(c, "closed genus " + std::to_string(genus));
  }
}

TEST(CutGraph, SurfacesWithHoles) {
  for (const auto& [genus, holes] :
       std::vector<std::pair<int, int>>{{0, 1}, {0, 2}, {0, 3}, {1, 1}, {1, 3}, {2, 2}}) {
    const Case c = make_case(make_surface_with_holes(genus, holes, 6 * (2 * genus + 1)));
    check_with_cones(
        c, "genus " + std::to_string(genus) + " with " + std::to_string(holes) + " holes");
  }
}

TEST(CutGraph, EveryComponentIsCut) {
  const Case c = make_case(
      concatenate({make_torus(12, 8), make_icosphere(1), make_disk(3), make_closed_surface(2, 5),
                   make_surface_with_holes(1, 2, 3), make_icosphere(1)}));
  ASSERT_EQ(c.topology.components.size(), 6u);
  check_with_cones(c, "six components");
  // Two cones on the first sphere only: it is cut, the second sphere is not.
  const int sphere = c.topology.components[1].vertices.front();
  CutGraphOptions options;
  options.cones = {sphere + 3, sphere + 40};
  check(c, options, "six components, cones on one sphere");
}

TEST(CutGraph, UserRootVertex) {
  const Case c = make_case(make_surface_with_holes(1, 2, 6));
  CutGraphOptions options;
  options.cones = spread_cones(c.topology.num_vertices, 2);
  const CutGraph automatic = check(c, options, "automatic root");
  int differs = 0;
  for (const int root : {0, c.topology.boundary_loops[0][0], c.topology.num_vertices - 1}) {
    options.root_vertex = root;
    const CutGraph cut = check(c, options, "root " + std::to_string(root));
    differs += cut.is_cut_edge != automatic.is_cut_edge;
  }
  EXPECT_GT(differs, 0) << "the root vertex changes nothing";
  options.root_vertex = c.topology.num_vertices;
  EXPECT_THROW(cut_graph(c.topology, c.lengths, options), InvalidInput);
  options.root_vertex = -2;
  EXPECT_THROW(cut_graph(c.topology, c.lengths, options), InvalidInput);
}

TEST(CutGraph, RefusesBadInput) {
  const Case c = make_case(make_torus(6, 5));
  CutGraphOptions options;
  options.cones = {3, c.topology.num_vertices};
  try {
    cut_graph(c.topology, c.lengths, options);
    ADD_FAILURE() << "out-of-range cone accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("cone 30"), std::string::npos) << e.what();
  }
  options.cones = {-1};
  EXPECT_THROW(cut_graph(c.topology, c.lengths, options), InvalidInput);
  EXPECT_THROW(cut_graph(c.topology, c.lengths.head(3), {}), InvalidInput);
  Eigen::VectorXd lengths = c.lengths;
  lengths[4] = -1;
  EXPECT_THROW(cut_graph(c.topology, lengths, {}), InvalidInput);
  CutGraph wrong;
  wrong.is_cut_edge.assign(3, 0);
  EXPECT_THROW(slice(c.topology, wrong), InvalidInput);
}

TEST(CutGraph, IsDeterministic) {
  const Case c = make_case(make_surface_with_holes(2, 2, 5));
  CutGraphOptions options;
  options.cones = spread_cones(c.topology.num_vertices, 4);
  const CutGraph a = cut_graph(c.topology, c.lengths, options);
  const CutGraph b = cut_graph(c.topology, c.lengths, options);
  EXPECT_EQ(a.is_cut_edge, b.is_cut_edge);
  EXPECT_EQ(a.nodes, b.nodes);
  EXPECT_EQ(a.segments, b.segments);
  EXPECT_EQ(a.length, b.length);
  const CutMesh sa = slice(c.topology, a), sb = slice(c.topology, b);
  EXPECT_EQ(sa.triangles, sb.triangles);
  EXPECT_EQ(sa.to_original, sb.to_original);
  // Listing the cones in another order, or twice, changes nothing.
  std::reverse(options.cones.begin(), options.cones.end());
  options.cones.push_back(options.cones.front());
  const CutGraph reordered = cut_graph(c.topology, c.lengths, options);
  EXPECT_EQ(reordered.is_cut_edge, a.is_cut_edge);
}

TEST(CutGraph, EveryManifoldSharedMesh) {
  RICCI_REQUIRE_SHARED_MESHES();
  int tested = 0;
  for (const auto& shared : testing::shared_meshes()) {
    // Larger meshes add time, not coverage; degtri_sliding has zero-area faces.
    if (!shared.manifold || !shared.orientable || shared.file == "degtri_sliding.off" ||
        shared.faces > 120000)
      continue;
    const Case c = make_case(read_mesh(shared.path).mesh);
    ASSERT_EQ(expected_generators(c.topology), 2 * shared.genus) << shared.file;
    for (const int k : {0, 8}) {
      CutGraphOptions options;
      options.cones = spread_cones(c.topology.num_vertices, k);
      check(c, options, shared.file + " with " + std::to_string(k) + " cones");
    }
    ++tested;
  }
  EXPECT_GE(tested, 12);
}

TEST(Slice, CopiesFollowTheWedges) {
  // A grid with its middle row of interior edges cut from the left boundary to the centre: the
  // slit's vertices split in two, its tip (a cone) stays whole.
  const Case c = make_case(make_grid(4, 2));
  CutGraph cut;
  cut.is_cut_edge.assign(c.topology.num_edges, 0);
  for (int e = 0; e < c.topology.num_edges; ++e) {
    const int a = c.topology.edge_vertices(e, 0), b = c.topology.edge_vertices(e, 1);
    if ((a == 5 && b == 6) || (a == 6 && b == 7)) cut.is_cut_edge[e] = 1;
  }
  const CutMesh sliced = slice(c.topology, cut);
  std::vector<int> copies(c.topology.num_vertices, 0);
  for (const int v : sliced.to_original) ++copies[v];
  EXPECT_EQ(copies[5], 2);  // on the boundary, one cut edge
  EXPECT_EQ(copies[6], 2);  // interior, two cut edges
  EXPECT_EQ(copies[7], 1);  // the tip
  EXPECT_EQ(static_cast<int>(sliced.to_original.size()), c.topology.num_vertices + 2);
  EXPECT_EQ(sliced.topology.components[0].euler_characteristic, 1);
  EXPECT_EQ(sliced.topology.num_boundary_loops(), 1);
  EXPECT_EQ(sliced.topology.boundary_loops[0].size(), c.topology.boundary_loops[0].size() + 4);
}

}  // namespace
}  // namespace ricci
