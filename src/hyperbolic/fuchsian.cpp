#include "ricci/hyperbolic/fuchsian.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "ricci/errors.hpp"
#include "ricci/numerics/disjoint_sets.hpp"
#include "ricci/numerics/wide_float.hpp"

namespace ricci {
namespace {

constexpr const char* kFn = "fuchsian_group";

std::string letter_text(int segment, int sign) {
  return "(" + std::to_string(segment) + ", " + std::to_string(sign) + ")";
}

/// Number of vertices of the polygon whose boundary word is `word` once its sides are glued in
/// pairs: side i runs from corner i to corner i + 1 (mod n); the sides (s, +1) at i and (s, -1)
/// at j are glued head to tail, corner i to corner j + 1 and corner i + 1 to corner j.
int polygon_vertex_count(const SegmentWord& word, int num_segments) {
  const int n = static_cast<int>(word.size());
  std::vector<int> plus(num_segments, -1), minus(num_segments, -1);
  for (int i = 0; i < n; ++i) (word[i].second > 0 ? plus : minus)[word[i].first] = i;
  DisjointSets corners(n);
  int classes = n;
  for (int s = 0; s < num_segments; ++s) {
    if (plus[s] < 0) continue;
    classes -= corners.unite(plus[s], (minus[s] + 1) % n);
    classes -= corners.unite((plus[s] + 1) % n, minus[s]);
  }
  return classes;
}

SegmentWord concatenate(const SegmentWord& u, const SegmentWord& v) {
  SegmentWord w = u;
  w.insert(w.end(), v.begin(), v.end());
  return free_reduce(w);
}

/// Bounds of the greedy descent (moves, and letters of the two words together): they matter only
/// for input that is not a Fuchsian group, where the descent need not stop.
constexpr int kMaxShorteningMoves = 50;
constexpr std::size_t kMaxHandleLetters = 4096;
/// A move must shrink the sum of the log norms by more than this: a smaller gain is rounding
/// (the candidates of a discrete group differ in size by far more).
constexpr double kShorteningGain = 1e-6;

/// Shortens one handle by the moves that keep its commutator: a -> a b^(+-1) and
/// b -> b a^(+-1) ([a b, b] = [a b^-1, b] = [a, b a] = [a, b a^-1] = [a, b]), greedily while the
/// sum of the logarithms of the two operator norms (about half the distances the two maps move
/// the origin) decreases.
void shorten_handle(Mobius& a, Mobius& b, SegmentWord& wa, SegmentWord& wb) {
  auto size = [](const Mobius& m) { return std::log(operator_norm(m)); };
  // In a discrete group the sizes are discrete and the greedy descent stops after a few moves;
  // the bounds only matter for input that is not a Fuchsian group (e.g. commuting maps).
  for (int move = 0; move < kMaxShorteningMoves && wa.size() + wb.size() < kMaxHandleLetters;
       ++move) {
    const double now = size(a) + size(b);
    const Mobius candidates[4] = {compose(a, b), compose(a, inverse(b)), compose(b, a),
                                  compose(b, inverse(a))};
    int best = -1;
    double best_size = now - kShorteningGain;
    for (int k = 0; k < 4; ++k) {
      const double total = size(candidates[k]) + (k < 2 ? size(b) : size(a));
      if (total < best_size) {
        best_size = total;
        best = k;
      }
    }
    if (best < 0) return;
    if (best < 2) {
      a = candidates[best];
      wa = concatenate(wa, best == 0 ? wb : ricci::inverse(wb));
    } else {
      b = candidates[best];
      wb = concatenate(wb, best == 2 ? wa : ricci::inverse(wa));
    }
  }
}

/// The cut-and-paste state: a cyclic word in symbols, each symbol with its matrix, its word in
/// the segments and whether it already belongs to a commutator block.
struct NormalForm {
  std::vector<std::pair<int, int>> word;  // (symbol, sign)
  std::vector<Mobius> matrix;
  std::vector<SegmentWord> expansion;
  std::vector<char> finished;

  Mobius product(int begin, int end) const {
    Mobius m;
    for (int k = begin; k < end; ++k) {
      const auto [symbol, sign] = word[k];
      m = compose(m, sign > 0 ? matrix[symbol] : inverse(matrix[symbol]));
    }
    return m;
  }

