// The Fuchsian group of a cut surface: regular hyperbolic polygons with canonical and
// non-canonical side pairings, several nodes, random one-vertex surface words made by cut and
// paste, malformed words, and the symbolic check that the canonical relator is a conjugate of the
// reduced one.

#include "ricci/hyperbolic/fuchsian.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <numbers>
#include <random>

#include "ricci/errors.hpp"
#include "support/hyperbolic_polygons.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;
using testing::PairedPolygon;

/// a_1 b_1 a_1^-1 b_1^-1 ... spelled in the segments.
SegmentWord canonical_relator_in_segments(const FuchsianGroup& group) {
  SegmentWord w;
  for (int k = 0; k < group.genus; ++k) {
    const SegmentWord ia = inverse(group.a_words[k]), ib = inverse(group.b_words[k]);
    for (const SegmentWord* part : {&group.a_words[k], &group.b_words[k], &ia, &ib}) {
      w.insert(w.end(), part->begin(), part->end());
    }
  }
  return w;
}

/// Everything a correct result satisfies whatever the input: 2 g generators, words in the
/// generator segments that evaluate to the matrices, the symbolic relation.
void expect_consistent(const FuchsianGroup& group, const SegmentRelations& relations,
                       double matrix_tolerance) {
  ASSERT_EQ(static_cast<int>(group.a.size()), group.genus);
  ASSERT_EQ(static_cast<int>(group.b.size()), group.genus);
  ASSERT_EQ(static_cast<int>(group.generator_segments.size()), 2 * group.genus);
  EXPECT_EQ(group.relator.size(), 4u * group.genus);
  EXPECT_EQ(group.tree_segments.size() + group.generator_segments.size(),
            relations.segment_maps.size());
  for (int k = 0; k < group.genus; ++k) {
    for (const auto* words : {&group.a_words, &group.b_words}) {
      for (const auto& [segment, sign] : (*words)[k]) {
        EXPECT_TRUE(std::binary_search(group.generator_segments.begin(),
                                       group.generator_segments.end(), segment));
      }
    }
    const Mobius a = evaluate(group.a_words[k], relations.segment_maps);
    const Mobius b = evaluate(group.b_words[k], relations.segment_maps);
    EXPECT_LT(distance_to_identity(compose(inverse(a), group.a[k])), matrix_tolerance) << k;
    EXPECT_LT(distance_to_identity(compose(inverse(b), group.b[k])), matrix_tolerance) << k;
  }
  // Symbolic: the canonical relator, each generator spelled in the segments, reduces to a cyclic
  // conjugate of the Tietze-reduced relator.
  EXPECT_TRUE(is_rotation(cyclic_reduce(canonical_relator_in_segments(group)),
                          cyclic_reduce(group.relator)));
}

/// The group of relations read off an exact polygon, with what such a group meets: the genus,
/// the node relations to 1e-12 and the surface relation to 1e-11, and expect_consistent with
/// `matrix_tolerance`.
FuchsianGroup exact_polygon_group(const SegmentRelations& relations, int genus,
                                  double matrix_tolerance) {
  FuchsianGroup group = fuchsian_group(relations);
  EXPECT_EQ(group.genus, genus);
  EXPECT_LT(group.node_residual, 1e-12);
  EXPECT_LT(group.relation_residual, 1e-11) << "scale " << group.relation_scale;
  expect_consistent(group, relations, matrix_tolerance);
  return group;
}

TEST(FuchsianWords, FreeAndCyclicReduction) {
  const SegmentWord w = {{0, 1}, {1, 1}, {1, -1}, {2, 1}, {0, -1}};
  EXPECT_EQ(free_reduce(w), (SegmentWord{{0, 1}, {2, 1}, {0, -1}}));
  EXPECT_EQ(cyclic_reduce(w), (SegmentWord{{2, 1}}));
  EXPECT_EQ(inverse(SegmentWord{{0, 1}, {3, -1}}), (SegmentWord{{3, 1}, {0, -1}}));
  EXPECT_TRUE(is_rotation({{0, 1}, {1, 1}, {2, -1}}, {{2, -1}, {0, 1}, {1, 1}}));
  EXPECT_FALSE(is_rotation({{0, 1}, {1, 1}, {2, -1}}, {{1, 1}, {0, 1}, {2, -1}}));
  EXPECT_TRUE(free_reduce({{4, 1}, {4, -1}}).empty());
}

