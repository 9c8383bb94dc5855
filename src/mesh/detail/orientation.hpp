#pragma once
// Private to the mesh module: the search for a consistent orientation that repair_mesh (which
// reverses the faces it finds) and find_defects (which reports them) share.

#include <cstddef>
#include <vector>

namespace ricci::mesh_detail {

/// Faces connected across two-faced edges, as search_orientation finds them.
struct OrientationComponent {
  int seed = 0;   ///< its smallest face, where the search started
  int begin = 0;  ///< its faces are OrientationSearch::order[begin, end), breadth first from seed
  int end = 0;
  /// A halfedge where the sides contradict (the first met, breadth first): the faces admit no
  /// consistent orientation (a Moebius strip); -1 when they do.
  int conflict = -1;
  int side_one = 0;  ///< faces on side 1

  int size() const { return end - begin; }
  /// The side to reverse for a consistent orientation: the smaller one, side 1 on a tie.
  int minority() const { return 2 * side_one <= size() ? 1 : 0; }
  /// Faces on the minority side.
  int to_reverse() const { return minority() ? side_one : size() - side_one; }
};

/// What search_orientation finds.
struct OrientationSearch {
  /// #F: 0 for the faces oriented like their component's seed, 1 for those to reverse to agree
  /// with it (when the component has no conflict), -1 for faces left out of the search.
  std::vector<signed char> side;
  std::vector<int> order;                        ///< the faces searched, component after component
  std::vector<OrientationComponent> components;  ///< in the order of their seeds
};

/// Breadth-first search across two-faced edges that gives each face a side such that neighbours
/// traverse their shared edge in opposite directions once the faces of side 1 are reversed.
/// Halfedge h = 3 f + k is a halfedge of face f.
/// \param twin #H: the other halfedge of h's edge when exactly two faces share it, else -1
///        (halfedges of faces left out have none and are nobody's twin)
/// \param tail tail(h): the vertex halfedge h starts from
/// \param included included(f): whether face f takes part
template <typename Tail, typename Included>
OrientationSearch search_orientation(const std::vector<int>& twin, const Tail& tail,
                                     const Included& included) {
  const int num_faces = static_cast<int>(twin.size() / 3);
  OrientationSearch out;
  out.side.assign(static_cast<std::size_t>(num_faces), -1);
  out.order.reserve(static_cast<std::size_t>(num_faces));
  std::vector<signed char>& side = out.side;
  for (int seed = 0; seed < num_faces; ++seed) {
    if (side[seed] >= 0 || !included(seed)) continue;
    OrientationComponent component;
    component.seed = seed;
    component.begin = static_cast<int>(out.order.size());
    out.order.push_back(seed);
    side[seed] = 0;
    for (std::size_t q = static_cast<std::size_t>(component.begin); q < out.order.size(); ++q) {
      const int f = out.order[q];
      component.side_one += side[f];
      for (int k = 0; k < 3; ++k) {
        const int h = 3 * f + k, g = twin[h];
        if (g < 0) continue;
        const int wanted = side[f] ^ (tail(h) == tail(g) ? 1 : 0);
        if (side[g / 3] < 0) {
          side[g / 3] = static_cast<signed char>(wanted);
          out.order.push_back(g / 3);
        } else if (side[g / 3] != wanted && component.conflict < 0) {
          component.conflict = h;
        }
      }
    }
    component.end = static_cast<int>(out.order.size());
    out.components.push_back(component);
  }
  return out;
}

}  // namespace ricci::mesh_detail
