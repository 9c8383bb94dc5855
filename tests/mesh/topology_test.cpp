#include "ricci/mesh/topology.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <initializer_list>
#include <numbers>
#include <string>

#include "ricci/errors.hpp"
#include "ricci/mesh/components.hpp"

namespace ricci {
namespace {

Triangles make_triangles(std::initializer_list<std::array<int, 3>> triangles) {
  Triangles out(static_cast<Eigen::Index>(triangles.size()), 3);
  Eigen::Index i = 0;
  for (const auto& t : triangles) out.row(i++) << t[0], t[1], t[2];
  return out;
}

const Triangles kTetrahedron = make_triangles({{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}});

/// Square [0,1]^2 split along its diagonal (0, 2), counter-clockwise.
const Triangles kSquare = make_triangles({{0, 1, 2}, {0, 2, 3}});

/// Square annulus: outer square 0-3, inner square 4-7, eight triangles between them.
const Triangles kAnnulus = make_triangles(
    {{0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}});

/// Torus grid of n by m quads split into triangles (connectivity only).
Triangles torus_triangles(int n, int m) {
  Triangles out(2 * n * m, 3);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const int a = i * m + j, b = ((i + 1) % n) * m + j, c = ((i + 1) % n) * m + (j + 1) % m,
                d = i * m + (j + 1) % m;
      out.row(2 * a) << a, b, c;
      out.row(2 * a + 1) << a, c, d;
    }
  }
  return out;
}

/// Checks the invariants every topology satisfies, independently of how it was built.
void expect_consistent(const Topology& t) {
  const int nh = 3 * t.num_faces;
  ASSERT_EQ(static_cast<int>(t.halfedge_twin.size()), nh);
  for (int h = 0; h < nh; ++h) {
    const int g = t.halfedge_twin[h];
    const int e = t.halfedge_edge[h];
    EXPECT_EQ(t.face_edges(h / 3, h % 3), e);
    EXPECT_EQ(t.edge_vertices(e, 0), std::min(t.tail(h), t.head(h)));
    EXPECT_EQ(t.edge_vertices(e, 1), std::max(t.tail(h), t.head(h)));
    if (g < 0) {
      EXPECT_TRUE(t.is_boundary_edge[e]);
      continue;
    }
    EXPECT_EQ(t.halfedge_twin[g], h);
    EXPECT_EQ(t.tail(g), t.head(h));  // opposite directions
    EXPECT_EQ(t.head(g), t.tail(h));
    EXPECT_EQ(t.halfedge_edge[g], e);
    EXPECT_FALSE(t.is_boundary_edge[e]);
  }
  for (const auto& loop : t.boundary_loops) {
    // Consecutive loop vertices are joined by a boundary halfedge running that way, which puts
    // the surface on the left of the loop.
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const int a = loop[i], b = loop[(i + 1) % loop.size()];
      bool found = false;
      for (int h = 0; h < nh; ++h) {
        found |= t.halfedge_twin[h] < 0 && t.tail(h) == a && t.head(h) == b;
      }
      EXPECT_TRUE(found) << "no boundary halfedge " << a << " -> " << b;
    }
  }
}

TEST(BuildTopology, TetrahedronCountsAndTwins) {
  const Topology t = build_topology(kTetrahedron, 4);
  expect_consistent(t);
  EXPECT_EQ(t.num_vertices, 4);
  EXPECT_EQ(t.num_edges, 6);
  EXPECT_EQ(t.num_faces, 4);
  EXPECT_EQ(t.num_boundary_loops(), 0);
  EXPECT_EQ(t.euler_characteristic(), 2);
  EXPECT_EQ(t.vertex_degree, (std::vector<int>{3, 3, 3, 3}));
  for (int h = 0; h < 12; ++h) EXPECT_GE(t.halfedge_twin[h], 0);
  // Halfedge 0 of face 0 runs 1 -> 2 and its twin lies in face 3 = (1, 3, 2), opposite corner 1.
  EXPECT_EQ(t.tail(0), 1);
  EXPECT_EQ(t.head(0), 2);
  EXPECT_EQ(t.halfedge_twin[0], 3 * 3 + 1);
  ASSERT_EQ(t.components.size(), 1u);
  EXPECT_EQ(t.components[0].euler_characteristic, 2);
  EXPECT_EQ(t.components[0].genus, 0);
}

