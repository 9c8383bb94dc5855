#pragma once
/// \file
/// Whether two connectivities are the same array for array: what a test compares a Topology
/// against build_topology of the same triangles with (a replayed flip log, a refined mesh).
#include <gtest/gtest.h>

#include "ricci/mesh/topology.hpp"

namespace ricci::testing {

inline void expect_same_connectivity(const Topology& a, const Topology& b) {
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.face_edges, b.face_edges);
  EXPECT_EQ(a.halfedge_edge, b.halfedge_edge);
  EXPECT_EQ(a.halfedge_twin, b.halfedge_twin);
  EXPECT_EQ(a.edge_vertices, b.edge_vertices);
  EXPECT_EQ(a.edge_halfedges, b.edge_halfedges);
  EXPECT_EQ(a.vertex_degree, b.vertex_degree);
}

}  // namespace ricci::testing
