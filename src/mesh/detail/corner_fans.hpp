#pragma once
// Private to the mesh module: the fans of corners around a vertex, which repair_mesh (to split a
// non-manifold vertex into one copy per fan) and find_defects (to report it) both build.
//
// Halfedge h = 3 f + k of face f lies opposite corner k and runs from corner (k+1)%3 to corner
// (k+2)%3, as in topology.hpp; corner c = 3 f + k is face f's corner k.

#include "ricci/numerics/disjoint_sets.hpp"

namespace ricci::mesh_detail {

/// The corner at the tail of halfedge h (the next corner of its face).
inline int next_corner(int h) {
  return h % 3 == 2 ? h - 2 : h + 1;
}
/// The corner at the head of halfedge h (the previous corner of its face).
inline int prev_corner(int h) {
  return h % 3 == 0 ? h + 2 : h - 1;
}

/// Joins the corners at each end of an edge whose two faces are glued along halfedges h and g:
/// the corners at the same vertex fall into one fan. Consistently oriented faces traverse the edge
/// in opposite directions (tail(h) == head(g)); faces of inconsistent orientation traverse it the
/// same way, and their corners at one vertex then sit at the same place in each face.
/// \param tail, head the vertex a halfedge starts and ends at
template <typename Tail, typename Head>
void unite_fans_across(DisjointSets& fans, int h, int g, const Tail& tail, const Head& head) {
  if (tail(h) == head(g)) {
    fans.unite(next_corner(h), prev_corner(g));
    fans.unite(prev_corner(h), next_corner(g));
  } else {
    fans.unite(next_corner(h), next_corner(g));
    fans.unite(prev_corner(h), prev_corner(g));
  }
}

}  // namespace ricci::mesh_detail
