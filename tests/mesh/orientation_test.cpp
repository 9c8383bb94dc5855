// The orientation search shared by repair_mesh and find_defects (src/mesh/detail/orientation.hpp):
// the sides it gives, the side it reverses, and the contradiction of a Moebius strip.

#include "mesh/detail/orientation.hpp"

#include <gtest/gtest.h>

#include <map>
#include <utility>
#include <vector>

#include "ricci/mesh/generate.hpp"
#include "support/test_meshes.hpp"

namespace ricci {
namespace {

using mesh_detail::OrientationSearch;
using mesh_detail::search_orientation;

/// Halfedge h = 3 f + k runs from corner k + 1 to corner k + 2 of face f (opposite corner k).
int tail_of(const Triangles& triangles, int h) {
  return triangles(h / 3, (h % 3 + 1) % 3);
}
int head_of(const Triangles& triangles, int h) {
  return triangles(h / 3, (h % 3 + 2) % 3);
}

/// Twins across edges of exactly two faces, -1 elsewhere, computed independently of the module.
std::vector<int> twins(const Triangles& triangles) {
  std::map<std::pair<int, int>, std::vector<int>> halfedges_of_edge;
  for (int h = 0; h < 3 * static_cast<int>(triangles.rows()); ++h) {
    const int a = tail_of(triangles, h), b = head_of(triangles, h);
    halfedges_of_edge[{std::min(a, b), std::max(a, b)}].push_back(h);
  }
  std::vector<int> twin(3 * triangles.rows(), -1);
  for (const auto& [edge, halfedges] : halfedges_of_edge) {
    if (halfedges.size() != 2) continue;
    twin[halfedges[0]] = halfedges[1];
    twin[halfedges[1]] = halfedges[0];
  }
  return twin;
}

OrientationSearch search(const Triangles& triangles, const std::vector<char>& included) {
  return search_orientation(
      twins(triangles), [&](int h) { return tail_of(triangles, h); },
      [&](int f) { return included[f] != 0; });
}

TEST(Orientation, ReversesTheSmallerSideOfEachComponent) {
  // Two grids side by side in one array: in the first, faces 1 and 4 reversed; in the second,
  // all but face 0 reversed, so that face 0 is the side to reverse.
  const Mesh grid = make_grid(3, 2);  // 12 faces
  const int nf = grid.num_faces(), nv = grid.num_vertices();
  Triangles triangles(2 * nf, 3);
  triangles.topRows(nf) = grid.triangles;
  triangles.bottomRows(nf) = grid.triangles.array() + nv;
  auto reverse = [&](int f) { std::swap(triangles(f, 1), triangles(f, 2)); };
  reverse(1);
  reverse(4);
  for (int f = nf + 1; f < 2 * nf; ++f) reverse(f);

  const OrientationSearch s = search(triangles, std::vector<char>(2 * nf, 1));
  ASSERT_EQ(s.components.size(), 2u);
  EXPECT_EQ(s.order.size(), static_cast<std::size_t>(2 * nf));
  for (int c = 0; c < 2; ++c) {
    const auto& component = s.components[c];
    EXPECT_EQ(component.seed, c * nf);
    EXPECT_EQ(component.size(), nf);
    EXPECT_EQ(component.conflict, -1);
  }
  // First grid: faces 1 and 4 disagree with seed 0 and are the smaller side.
  EXPECT_EQ(s.components[0].to_reverse(), 2);
  for (int f = 0; f < nf; ++f) {
    EXPECT_EQ(s.side[f] == s.components[0].minority(), f == 1 || f == 4) << f;
  }
  // Second grid: the seed's own side (side 0) is the smaller one.
  EXPECT_EQ(s.components[1].minority(), 0);
  EXPECT_EQ(s.components[1].to_reverse(), 1);
  EXPECT_EQ(s.side[nf], 0);
}

TEST(Orientation, TieReversesSideOne) {
  // Two faces sharing an edge in the same direction: one face each side; side 1 is reversed.
  Triangles triangles(2, 3);
  triangles << 0, 1, 2, 0, 1, 3;
  const OrientationSearch s = search(triangles, {1, 1});
  ASSERT_EQ(s.components.size(), 1u);
  EXPECT_EQ(s.components[0].minority(), 1);
  EXPECT_EQ(s.side[0], 0);
  EXPECT_EQ(s.side[1], 1);
}

TEST(Orientation, MoebiusStripHasAContradiction) {
  const Mesh strip = testing::moebius_strip(7);
  const OrientationSearch s = search(strip.triangles, std::vector<char>(strip.num_faces(), 1));
  ASSERT_EQ(s.components.size(), 1u);
  const int h = s.components[0].conflict;
  ASSERT_GE(h, 0);
  EXPECT_EQ(s.components[0].size(), strip.num_faces());
  // The contradiction is at an edge of two faces.
  EXPECT_GE(twins(strip.triangles)[h], 0);
}

TEST(Orientation, FacesLeftOutHaveNoSide) {
  // Two faces not connected: the second is left out, so only the first is searched.
  Triangles triangles(2, 3);
  triangles << 0, 1, 2, 3, 4, 5;
  const OrientationSearch s = search(triangles, {1, 0});
  ASSERT_EQ(s.components.size(), 1u);
  EXPECT_EQ(s.side[0], 0);
  EXPECT_EQ(s.side[1], -1);
  EXPECT_EQ(s.order, std::vector<int>{0});
}

}  // namespace
}  // namespace ricci