  SegmentWord spelled(int begin, int end) const {
    SegmentWord w;
    for (int k = begin; k < end; ++k) {
      const auto [symbol, sign] = word[k];
      const SegmentWord& e = expansion[symbol];
      if (sign > 0) {
        w.insert(w.end(), e.begin(), e.end());
      } else {
        const SegmentWord inv = inverse(e);
        w.insert(w.end(), inv.begin(), inv.end());
      }
    }
    return w;
  }

  /// Renames symbol s to its inverse.
  void flip(int symbol) {
    for (auto& letter : word) {
      if (letter.first == symbol) letter.second = -letter.second;
    }
    matrix[symbol] = inverse(matrix[symbol]);
    expansion[symbol] = inverse(expansion[symbol]);
  }

  void rotate_to(int position) { std::rotate(word.begin(), word.begin() + position, word.end()); }

  /// Where a cut and paste can happen: a at `start`, then b at start + i, a^-1 at start + q,
  /// b^-1 at start + j (positions mod n, signs as found: a or b may need renaming to their
  /// inverse), with the cost of the new letters.
  struct Choice {
    double cost = 0;
    int start = -1, i = -1, q = -1, j = -1;
  };

  /// Every interleaved pair of unfinished letters, cheapest first. The new letters are products
  /// of B, C and D: their size is about the product of those letters' operator norms, so the
  /// cost adds the logarithms of the norms.
  std::vector<Choice> choices() const {
    const int n = static_cast<int>(word.size());
    std::vector<Choice> all;
    for (int p = 0; p < n; ++p) {
      const int a = word[p].first;
      if (finished[a]) continue;
      auto at = [&](int k) { return word[(p + k) % n]; };  // positions relative to p
      int q = -1;
      for (int k = 1; k < n; ++k) {
        if (at(k).first == a) q = k;
      }
      std::vector<double> prefix(n + 1, 0);
      for (int k = 0; k < n; ++k) {
        prefix[k + 1] = prefix[k] + std::log(operator_norm(matrix[at(k).first]));
      }
      std::vector<int> first(matrix.size(), -1);
      for (int k = 1; k < q; ++k) first[at(k).first] = k;
      for (int j = q + 1; j < n; ++j) {
        const int b = at(j).first;
        const int i = first[b];
        if (i < 0 || finished[b]) continue;
        // B = (0, i), C = (i, q), D = (q, j).
        const double cost =
            (prefix[j] - prefix[1]) - (prefix[i + 1] - prefix[i]) - (prefix[q + 1] - prefix[q]);
        all.push_back({cost, p, i, q, j});
      }
    }
    std::stable_sort(all.begin(), all.end(),
                     [](const Choice& x, const Choice& y) { return x.cost < y.cost; });
    return all;
  }

