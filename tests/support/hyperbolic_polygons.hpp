#pragma once
// Regular hyperbolic polygons with side pairings, their deck transformations and the relations
// around their vertex classes (the node words of fuchsian_group): the closed surfaces of the
// Fuchsian group tests and of the tiling pictures.

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "ricci/hyperbolic/fuchsian.hpp"
#include "ricci/numerics/mobius.hpp"

namespace ricci::testing {

/// Corners of the regular hyperbolic n-gon with interior angle `angle`, centred at the origin,
/// counter-clockwise from angle `offset`. Circumradius R: cosh R = cot(pi / n) cot(angle / 2);
/// in the disk the corners lie at Euclidean radius tanh(R / 2).
inline std::vector<std::complex<double>> regular_polygon(int n, double angle, double offset = 0) {
  const double cosh_r = 1.0 / (std::tan(std::numbers::pi / n) * std::tan(0.5 * angle));
  const double radius = std::sqrt((cosh_r - 1.0) / (cosh_r + 1.0));
  std::vector<std::complex<double>> corners(n);
  for (int k = 0; k < n; ++k) {
    corners[k] = std::polar(radius, offset + 2 * std::numbers::pi * k / n);
  }
  return corners;
}

/// A polygon in the disk (corners counter-clockwise, sides geodesic from corner k to k + 1)
/// whose sides are labelled: side k carries (segment, +1 or -1), each segment once with each
/// sign.
struct PairedPolygon {
  std::vector<std::complex<double>> corners;
  SegmentWord sides;
};

/// The side-pairing maps: g_s takes side j (labelled s^-1) onto side i (labelled s), corner j to
/// corner i + 1 and corner j + 1 to corner i, so that g_s(polygon) is the neighbour across side i.
inline std::vector<Mobius> side_pairings(const PairedPolygon& p, double* worst_mismatch = nullptr) {
  const int n = static_cast<int>(p.sides.size());
  int segments = 0;
  for (const auto& letter : p.sides) segments = std::max(segments, letter.first + 1);
  std::vector<int> plus(segments, -1), minus(segments, -1);
  for (int k = 0; k < n; ++k) (p.sides[k].second > 0 ? plus : minus)[p.sides[k].first] = k;
  std::vector<Mobius> maps(segments);
  if (worst_mismatch) *worst_mismatch = 0;
  for (int s = 0; s < segments; ++s) {
    const int i = plus[s], j = minus[s];
    double mismatch = 0;
    maps[s] = disk_isometry(p.corners[j], p.corners[(j + 1) % n], p.corners[(i + 1) % n],
                            p.corners[i], &mismatch);
    if (worst_mismatch) *worst_mismatch = std::max(*worst_mismatch, mismatch);
  }
  return maps;
}

/// The relation around each vertex class: going counter-clockwise around a corner c of a tile
/// gamma(P), one leaves the tile across side c - 1 into gamma h(P), h = g_s^e for the label
/// (s, e) of side c - 1, and arrives at the corner of the partner side of c - 1 (where that side
/// starts). A full turn multiplies the letters left to right to the identity.
inline std::vector<SegmentWord> vertex_cycles(const SegmentWord& sides) {
  const int n = static_cast<int>(sides.size());
  std::vector<int> partner(n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (j != i && sides[j].first == sides[i].first) partner[i] = j;
    }
  }
  std::vector<char> seen(n, 0);
  std::vector<SegmentWord> cycles;
  for (int start = 0; start < n; ++start) {
    if (seen[start]) continue;
    SegmentWord cycle;
    int c = start;
    do {
      seen[c] = 1;
      const int side = (c + n - 1) % n;
      cycle.push_back(sides[side]);
      c = partner[side];
    } while (c != start);
    cycles.push_back(cycle);
  }
  return cycles;
}

/// The segment relations of a paired polygon: its side pairings and vertex cycles.
inline SegmentRelations polygon_relations(const PairedPolygon& p) {
  return {side_pairings(p), vertex_cycles(p.sides)};
}

/// Labels a_1 b_1 a_1^-1 b_1^-1 ... a_g b_g a_g^-1 b_g^-1 (a_k = segment 2k, b_k = 2k + 1).
inline SegmentWord canonical_sides(int genus) {
  SegmentWord w;
  for (int k = 0; k < genus; ++k) {
    for (const auto& letter : {std::pair{2 * k, 1}, {2 * k + 1, 1}, {2 * k, -1}, {2 * k + 1, -1}}) {
      w.push_back(letter);  // not insert(initializer_list): GCC 12 warns falsely there
    }
  }
  return w;
}

/// Opposite sides paired: x_1 ... x_m x_1^-1 ... x_m^-1 on a 2m-gon (genus m / 2 with one vertex
/// class for m even, (m - 1) / 2 with two for m odd).
inline SegmentWord opposite_sides(int m) {
  SegmentWord w;
  for (int k = 0; k < m; ++k) w.push_back({k, 1});
  for (int k = 0; k < m; ++k) w.push_back({k, -1});
  return w;
}

/// The regular 4g-gon with interior angle 2 pi / 4g and the given labels (4g of them).
inline PairedPolygon regular_surface_polygon(int genus, SegmentWord sides, double offset = 0.1) {
  const int n = 4 * genus;
  return {regular_polygon(n, 2 * std::numbers::pi / n, offset), std::move(sides)};
}

}  // namespace ricci::testing