TEST(BuildTopology, SquareBoundaryLoopRunsCounterClockwise) {
  const Topology t = build_topology(kSquare, 4);
  expect_consistent(t);
  EXPECT_EQ(t.num_edges, 5);
  ASSERT_EQ(t.boundary_loops.size(), 1u);
  // The first boundary halfedge is halfedge 0 (1 -> 2); the loop then follows the surface.
  EXPECT_EQ(t.boundary_loops[0], (std::vector<int>{1, 2, 3, 0}));
  EXPECT_EQ(t.euler_characteristic(), 1);
  EXPECT_EQ(t.components[0].genus, 0);
  int boundary_edges = 0;
  for (char b : t.is_boundary_edge) boundary_edges += b;
  EXPECT_EQ(boundary_edges, 4);
  EXPECT_EQ(t.vertex_degree, (std::vector<int>{3, 2, 3, 2}));
}

TEST(BuildTopology, AnnulusHasTwoOppositeLoops) {
  const Topology t = build_topology(kAnnulus, 8);
  expect_consistent(t);
  EXPECT_EQ(t.num_edges, 16);
  ASSERT_EQ(t.boundary_loops.size(), 2u);
  EXPECT_EQ(t.boundary_loops[0], (std::vector<int>{0, 1, 2, 3}));  // outer: counter-clockwise
  EXPECT_EQ(t.boundary_loops[1], (std::vector<int>{5, 4, 7, 6}));  // inner: clockwise
  EXPECT_EQ(t.euler_characteristic(), 0);
  EXPECT_EQ(t.components[0].num_boundary_loops, 2);
  EXPECT_EQ(t.components[0].genus, 0);
}

TEST(BuildTopology, TorusHasGenusOne) {
  const Topology t = build_topology(torus_triangles(6, 4), 24);
  expect_consistent(t);
  EXPECT_EQ(t.num_edges, 72);
  EXPECT_EQ(t.euler_characteristic(), 0);
  ASSERT_EQ(t.components.size(), 1u);
  EXPECT_EQ(t.components[0].genus, 1);
  for (int d : t.vertex_degree) EXPECT_EQ(d, 6);
}

TEST(BuildTopology, ComponentsAndUnreferencedVertices) {
  // A square on 5, 6, 7, 8 listed first, vertex 4 unused, then the tetrahedron on 0-3.
  const Triangles triangles =
      make_triangles({{5, 6, 7}, {0, 1, 2}, {5, 7, 8}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}});
  const Topology t = build_topology(triangles, 9);
  expect_consistent(t);
  ASSERT_EQ(t.components.size(), 2u);
  EXPECT_EQ(t.components[0].faces, (std::vector<int>{0, 2}));
  EXPECT_EQ(t.components[0].vertices, (std::vector<int>{5, 6, 7, 8}));
  EXPECT_EQ(t.components[0].euler_characteristic, 1);
  EXPECT_EQ(t.components[0].num_boundary_loops, 1);
  EXPECT_EQ(t.components[1].faces, (std::vector<int>{1, 3, 4, 5}));
  EXPECT_EQ(t.components[1].num_edges, 6);
  EXPECT_EQ(t.components[1].euler_characteristic, 2);
  EXPECT_EQ(t.vertex_component, (std::vector<int>{1, 1, 1, 1, -1, 0, 0, 0, 0}));
  EXPECT_EQ(t.num_referenced_vertices(), 8);
  EXPECT_EQ(t.euler_characteristic(), 3);
}

TEST(BuildTopology, ThrowsOnNonManifoldEdge) {
  const Triangles fin = make_triangles({{0, 1, 2}, {1, 3, 2}, {1, 4, 2}});
  try {
    build_topology(fin, 5);
    FAIL() << "no exception";
  } catch (const TopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("non-manifold edge (1, 2)"), std::string::npos)
        << e.what();
  }
}

TEST(BuildTopology, ThrowsOnNonManifoldVertex) {
  const Triangles bowtie = make_triangles({{0, 1, 2}, {2, 4, 3}});
  try {
    build_topology(bowtie, 5);
    FAIL() << "no exception";
  } catch (const TopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("non-manifold vertex 2"), std::string::npos) << e.what();
  }
}

