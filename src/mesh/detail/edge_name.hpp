#pragma once
/// \file
/// Private to the mesh module: how messages name an edge of the input.

#include <algorithm>
#include <string>

namespace ricci::mesh_detail {

/// "(a, b)" with the smaller index first.
inline std::string edge_name(int a, int b) {
  return "(" + std::to_string(std::min(a, b)) + ", " + std::to_string(std::max(a, b)) + ")";
}

}  // namespace ricci::mesh_detail