TEST(FuchsianGroup, RegularPolygonClosedForm) {
  // The octagon's corners at 2^(-1/4) (cosh R = (1 + sqrt 2)^2).
  const auto octagon = testing::regular_polygon(8, std::numbers::pi / 4);
  EXPECT_NEAR(std::abs(octagon[3]), std::pow(2.0, -0.25), 1e-15);
  // Side pairings of equal sides are exact; the vertex cycle of a_1 b_1 a_1^-1 b_1^-1 ... is a
  // relation of the side pairings.
  for (int genus : {2, 3}) {
    const PairedPolygon p =
        testing::regular_surface_polygon(genus, testing::canonical_sides(genus));
    double mismatch = 1;
    const auto maps = testing::side_pairings(p, &mismatch);
    EXPECT_LT(mismatch, 1e-14);
    const auto cycles = testing::vertex_cycles(p.sides);
    ASSERT_EQ(cycles.size(), 1u);
    EXPECT_EQ(cycles[0].size(), 4u * genus);
    EXPECT_LT(distance_to_identity(evaluate(cycles[0], maps)), 1e-12);
  }
}

TEST(FuchsianGroup, CanonicalSidePairing) {
  for (int genus : {2, 3}) {
    const SegmentRelations relations = testing::polygon_relations(
        testing::regular_surface_polygon(genus, testing::canonical_sides(genus)));
    const FuchsianGroup group = exact_polygon_group(relations, genus, 1e-12);
    EXPECT_TRUE(group.tree_segments.empty());
    // Every generator is hyperbolic (a Fuchsian group of a closed surface has no elliptic or
    // parabolic elements).
    for (int k = 0; k < genus; ++k) {
      EXPECT_GT(half_trace(group.a[k]), 1.0 + 1e-3);
      EXPECT_GT(half_trace(group.b[k]), 1.0 + 1e-3);
    }
  }
}

TEST(FuchsianGroup, OppositeSidesPaired) {
  // x_1 .. x_2g x_1^-1 .. x_2g^-1 on the regular 4g-gon: one vertex class, non-canonical word.
  for (int genus : {2, 3}) {
    const SegmentRelations relations = testing::polygon_relations(
        testing::regular_surface_polygon(genus, testing::opposite_sides(2 * genus)));
    ASSERT_EQ(relations.node_words.size(), 1u);
    exact_polygon_group(relations, genus, 1e-11);
  }
}

TEST(FuchsianGroup, TwoVertexClassesOfTheOppositeSided4gPlus2Gon) {
  // The regular (4g + 2)-gon with opposite sides paired has two vertex classes of 2g + 1 corners:
  // interior angle 2 pi / (2g + 1), a cut graph with 2 nodes and 2g + 1 segments.
  for (int genus : {2, 3}) {
    const int n = 4 * genus + 2;
    const PairedPolygon p{testing::regular_polygon(n, 2 * std::numbers::pi / (2 * genus + 1), 0.2),
                          testing::opposite_sides(2 * genus + 1)};
    const SegmentRelations relations = testing::polygon_relations(p);
    ASSERT_EQ(relations.node_words.size(), 2u);
    const FuchsianGroup group = exact_polygon_group(relations, genus, 1e-11);
    EXPECT_EQ(group.tree_segments.size(), 1u);
  }
}

/// Splits both sides of `segment` at their hyperbolic midpoints: the first halves keep the
/// label, the second halves get a new segment; the midpoints form a new vertex class (two
/// corners of angle pi).
PairedPolygon split_segment(const PairedPolygon& p, int segment) {
  int next_segment = 0;
  for (const auto& letter : p.sides) next_segment = std::max(next_segment, letter.first + 1);
  const int n = static_cast<int>(p.sides.size());
  PairedPolygon q;
  for (int k = 0; k < n; ++k) {
    const Complex from = p.corners[k], to = p.corners[(k + 1) % n];
    q.corners.push_back(from);
    q.sides.push_back(p.sides[k]);
    if (p.sides[k].first != segment) continue;
    const Mobius t = translation_to_origin(from);
    const Complex image = apply_mobius(t, to);
    const double half = std::tanh(0.25 * disk_distance(from, to));  // Euclidean radius of d / 2
    q.corners.push_back(apply_mobius(inverse(t), half * image / std::abs(image)));
    // s = s' s'': a side labelled s runs s' then s''; one labelled s^-1 runs s''^-1 then s'^-1.
    if (p.sides[k].second > 0) {
      q.sides.push_back({next_segment, 1});
    } else {
      q.sides.back() = {next_segment, -1};
      q.sides.push_back({segment, -1});
    }
  }
  return q;
}

