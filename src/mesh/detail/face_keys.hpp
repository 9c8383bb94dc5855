#pragma once
// Private to the mesh module: faces keyed by their vertex sets, the search for duplicate faces
// that repair_mesh (which removes them) and find_defects (which reports them) share.

#include <algorithm>
#include <array>
#include <vector>

#include "numerics/detail/bucket_sort.hpp"
#include "ricci/mesh/mesh.hpp"

namespace ricci::mesh_detail {

/// Per included face {a, b, c, f}: its vertices sorted ascending, then the face; the list sorted,
/// so that faces on the same three vertices (duplicates, whatever their orientation) are
/// neighbours, in ascending face order.
/// \param included included(f): whether face f takes part
template <typename Included>
std::vector<std::array<int, 4>> sorted_face_keys(const Triangles& triangles,
                                                 const Included& included) {
  std::vector<std::array<int, 4>> keyed;
  keyed.reserve(static_cast<std::size_t>(triangles.rows()));
  int buckets = 0;
  bool in_range = true;
  for (int f = 0; f < static_cast<int>(triangles.rows()); ++f) {
    if (!included(f)) continue;
    std::array<int, 4> key = {triangles(f, 0), triangles(f, 1), triangles(f, 2), f};
    std::sort(key.begin(), key.begin() + 3);
    in_range = in_range && key[0] >= 0;
    buckets = std::max(buckets, key[0] + 1);
    keyed.push_back(key);
  }
  if (in_range) {
    numerics_detail::bucket_sort(keyed, buckets,
                                 [](const std::array<int, 4>& key) { return key[0]; });
  } else {  // (a negative index: no counting sort on it)
    std::sort(keyed.begin(), keyed.end());
  }
  return keyed;
}

}  // namespace ricci::mesh_detail
