// The passes of repair_mesh one by one (src/mesh/detail/repair_passes.hpp): welding, duplicate
// faces, the pairing around a non-manifold edge, and the vertex copies and orientation.

#include "mesh/detail/repair_passes.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <utility>
#include <vector>

#include "support/test_meshes.hpp"

namespace ricci::mesh_detail {
namespace {

using testing::make_mesh;

std::vector<int> all_faces(int n) {
  std::vector<int> kept(n);
  std::iota(kept.begin(), kept.end(), 0);
  return kept;
}

TEST(Weld, EqualPositionsJoinTheSmallestIndex) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Positions P(6, 3);
  P << 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, nan, 0, 0;
  // Vertex 4 sits on vertex 0 but no face uses it; vertex 5 is not finite.
  const std::vector<char> referenced = {1, 1, 1, 1, 0, 1};
  EXPECT_EQ(weld(P, referenced, 0), (std::vector<int>{0, 1, 0, 1, 4, 5}));
}

TEST(Weld, ToleranceIsRelativeToTheDiagonalAndTransitive) {
  Positions P(6, 3);
  P << 0, 0, 0, 1, 0, 0, 0.5, 0, 0, 0.58, 0, 0, 0.66, 0, 0, 0.85, 0, 0;
  const std::vector<char> referenced(6, 1);
  // A radius of 0.1 (the diagonal is 1): 0.5, 0.58 and 0.66 form a chain; 0.85 stays apart.
  EXPECT_EQ(weld(P, referenced, 0.1), (std::vector<int>{0, 1, 2, 2, 2, 5}));
  // The same chain at a tenth of the scale welds the same way.
  EXPECT_EQ(weld(P * 0.1, referenced, 0.1), (std::vector<int>{0, 1, 2, 2, 2, 5}));
  EXPECT_EQ(weld(P, referenced, 0.01), (std::vector<int>{0, 1, 2, 3, 4, 5}));
}

TEST(FindDuplicateFaces, NamesTheEarliestFaceOnTheSameVerticesInAnyOrder) {
  Triangles T(5, 3);
  T << 0, 1, 2, 2, 1, 0, 3, 4, 5, 1, 2, 0, 0, 1, 3;
  EXPECT_EQ(find_duplicate_faces(T, {1, 1, 1, 1, 1}), (std::vector<int>{-1, 0, -1, 0, -1}));
  // Faces left out neither count as duplicates nor as the face others repeat.
  EXPECT_EQ(find_duplicate_faces(T, {0, 1, 1, 1, 1}), (std::vector<int>{-1, -1, -1, 1, -1}));
}

/// Four pages around edge (0, 1) on the x axis, their third vertices at 0, 90, 180 and 270
/// degrees about it, running 0 -> 1 and 1 -> 0 by turns.
Mesh book_of_four_pages() {
  return make_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, 0, 1}, {0.5, -1, 0}, {0.5, 0, -1}},
                   {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {1, 0, 5}});
}

TEST(PairAroundEdge, PairsEachForwardFaceWithTheBackwardFaceJustBelowIt) {
  const Mesh book = book_of_four_pages();
  // The halfedge of edge (0, 1) is opposite corner 2 in every face.
  const std::vector<std::pair<int, int>> pairs =
      pair_around_edge(book.positions, book.triangles, all_faces(4), {2, 5, 8, 11}, 0, 1);
  // By angle: page 3 (-90 degrees, backward) lies below page 0 (forward), page 1 (backward)
  // below page 2 (forward).
  EXPECT_EQ(pairs, (std::vector<std::pair<int, int>>{{11, 2}, {5, 8}}));
}

TEST(SplitAndOrient, SplitsANonManifoldEdgeIntoTwoSheets) {
  const Mesh book = book_of_four_pages();
  const Split split = split_and_orient(book.positions, book.triangles, all_faces(4), 6, {});
  EXPECT_EQ(split.non_manifold_edges, (std::vector<std::array<int, 2>>{{0, 1}}));
  // Vertices 0 and 1 get a copy per sheet; the sheets are oriented already.
  EXPECT_EQ(split.vertex_map, (std::vector<int>{0, 1, 2, 3, 4, 5, 0, 1}));
  EXPECT_EQ(split.flip, (std::vector<signed char>{0, 0, 0, 0}));
  EXPECT_TRUE(split.non_orientable.empty());
  RepairOptions keep;
  keep.split_non_manifold = false;
  const Split kept = split_and_orient(book.positions, book.triangles, all_faces(4), 6, keep);
  EXPECT_EQ(kept.non_manifold_edges, split.non_manifold_edges);
  EXPECT_EQ(kept.vertex_map, (std::vector<int>{0, 1, 2, 3, 4, 5}));
}

TEST(SplitAndOrient, GivesAVertexOneCopyPerFanAndKeepsTheInputOrder) {
  const Mesh bowtie =
      make_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0, 2, 0}, {1, 2, 0}}, {{0, 1, 2}, {2, 4, 3}});
  const Split split = split_and_orient(bowtie.positions, bowtie.triangles, all_faces(2), 5, {});
  EXPECT_EQ(split.vertex_map, (std::vector<int>{0, 1, 2, 3, 4, 2}));
  EXPECT_EQ(split.corner_output, (std::vector<int>{0, 1, 2, 5, 4, 3}));
  EXPECT_TRUE(split.non_manifold_edges.empty());
}

TEST(SplitAndOrient, ReversesTheMinoritySideOnlyWhenAskedTo) {
  // Both faces run 0 -> 1 along their shared edge.
  const Mesh pair =
      make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}}, {{0, 1, 2}, {0, 1, 3}});
  const Split split = split_and_orient(pair.positions, pair.triangles, all_faces(2), 4, {});
  EXPECT_EQ(split.corner_output, (std::vector<int>{0, 1, 2, 0, 1, 3}));
  EXPECT_EQ(split.flip, (std::vector<signed char>{0, 1}));
  RepairOptions no_orient;
  no_orient.orient = false;
  EXPECT_EQ(split_and_orient(pair.positions, pair.triangles, all_faces(2), 4, no_orient).flip,
            (std::vector<signed char>{0, 0}));
}

TEST(SplitAndOrient, ReportsANonOrientableComponentByItsSeed) {
  // A Moebius strip of six triangles: a band around three stations whose last two faces join
  // its end to its start with a half twist.
  Mesh strip;
  strip.positions.resize(6, 3);
  for (int i = 0; i < 6; ++i) {
    const int station = i / 2;  // two vertices per station
    const double angle = 2 * std::numbers::pi * station / 3;
    const double lift = i % 2 == 0 ? 0.3 : -0.3;
    strip.positions.row(i) << std::cos(angle), std::sin(angle), lift;
  }
  strip.triangles.resize(6, 3);
  strip.triangles << 0, 1, 2, 2, 1, 3, 2, 3, 4, 4, 3, 5, 4, 5, 1, 1, 5, 0;
  const Split split = split_and_orient(strip.positions, strip.triangles, all_faces(6), 6, {});
  EXPECT_EQ(split.non_orientable, (std::vector<int>{0}));
  EXPECT_EQ(split.flip, (std::vector<signed char>(6, 0)));
}

}  // namespace
}  // namespace ricci::mesh_detail
