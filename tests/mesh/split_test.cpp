// raise_valence (mesh/split.hpp): the splits reach the valence asked for, keep the input's
// vertices first, and the connectivity it returns is the refined mesh's own (so the pipeline's
// valence stage builds it once, not again).
#include "ricci/mesh/split.hpp"

#include <gtest/gtest.h>

#include "ricci/errors.hpp"
#include "ricci/mesh/build_counts.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/topology.hpp"
#include "support/topology_checks.hpp"

namespace ricci {
namespace {

using testing::expect_same_connectivity;

TEST(RaiseValence, ReturnsTheRefinedMeshsOwnConnectivity) {
  const Mesh mesh = make_closed_surface(2, 10);
  const Topology topology = build_topology(mesh.triangles, mesh.num_vertices());
  const int before = topology.vertex_degree[0];
  const ValenceResult r = raise_valence(mesh, topology, 0, before + 9);
  EXPECT_GE(r.final_valence, before + 9);
  EXPECT_EQ(r.topology.vertex_degree[0], r.final_valence);
  EXPECT_EQ(r.mesh.num_vertices(), mesh.num_vertices() + r.splits);
  EXPECT_TRUE(r.mesh.positions.topRows(mesh.num_vertices()) == mesh.positions);
  expect_same_connectivity(r.topology, build_topology(r.mesh.triangles, r.mesh.num_vertices()));
  // The overload that builds the connectivity itself refines the same way.
  const ValenceResult same = raise_valence(mesh, 0, before + 9);
  EXPECT_TRUE(same.mesh.triangles == r.mesh.triangles);
  EXPECT_EQ(same.splits, r.splits);
}

TEST(RaiseValence, BuildsTheConnectivityOncePerRoundOfSplits) {
  const Mesh mesh = make_closed_surface(2, 10);
  const Topology topology = build_topology(mesh.triangles, mesh.num_vertices());
  const int before = topology.vertex_degree[0];
  // Enough splits for one round (each link face split once): one build, the result's.
  const BuildCounts start = build_counts();
  const ValenceResult r = raise_valence(mesh, topology, 0, before + 2);
  EXPECT_EQ((build_counts() - start).topologies, 1) << r.splits << " splits";
  // Nothing to split: no build, the caller's connectivity returned.
  const BuildCounts again = build_counts();
  const ValenceResult kept = raise_valence(mesh, topology, 0, before);
  EXPECT_EQ((build_counts() - again).topologies, 0);
  EXPECT_EQ(kept.splits, 0);
  expect_same_connectivity(kept.topology, topology);
}

TEST(RaiseValence, RefusesAConnectivityOfAnotherMesh) {
  const Mesh mesh = make_closed_surface(2, 10);
  const Mesh other = make_icosphere(1);
  const Topology wrong = build_topology(other.triangles, other.num_vertices());
  EXPECT_THROW(raise_valence(mesh, wrong, 0, 12), InvalidInput);
}

}  // namespace
}  // namespace ricci