  /// One cut and paste at `best`: a B b C a^-1 D b^-1 E becomes a commutator block. Returns the
  /// block's (z, y) symbols (they reuse a's and b's).
  std::pair<int, int> make_block(const Choice& best) {
    rotate_to(best.start);
    const int a = word[0].first, b = word[best.i].first;
    if (word[0].second < 0) flip(a);
    if (word[best.i].second < 0) flip(b);
    const int i = best.i, q = best.q, j = best.j;
    // a B b C a^-1 D b^-1 E  ->  z y z^-1 y^-1 E D C B,  y = b C B,  z = (D C B)^-1 a B.
    const Mobius mb = product(1, i), mc = product(i + 1, q), md = product(q + 1, j);
    const SegmentWord wb = spelled(1, i), wc = spelled(i + 1, q), wd = spelled(q + 1, j);
    const Mobius dcb = compose(md, compose(mc, mb));
    const Mobius y = compose(matrix[b], compose(mc, mb));
    const Mobius z = compose(inverse(dcb), compose(matrix[a], mb));
    SegmentWord wy = expansion[b];
    wy.insert(wy.end(), wc.begin(), wc.end());
    wy.insert(wy.end(), wb.begin(), wb.end());
    SegmentWord wdcb = wd;
    wdcb.insert(wdcb.end(), wc.begin(), wc.end());
    wdcb.insert(wdcb.end(), wb.begin(), wb.end());
    SegmentWord wz = inverse(wdcb);
    wz.insert(wz.end(), expansion[a].begin(), expansion[a].end());
    wz.insert(wz.end(), wb.begin(), wb.end());

    std::vector<std::pair<int, int>> next = {{a, 1}, {b, 1}, {a, -1}, {b, -1}};
    next.insert(next.end(), word.begin() + j + 1, word.end());        // E
    next.insert(next.end(), word.begin() + q + 1, word.begin() + j);  // D
    next.insert(next.end(), word.begin() + i + 1, word.begin() + q);  // C
    next.insert(next.end(), word.begin() + 1, word.begin() + i);      // B
    word = std::move(next);
    // Shortened at once (the moves keep [z, y], so the word stays as it is), so that later
    // blocks, which may contain this one in B, C or D, are built from small matrices.
    matrix[a] = z;
    matrix[b] = y;
    expansion[a] = free_reduce(wz);
    expansion[b] = free_reduce(wy);
    shorten_handle(matrix[a], matrix[b], expansion[a], expansion[b]);
    finished[a] = finished[b] = 1;
    return {a, b};
  }
};

/// Moebius maps in quadruple precision (__float128, 113-bit significands; long double where the
/// compiler has no __float128): the final generators and the relation are evaluated from the
/// segment maps with 60 more bits than double. The relation multiplies some 4 g words of up to
/// a dozen maps of norm up to 1e3: in long double its rounding alone reached 1e-7 (a generated
/// genus-3 surface) and 5e-6 (fertility.off), in quad it is far below the consistency of the
/// input maps, which the residual then measures. std::complex<__float128> is libstdc++'s generic
/// template (the textbook products and sums, no library calls), hence the test of __GLIBCXX__;
/// only the algebra of ricci/numerics/mobius.hpp is used on it, and the square root and
/// magnitudes below go through long double.
using Extended = Quad;
using ExtendedComplex = std::complex<Extended>;
using ExtendedMobius = BasicMobius<Extended>;

/// |x|^2 as x.re^2 + x.im^2 (std::norm could take the square root of the squared modulus).
Extended squared_modulus(ExtendedComplex x) {
  return x.real() * x.real() + x.imag() * x.imag();
}

/// 1 / sqrt(x) to the precision of Extended: the long double root refined by one Newton step.
Extended inverse_sqrt(Extended x) {
  const Extended s = 1.0L / std::sqrt(static_cast<long double>(x));
  return s * (Extended{1.5} - Extended{0.5} * x * s * s);
}

/// Scaled to determinant 1 (unchanged when the determinant is not positive and finite). Not
/// `normalized`: the determinant from the squared moduli (no quad hypot), no sign fixed.
ExtendedMobius normalized_extended(const ExtendedMobius& m) {
  const Extended det = squared_modulus(m.a) - squared_modulus(m.b);
  if (!(det > 0) || !std::isfinite(static_cast<long double>(det))) return m;
  const Extended s = inverse_sqrt(det);
  return {m.a * s, m.b * s};
}

/// A double or long double map in Extended, normalised there.
template <class T>
ExtendedMobius extend(const BasicMobius<T>& m) {
  return normalized_extended(mobius_cast<Extended>(m));
}

/// The product of a word's letters, left to right (no check of the letters).
template <class T>
BasicMobius<T> word_product(const SegmentWord& word, const std::vector<BasicMobius<T>>& maps) {
  BasicMobius<T> m;
  for (const auto& [segment, sign] : word) {
    m = compose(m, sign > 0 ? maps[segment] : inverse(maps[segment]));
  }
  return m;
}

/// Scaled to determinant 1, Re a >= 0, rounded to double.
Mobius round_to_double(const ExtendedMobius& m) {
  ExtendedMobius n = normalized_extended(m);
  if (n.a.real() < 0) n = {-n.a, -n.b};
  return mobius_cast<double>(n);
}

/// distance_to_identity in Extended, rounded.
double extended_distance_to_identity(const ExtendedMobius& m) {
  const ExtendedMobius n = normalized_extended(m);
  auto magnitude = [](Extended re, Extended im) {
    return std::hypot(static_cast<long double>(re), static_cast<long double>(im));
  };
  const long double off = magnitude(n.b.real(), n.b.imag());
  const long double minus = magnitude(n.a.real() - 1, n.a.imag());
  const long double plus = magnitude(n.a.real() + 1, n.a.imag());
  return static_cast<double>(std::min(std::max(minus, off), std::max(plus, off)));
}

/// The canonical generators read from a finished normal form (blocks: the (z, y) symbols of
/// each commutator block), each handle shortened.
struct Handles {
  /// ln of the largest operator norm of a partial product of the relation times its factor's
  double size = std::numeric_limits<double>::infinity();
  std::vector<SegmentWord> a_words, b_words;
};

Handles read_handles(NormalForm form, const std::vector<std::pair<int, int>>& blocks) {
  std::vector<int> partner(form.matrix.size(), -1);
  for (const auto& [z, y] : blocks) partner[z] = y;
  int start = 0;
  while (!(partner[form.word[start].first] >= 0 && form.word[start].second > 0)) ++start;
  form.rotate_to(start);
  Handles handles;
  handles.size = 0;
  Mobius prefix;  // a_1 b_1 a_1^-1 b_1^-1 ... so far
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const int z = form.word[4 * k].first, y = partner[z];
    const bool block = y >= 0 && form.word[4 * k] == std::pair<int, int>{z, 1} &&
                       form.word[4 * k + 1] == std::pair<int, int>{y, 1} &&
                       form.word[4 * k + 2] == std::pair<int, int>{z, -1} &&
                       form.word[4 * k + 3] == std::pair<int, int>{y, -1};
    if (!block) {
      throw SolverError(std::string(kFn) +
                        ": internal error: the normal form is not a product of commutators at "
                        "letter " +
                        std::to_string(4 * k));
    }
    Mobius a = form.matrix[z], b = form.matrix[y];
    SegmentWord wa = form.expansion[z], wb = form.expansion[y];
    shorten_handle(a, b, wa, wb);
    // The relation's rounding error grows with the largest partial product of the commutators
    // (each letter's error is multiplied by the products on its two sides): that is the size.
    for (const Mobius& factor : {a, b, inverse(a), inverse(b)}) {
      prefix = compose(prefix, factor);
      handles.size =
          std::max(handles.size, std::log(operator_norm(prefix)) + std::log(operator_norm(factor)));
    }
    handles.a_words.push_back(std::move(wa));
    handles.b_words.push_back(std::move(wb));
  }
  return handles;
}

/// A choice whose cost (a sum of log norms) exceeds the cheapest one's by more than this, new
/// letters about e^3 = 20 times larger, is not tried.
constexpr double kCostMargin = 3.0;

/// Depth-first over the `breadth` cheapest cut-and-paste choices at each of `remaining` steps.
void explore(const NormalForm& form, std::vector<std::pair<int, int>>& blocks, int remaining,
             int breadth, Handles& best) {
  if (remaining == 0) {
    Handles handles = read_handles(form, blocks);
    // (A size that overflowed, as the partial products of a high-genus group can, still gives
    // generators: the first finished form is kept rather than none.)
    if (handles.size < best.size || best.a_words.empty()) best = std::move(handles);
    return;
  }
  const std::vector<NormalForm::Choice> options = form.choices();
  if (options.empty()) {
    throw InvalidInput(std::string(kFn) +
                       ": no two unfinished letters of the reduced relator interleave (not the "
                       "word of a one-vertex orientable surface)");
  }
  // Choices much dearer than the cheapest (new letters 20 times larger) are not worth trying;
  // the cheapest always is (even when the costs overflowed, as a high genus's can).
  const int tries = std::min(breadth, static_cast<int>(options.size()));
  for (int t = 0; t < tries && (t == 0 || options[t].cost <= options[0].cost + kCostMargin); ++t) {
    NormalForm next = form;
    blocks.push_back(next.make_block(options[t]));
    explore(next, blocks, remaining - 1, breadth, best);
    blocks.pop_back();
  }
}

}  // namespace