TEST(FuchsianGroup, SplitSidesGiveMoreNodes) {
  for (int genus : {2, 3}) {
    PairedPolygon p = testing::regular_surface_polygon(genus, testing::canonical_sides(genus));
    // Split three segments, one of them twice: 1 + 4 nodes, 4g + 4 segments.
    for (int segment : {0, 3, 1, 0}) p = split_segment(p, segment);
    double mismatch = 1;
    testing::side_pairings(p, &mismatch);
    EXPECT_LT(mismatch, 1e-13);
    const SegmentRelations relations = testing::polygon_relations(p);
    ASSERT_EQ(relations.node_words.size(), 5u);
    const FuchsianGroup group = exact_polygon_group(relations, genus, 1e-11);
    EXPECT_EQ(group.tree_segments.size(), 4u);

    // The same relations with the node words rotated and listed in another order.
    SegmentRelations shuffled = relations;
    std::mt19937 random(genus);
    for (auto& w : shuffled.node_words) {
      std::rotate(w.begin(), w.begin() + random() % w.size(), w.end());
    }
    std::shuffle(shuffled.node_words.begin(), shuffled.node_words.end(), random);
    const FuchsianGroup again = fuchsian_group(shuffled);
    EXPECT_EQ(again.genus, genus);
    EXPECT_LT(again.relation_residual, 1e-12);
    expect_consistent(again, shuffled, 1e-11);
  }
}

/// A random side pairing of the regular 4g-gon: sides labelled by a random arrangement of
/// s_1, s_1^-1, ..., s_2g, s_2g^-1, drawn until its corners form one vertex class (the angle sum
/// 4g * 2 pi / 4g = 2 pi then makes it a fundamental polygon of a closed surface of genus g, by
/// Poincare's polygon theorem).
PairedPolygon random_pairing(int genus, std::mt19937& random) {
  SegmentWord sides;
  for (int s = 0; s < 2 * genus; ++s) {
    sides.push_back({s, 1});
    sides.push_back({s, -1});
  }
  do {
    std::shuffle(sides.begin(), sides.end(), random);
  } while (testing::vertex_cycles(sides).size() != 1);
  return testing::regular_surface_polygon(genus, sides);
}

TEST(FuchsianGroup, RandomSidePairingsReachTheNormalForm) {
  std::mt19937 random(11);
  int non_canonical = 0;
  double worst_relation[6] = {0, 0, 0, 0, 0, 0};
  std::size_t longest_word = 0;
  for (int trial = 0; trial < 80; ++trial) {
    const int genus = 2 + trial % 4;
    const PairedPolygon polygon = random_pairing(genus, random);
    const SegmentRelations relations = testing::polygon_relations(polygon);
    non_canonical += polygon.sides != testing::canonical_sides(genus);
    const FuchsianGroup group = fuchsian_group(relations);
    EXPECT_EQ(group.genus, genus);
    EXPECT_TRUE(is_rotation(group.relator, cyclic_reduce(relations.node_words[0])));
    EXPECT_LT(group.node_residual, 1e-10);
    // Symbolic check at every genus; the numbers only up to genus 3: from genus 4 on, the
    // generators that cut and paste finds for a random pairing can be long words whose
    // commutators' partial products are large, and the relation loses digits accordingly.
    if (genus <= 3) {
      EXPECT_LT(group.relation_residual, 1e-9)
          << "trial " << trial << " scale " << group.relation_scale;
      expect_consistent(group, relations, 1e-9);
    } else {
      EXPECT_TRUE(is_rotation(cyclic_reduce(canonical_relator_in_segments(group)),
                              cyclic_reduce(group.relator)));
    }
    worst_relation[genus] = std::max(worst_relation[genus], group.relation_residual);
    for (int k = 0; k < genus; ++k) {
      longest_word = std::max({longest_word, group.a_words[k].size(), group.b_words[k].size()});
    }
  }
  EXPECT_GT(non_canonical, 70);
  std::printf(
      "[ measured ] 20 random pairings per genus: worst relation residual g2 %.1e, g3 "
      "%.1e, g4 %.1e, g5 %.1e; longest generator word %zu\n",
      worst_relation[2], worst_relation[3], worst_relation[4], worst_relation[5], longest_word);
}

