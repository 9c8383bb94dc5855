#pragma once
/// \file
/// The Fuchsian group of a closed surface of genus g cut into a disk and laid out in the Poincare
/// disk: from the deck transformations across the cut segments (one Moebius map per segment) and
/// the relation around every node of the cut graph, 2 g canonical generators a_1, b_1, ..., a_g,
/// b_g with a_1 b_1 a_1^-1 b_1^-1 ... a_g b_g a_g^-1 b_g^-1 = identity.
///
/// Method: (1) Tietze reduction to one relator: a spanning tree of the graph of nodes and
/// segments is contracted leaves first (in the dual cell complex: the faces of the nodes are
/// merged across the tree segments), which leaves one relator in the 2 g other segments, the
/// boundary word of a one-vertex polygon. (2) Cut and paste to the normal form (e.g. Stillwell,
/// Classical Topology and Combinatorial Group Theory, section 1.3; Massey, Algebraic Topology,
/// section 1.8): two interleaved letters a B b C a^-1 D b^-1 E become the commutator block
/// z y z^-1 y^-1 E D C B with y = b C B and z = (D C B)^-1 a B, g times. Every new letter is kept
/// both as a matrix (products of the current letters' matrices) and as a word in the segments.

#include <utility>
#include <vector>

#include "ricci/numerics/mobius.hpp"

namespace ricci {

/// A word in the segment maps: (segment, +1 or -1) stands for M(segment)^(+1 or -1); the word's
/// element is the product of its letters from left to right.
using SegmentWord = std::vector<std::pair<int, int>>;

/// The input of fuchsian_group: the deck transformations of the cut segments and the relations
/// around the nodes of the cut graph.
struct SegmentRelations {
  /// g_s, one per cut segment: the deck transformation between the segment's two sides.
  std::vector<Mobius> segment_maps;
  /// One cyclic word per node of the cut graph: the crossings of cut segments met going once
  /// around the node counter-clockwise, as (segment, +1 or -1). The product
  /// M(s_1)^{e_1} M(s_2)^{e_2} ... M(s_k)^{e_k} (matrix product, left to right) equals
  /// +-identity. Every segment occurs exactly twice over all words, with opposite signs (once
  /// at each end; a segment that is a loop occurs twice in its node's word).
  std::vector<SegmentWord> node_words;
  /// Optional: the same maps in long double (one per segment, or none). The residuals and the
  /// final generators are then evaluated from these: rounded to double, a map of norm N loses
  /// about 1e-16 N of consistency (and its determinant 1e-16 N^2), which the relation
  /// multiplies through its long words.
  std::vector<WideMobius> wide_segment_maps{};
};

/// Canonical generators of the Fuchsian group and how they were found.
struct FuchsianGroup {
  int genus = 0;
  /// a_1..a_g and b_1..b_g (normalised to determinant 1):
  /// a_1 b_1 a_1^-1 b_1^-1 ... a_g b_g a_g^-1 b_g^-1 = +-identity.
  std::vector<Mobius> a, b;
  /// The same generators as freely reduced words in the segment maps (evaluating a_words[i] with
  /// `evaluate` gives a[i] up to rounding).
  std::vector<SegmentWord> a_words, b_words;
  /// The single relator left after the Tietze reduction, cyclically reduced: a word of length
  /// 4 g in which each of the 2 g `generator_segments` occurs once with each sign.
  SegmentWord relator;
  std::vector<int> generator_segments;  ///< the segments outside the spanning tree, ascending
  std::vector<int> tree_segments;       ///< the segments of the spanning tree, in contraction order
  int root_node = 0;                    ///< the node word the tree was contracted into
  /// distance_to_identity of a_1 b_1 a_1^-1 b_1^-1 ... a_g b_g a_g^-1 b_g^-1, absolute (max-norm
  /// of M -+ I of the determinant-1 product). The generators are evaluated from their words in
  /// the segment maps and multiplied in long double, so rounding adds little: the residual shows
  /// the input's inconsistency (node_residual) carried through the Tietze conjugations. It only
  /// sees the generator segments; node_residual sees every segment.
  double relation_residual = 0;
  /// The product of the operator norms of the 4 g factors of that product (an upper bound of the
  /// factor by which errors in the generators can grow in it).
  double relation_scale = 1;
  /// max over the input node words of distance_to_identity of its product (in long double).
  double node_residual = 0;
  /// Largest operator norm among the generators (how far they move the origin: about
  /// exp(d(0, g(0)) / 2)).
  double largest_generator_norm = 1;
};

/// Canonical generators of the Fuchsian group of a cut surface (see the file comment). Among the
/// cut-and-paste choices the few cheapest at each step are tried (about 512 finished forms) and
/// each handle is shortened by a -> a b^(+-1), b -> b a^(+-1) while its matrices shrink; the
/// result with the smallest partial products of the relation is kept. Measured on the regular
/// 4g-gon with random one-vertex side pairings (tests/hyperbolic/fuchsian_test.cpp): relation
/// residual
/// <= 1e-13 at genus 2 and <= 3e-10 at genus 3; from genus 4 on some pairings give generators
/// whose commutators are so large that the relation loses all its digits (the words stay right:
/// the symbolic relation holds). Genus 0 (an empty relator) and 1 work too (no generators; one
/// commutator), although only genus >= 2 is hyperbolic.
FuchsianGroup fuchsian_group(const SegmentRelations& relations);

/// The product of a word's letters, left to right, normalised.
/// \throw InvalidInput when a letter's segment is out of range or its sign is not +-1
Mobius evaluate(const SegmentWord& word, const std::vector<Mobius>& segment_maps);

/// The inverse word (reversed, signs flipped).
SegmentWord inverse(const SegmentWord& word);

/// Removes adjacent pairs (s, e) (s, -e) until none is left.
SegmentWord free_reduce(const SegmentWord& word);

/// Freely reduces, then removes matching letters at the two ends (a cyclic word's reduction: the
/// result is a conjugate of the input).
SegmentWord cyclic_reduce(const SegmentWord& word);

/// Whether two words are equal as cyclic words (one is a rotation of the other).
bool is_rotation(const SegmentWord& u, const SegmentWord& v);

}  // namespace ricci