Mobius evaluate(const SegmentWord& word, const std::vector<Mobius>& segment_maps) {
  for (const auto& [segment, sign] : word) {
    if (segment < 0 || segment >= static_cast<int>(segment_maps.size()) ||
        (sign != 1 && sign != -1)) {
      throw InvalidInput("evaluate: letter " + letter_text(segment, sign) +
                         " is not (segment in [0, " + std::to_string(segment_maps.size()) +
                         "), +-1)");
    }
  }
  return normalized(word_product(word, segment_maps));
}

SegmentWord inverse(const SegmentWord& word) {
  SegmentWord result(word.rbegin(), word.rend());
  for (auto& letter : result) letter.second = -letter.second;
  return result;
}

SegmentWord free_reduce(const SegmentWord& word) {
  SegmentWord stack;
  stack.reserve(word.size());
  for (const auto& letter : word) {
    if (!stack.empty() && stack.back().first == letter.first &&
        stack.back().second == -letter.second) {
      stack.pop_back();
    } else {
      stack.push_back(letter);
    }
  }
  return stack;
}

SegmentWord cyclic_reduce(const SegmentWord& word) {
  const SegmentWord w = free_reduce(word);
  std::size_t lo = 0, hi = w.size();
  while (hi - lo >= 2 && w[lo].first == w[hi - 1].first && w[lo].second == -w[hi - 1].second) {
    ++lo;
    --hi;
  }
  return SegmentWord(w.begin() + static_cast<std::ptrdiff_t>(lo),
                     w.begin() + static_cast<std::ptrdiff_t>(hi));
}