TEST(FuchsianGroup, PerturbedMapsShowInTheResiduals) {
  const int genus = 2;
  PairedPolygon p = testing::regular_surface_polygon(genus, testing::opposite_sides(2 * genus));
  p = split_segment(p, 1);
  const SegmentRelations relations = testing::polygon_relations(p);
  const FuchsianGroup exact = fuchsian_group(relations);
  ASSERT_LT(exact.relation_residual, 1e-12);
  const Mobius nudge = translation_to_origin({1e-6, 0.0});
  // A generator segment: both residuals see it.
  SegmentRelations perturbed = relations;
  const int generator = exact.generator_segments[0];
  perturbed.segment_maps[generator] = compose(nudge, perturbed.segment_maps[generator]);
  FuchsianGroup group = fuchsian_group(perturbed);
  EXPECT_GT(group.relation_residual, 1e-7);
  EXPECT_GT(group.node_residual, 1e-7);
  // A tree segment is eliminated from the relator: only the node residual sees it.
  ASSERT_EQ(exact.tree_segments.size(), 1u);
  perturbed = relations;
  const int tree = exact.tree_segments[0];
  perturbed.segment_maps[tree] = compose(nudge, perturbed.segment_maps[tree]);
  group = fuchsian_group(perturbed);
  EXPECT_LT(group.relation_residual, 1e-12);
  EXPECT_GT(group.node_residual, 1e-7);
}

TEST(FuchsianGroup, LowGenus) {
  // A sphere cut along one segment between two nodes: no generators.
  SegmentRelations sphere{{Mobius{}}, {{{0, 1}}, {{0, -1}}}};
  const FuchsianGroup g0 = fuchsian_group(sphere);
  EXPECT_EQ(g0.genus, 0);
  EXPECT_TRUE(g0.a.empty());
  EXPECT_EQ(g0.relation_residual, 0.0);
  // A torus: two commuting translations along the real axis, a b a^-1 b^-1 = I.
  SegmentRelations torus{{translation_to_origin(0.3), translation_to_origin(-0.5)},
                         {testing::canonical_sides(1)}};
  const FuchsianGroup g1 = fuchsian_group(torus);
  EXPECT_EQ(g1.genus, 1);
  EXPECT_LT(g1.relation_residual, 1e-15);
  expect_consistent(g1, torus, 1e-12);
}

TEST(FuchsianGroup, MalformedWordsThrow) {
  const std::vector<Mobius> two(2), three(3), four(4);
  auto throws = [](const SegmentRelations& r, const std::string& phrase) {
    try {
      fuchsian_group(r);
      ADD_FAILURE() << "no exception; expected \"" << phrase << "\"";
    } catch (const InvalidInput& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("fuchsian_group"), std::string::npos) << message;
      EXPECT_NE(message.find(phrase), std::string::npos) << message;
    }
  };
  throws({two, {}}, "no node words");
  throws({two, {{}}}, "node word 0 is empty");
  throws({two, {{{0, 1}, {1, 1}, {0, -1}}}}, "segment 1 occurs only once");
  throws({two, {{{0, 1}, {1, 1}, {0, -1}, {1, 1}}}}, "segment 1 occurs more than once");
  throws({two, {{{0, 1}, {0, -1}}}}, "segment 1 occurs in no node word");
  throws({two, {{{0, 1}, {2, 1}, {0, -1}, {2, -1}}}}, "letter (2, 1)");
  throws({two, {{{0, 2}, {1, 1}, {0, -1}, {1, -1}}}}, "letter (0, 2)");
  // Two separate tori.
  throws({four, {testing::canonical_sides(1), {{2, 1}, {3, 1}, {2, -1}, {3, -1}}}},
         "node 1 is not connected");
  // a b a^-1 c b^-1 c^-1: each letter twice with opposite signs, but the hexagon's corners make
  // two vertices (a torus with two vertices, not a cut into one disk).
  throws({three, {{{0, 1}, {1, 1}, {0, -1}, {2, 1}, {1, -1}, {2, -1}}}}, "into 2 vertices");
  // a a^-1 b b^-1: letters cancel.
  throws({two, {{{0, 1}, {0, -1}, {1, 1}, {1, -1}}}}, "letters cancelled");
  // A map that is not in SU(1,1) up to scale.
  throws({{Mobius{0.5, 1.0}, Mobius{}}, {testing::canonical_sides(1)}}, "segment map 0");
}

}  // namespace
}  // namespace ricci