TEST(BuildTopology, ThrowsOnInconsistentOrientation) {
  const Triangles flipped = make_triangles({{0, 1, 2}, {3, 1, 2}});
  try {
    build_topology(flipped, 4);
    FAIL() << "no exception";
  } catch (const TopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("faces 0 and 1"), std::string::npos) << e.what();
  }
}

TEST(BuildTopology, FirstHalfedgeFlagsPickEachEdgesFirstHalfedge) {
  const Topology plain = build_topology(torus_triangles(6, 4), 24);
  // Flag the halfedge the plain build puts second on every interior edge: they all swap, and
  // nothing else changes.
  std::vector<char> first(3 * plain.num_faces, 0);
  for (int e = 0; e < plain.num_edges; ++e) {
    first[plain.edge_halfedges(e, 1) >= 0 ? plain.edge_halfedges(e, 1)
                                          : plain.edge_halfedges(e, 0)] = 1;
  }
  const Topology t = build_topology(torus_triangles(6, 4), 24, first);
  expect_consistent(t);
  ASSERT_EQ(t.num_edges, plain.num_edges);
  for (int e = 0; e < t.num_edges; ++e) {
    EXPECT_EQ(t.edge_halfedges(e, 0), plain.edge_halfedges(e, 1));
    EXPECT_EQ(t.edge_halfedges(e, 1), plain.edge_halfedges(e, 0));
  }
  EXPECT_EQ(t.halfedge_edge, plain.halfedge_edge);
  EXPECT_EQ(t.components[0].num_edges, plain.components[0].num_edges);
  // The plain build's own choice flagged: the same edges.
  std::vector<char> own(3 * plain.num_faces, 0);
  for (int e = 0; e < plain.num_edges; ++e) own[plain.edge_halfedges(e, 0)] = 1;
  EXPECT_EQ(build_topology(torus_triangles(6, 4), 24, own).edge_halfedges, plain.edge_halfedges);
}

TEST(BuildTopology, FirstHalfedgeFlagsKeepABoundaryEdgesOnlyHalfedge) {
  const Topology plain = build_topology(kSquare, 4);
  const Topology t = build_topology(kSquare, 4, std::vector<char>(3 * plain.num_faces, 0));
  EXPECT_EQ(t.edge_halfedges, plain.edge_halfedges);
  EXPECT_THROW(build_topology(kSquare, 4, std::vector<char>(5, 0)), InvalidInput);
}

TEST(BuildTopology, ThrowsInvalidInputOnBadIndices) {
  EXPECT_THROW(build_topology(make_triangles({{0, 1, 4}}), 4), InvalidInput);
  EXPECT_THROW(build_topology(make_triangles({{0, 1, -1}}), 4), InvalidInput);
  EXPECT_THROW(build_topology(make_triangles({{0, 1, 1}}), 4), InvalidInput);
}

TEST(SplitComponents, LocalIndicesAndMapsBack) {
  Mesh mesh;
  mesh.triangles =
      make_triangles({{5, 6, 7}, {0, 1, 2}, {5, 7, 8}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}});
  mesh.positions.resize(9, 3);
  for (int v = 0; v < 9; ++v) mesh.positions.row(v) << v, 2 * v, -v;
  const Topology t = build_topology(mesh.triangles, 9);
  const std::vector<Submesh> parts = split_components(mesh, t);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].vertex_map, (std::vector<int>{5, 6, 7, 8}));
  EXPECT_EQ(parts[0].face_map, (std::vector<int>{0, 2}));
  EXPECT_EQ(parts[0].mesh.triangles, make_triangles({{0, 1, 2}, {0, 2, 3}}));
  EXPECT_EQ(parts[1].mesh.num_vertices(), 4);
  EXPECT_EQ(parts[1].mesh.num_faces(), 4);
  for (const Submesh& part : parts) {
    for (int f = 0; f < part.mesh.num_faces(); ++f) {
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(part.vertex_map[part.mesh.triangles(f, k)], mesh.triangles(part.face_map[f], k));
      }
    }
    for (int v = 0; v < part.mesh.num_vertices(); ++v) {
      EXPECT_EQ(part.mesh.positions.row(v), mesh.positions.row(part.vertex_map[v]));
    }
    // Each part is a valid mesh on its own.
    EXPECT_EQ(build_topology(part.mesh.triangles, part.mesh.num_vertices()).components.size(), 1u);
  }
}

}  // namespace
}  // namespace ricci