bool is_rotation(const SegmentWord& u, const SegmentWord& v) {
  if (u.size() != v.size()) return false;
  if (u.empty()) return true;
  SegmentWord doubled = u;
  doubled.insert(doubled.end(), u.begin(), u.end());
  return std::search(doubled.begin(), doubled.end(), v.begin(), v.end()) != doubled.end();
}

namespace {

/// The two node words each segment occurs in, with sign +1 and with sign -1.
struct SegmentEnds {
  std::vector<int> plus_node, minus_node;
};

/// Checks that every letter is in range and every segment occurs once with each sign; returns
/// the nodes at each segment's two ends.
SegmentEnds segment_ends(const SegmentRelations& relations, int num_segments) {
  const int num_nodes = static_cast<int>(relations.node_words.size());
  SegmentEnds ends{std::vector<int>(num_segments, -1), std::vector<int>(num_segments, -1)};
  for (int v = 0; v < num_nodes; ++v) {
    const SegmentWord& w = relations.node_words[v];
    if (w.empty()) {
      throw InvalidInput(std::string(kFn) + ": node word " + std::to_string(v) + " is empty");
    }
    for (const auto& [segment, sign] : w) {
      if (segment < 0 || segment >= num_segments || (sign != 1 && sign != -1)) {
        throw InvalidInput(std::string(kFn) + ": node word " + std::to_string(v) + " has letter " +
                           letter_text(segment, sign) + "; letters must be (segment in [0, " +
                           std::to_string(num_segments) + "), +1 or -1)");
      }
      int& end = sign > 0 ? ends.plus_node[segment] : ends.minus_node[segment];
      if (end >= 0) {
        throw InvalidInput(std::string(kFn) + ": segment " + std::to_string(segment) +
                           " occurs more than once with sign " + std::to_string(sign) +
                           " (in node words " + std::to_string(end) + " and " + std::to_string(v) +
                           "); each segment occurs once with each sign");
      }
      end = v;
    }
  }
  for (int s = 0; s < num_segments; ++s) {
    if (ends.plus_node[s] < 0 || ends.minus_node[s] < 0) {
      throw InvalidInput(std::string(kFn) + ": segment " + std::to_string(s) +
                         (ends.plus_node[s] < 0 && ends.minus_node[s] < 0
                              ? " occurs in no node word"
                              : " occurs only once (with sign " +
                                    std::string(ends.plus_node[s] < 0 ? "-1" : "+1") + ")") +
                         "; each segment occurs once with each sign");
    }
  }
  return ends;
}

/// The segment maps normalised to determinant 1 (throws for a determinant that is not
/// positive).
std::vector<Mobius> normalized_segment_maps(const SegmentRelations& relations) {
  const int num_segments = static_cast<int>(relations.segment_maps.size());
  std::vector<Mobius> maps(num_segments);
  for (int s = 0; s < num_segments; ++s) {
    const double det = determinant(relations.segment_maps[s]);
    if (!(det > 0) || !std::isfinite(det)) {
      throw InvalidInput(std::string(kFn) + ": segment map " + std::to_string(s) +
                         " has determinant " + std::to_string(det) + " (must be positive)");
    }
    maps[s] = normalized(relations.segment_maps[s]);
  }
  return maps;
}

/// The segment maps in Extended: the wide ones where the relations carry them, else the double
/// ones.
std::vector<ExtendedMobius> extended_segment_maps(const SegmentRelations& relations,
                                                  const std::vector<Mobius>& maps) {
  const int num_segments = static_cast<int>(maps.size());
  std::vector<ExtendedMobius> extended(num_segments);
  for (int s = 0; s < num_segments; ++s) extended[s] = extend(maps[s]);
  if (static_cast<int>(relations.wide_segment_maps.size()) == num_segments) {
    for (int s = 0; s < num_segments; ++s) {
      const auto& [a, b] = relations.wide_segment_maps[s];
      const long double det = std::norm(a) - std::norm(b);
      if (!(det > 0) || !std::isfinite(det)) {
        throw InvalidInput(std::string(kFn) + ": wide segment map " + std::to_string(s) +
                           " has a determinant that is not positive");
      }
      extended[s] = extend(relations.wide_segment_maps[s]);
    }
  } else if (!relations.wide_segment_maps.empty()) {
    throw InvalidInput(std::string(kFn) + ": " +
                       std::to_string(relations.wide_segment_maps.size()) +
                       " wide segment maps for " + std::to_string(num_segments) + " segments");
  }
  return extended;
}

/// A spanning tree of the nodes (vertices) and segments (edges), breadth first from node 0.
struct SpanningTree {
  std::vector<int> order;  ///< the nodes in the order reached
  std::vector<int> parent_segment, parent_node;
  std::vector<char> in_tree;  ///< per segment
};

SpanningTree spanning_tree(const SegmentEnds& ends, int num_nodes) {
  const int num_segments = static_cast<int>(ends.plus_node.size());
  std::vector<std::vector<int>> incident(num_nodes);
  for (int s = 0; s < num_segments; ++s) {
    if (ends.plus_node[s] == ends.minus_node[s]) continue;  // a loop is never a tree edge
    incident[ends.plus_node[s]].push_back(s);
    incident[ends.minus_node[s]].push_back(s);
  }
  SpanningTree tree{{0},
                    std::vector<int>(num_nodes, -1),
                    std::vector<int>(num_nodes, -1),
                    std::vector<char>(num_segments, 0)};
  std::vector<char> reached(num_nodes, 0);
  reached[0] = 1;
  for (std::size_t k = 0; k < tree.order.size(); ++k) {
    const int v = tree.order[k];
    for (int s : incident[v]) {
      const int u = ends.plus_node[s] == v ? ends.minus_node[s] : ends.plus_node[s];
      if (reached[u]) continue;
      reached[u] = 1;
      tree.parent_segment[u] = s;
      tree.parent_node[u] = v;
      tree.in_tree[s] = 1;
      tree.order.push_back(u);
    }
  }
  if (static_cast<int>(tree.order.size()) != num_nodes) {
    const int missing =
        static_cast<int>(std::find(reached.begin(), reached.end(), 0) - reached.begin());
    throw InvalidInput(std::string(kFn) + ": node " + std::to_string(missing) +
                       " is not connected to node 0 through shared segments");
  }
  return tree;
}

/// Contracts the tree, leaves first: in node v's word p^e R, p = parent segment, the parent's
/// letter p^-e becomes R (p^e = R^-1 substituted; the faces of v and its parent merge). Sets
/// group.tree_segments, group.relator (node 0's word, cyclically reduced) and
/// group.generator_segments (the segments outside the tree).
void contract_tree(const SegmentRelations& relations, const SpanningTree& tree,
                   FuchsianGroup& group) {
  std::vector<SegmentWord> words = relations.node_words;
  for (std::size_t k = tree.order.size(); k-- > 1;) {
    const int v = tree.order[k], p = tree.parent_segment[v], u = tree.parent_node[v];
    SegmentWord& child = words[v];
    const auto at = std::find_if(child.begin(), child.end(),
                                 [p](const std::pair<int, int>& l) { return l.first == p; });
    std::rotate(child.begin(), at, child.end());
    const SegmentWord rest(child.begin() + 1, child.end());
    SegmentWord& up = words[u];
    const auto slot = std::find_if(up.begin(), up.end(),
                                   [p](const std::pair<int, int>& l) { return l.first == p; });
    const auto offset = slot - up.begin();
    up.erase(slot);
    up.insert(up.begin() + offset, rest.begin(), rest.end());
    group.tree_segments.push_back(p);
    SegmentWord().swap(child);
  }
  group.relator = cyclic_reduce(words[0]);
  for (int s = 0; s < static_cast<int>(tree.in_tree.size()); ++s) {
    if (!tree.in_tree[s]) group.generator_segments.push_back(s);
  }
}

/// The relator must be the word of a one-vertex orientable polygon in all the other segments;
/// returns the genus.
int relator_genus(const FuchsianGroup& group, int num_segments) {
  const int n = static_cast<int>(group.relator.size());
  if (n != 2 * static_cast<int>(group.generator_segments.size())) {
    throw InvalidInput(std::string(kFn) + ": the reduced relator has " + std::to_string(n) +
                       " letters for " + std::to_string(group.generator_segments.size()) +
                       " segments outside the spanning tree (letters cancelled: not a surface "
                       "cut into one disk)");
  }
  if (n > 0) {
    const int vertices = polygon_vertex_count(group.relator, num_segments);
    if (vertices != 1 || n % 4 != 0) {
      throw InvalidInput(std::string(kFn) + ": the reduced relator (" + std::to_string(n) +
                         " letters) glues its polygon's corners into " + std::to_string(vertices) +
                         " vertices, not 1: the node words do not describe a closed surface cut "
                         "into one disk");
    }
  }
  return n / 4;
}

/// Number of finished normal forms the cut-and-paste search visits at most, in all.
constexpr double kSearchedForms = 512;
/// Rounding slack of the genus-th root of kSearchedForms (an exact power, 512 = 8^3, must not
/// round down to 7.999...).
constexpr double kBreadthSlack = 1e-9;

/// The canonical generators' words: a small search over the cut-and-paste choices (the
/// cheapest few at each step, about kSearchedForms finished forms in all), keeping the
/// generators of least total size. Sets group.a_words and group.b_words.
void canonical_words(const std::vector<Mobius>& maps, FuchsianGroup& group) {
  const int num_segments = static_cast<int>(maps.size());
  NormalForm form;
  std::vector<int> symbol_of(num_segments, -1);
  for (int segment : group.generator_segments) {
    symbol_of[segment] = static_cast<int>(form.matrix.size());
    form.matrix.push_back(maps[segment]);
    form.expansion.push_back({{segment, 1}});
    form.finished.push_back(0);
  }
  for (const auto& [segment, sign] : group.relator)
    form.word.emplace_back(symbol_of[segment], sign);
  if (group.genus > 0) {
    const int breadth = std::clamp(
        static_cast<int>(std::pow(kSearchedForms, 1.0 / group.genus) + kBreadthSlack), 1, 8);
    Handles best;
    std::vector<std::pair<int, int>> blocks;
    explore(form, blocks, group.genus, breadth, best);
    group.a_words = std::move(best.a_words);
    group.b_words = std::move(best.b_words);
  }
}

/// The generators evaluated afresh from their words, and the relation, in Extended; sets
/// group.a, group.b, their norms and the relation's residual.
void evaluate_generators(const std::vector<ExtendedMobius>& extended, FuchsianGroup& group) {
  ExtendedMobius relation;
  for (int k = 0; k < group.genus; ++k) {
    const ExtendedMobius a = word_product(group.a_words[k], extended);
    const ExtendedMobius b = word_product(group.b_words[k], extended);
    relation = compose(relation, compose(compose(a, b), compose(inverse(a), inverse(b))));
    group.a.push_back(round_to_double(a));
    group.b.push_back(round_to_double(b));
    const double na = operator_norm(group.a[k]), nb = operator_norm(group.b[k]);
    group.relation_scale *= na * na * nb * nb;
    group.largest_generator_norm = std::max({group.largest_generator_norm, na, nb});
  }
  group.relation_residual = extended_distance_to_identity(relation);
}

}  // namespace

FuchsianGroup fuchsian_group(const SegmentRelations& relations) {
  const int num_segments = static_cast<int>(relations.segment_maps.size());
  const int num_nodes = static_cast<int>(relations.node_words.size());
  if (num_nodes == 0) throw InvalidInput(std::string(kFn) + ": there are no node words");
  const SegmentEnds ends = segment_ends(relations, num_segments);
  const std::vector<Mobius> maps = normalized_segment_maps(relations);

  FuchsianGroup group;
  const std::vector<ExtendedMobius> extended = extended_segment_maps(relations, maps);
  for (const SegmentWord& w : relations.node_words) {
    group.node_residual =
        std::max(group.node_residual, extended_distance_to_identity(word_product(w, extended)));
  }
  contract_tree(relations, spanning_tree(ends, num_nodes), group);
  group.genus = relator_genus(group, num_segments);
  canonical_words(maps, group);
  evaluate_generators(extended, group);
  return group;
}

}  // namespace ricci
