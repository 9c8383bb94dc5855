#pragma once
/// \file
/// Internal: an elimination tree split for two threads (supernodal_split.hpp,
/// simplicial_split.hpp). A Cholesky factor's work on a node reads only its descendants (the
/// factorisation) or its ancestors (the backward substitution), so two groups of whole subtrees run
/// beside each other, and the top separators above them, every one an ancestor of the groups,
/// before or after them.

#include <optional>
#include <vector>

namespace ricci::tree_split {

/// The nodes of each part, in increasing order.
struct Parts {
  std::vector<int> first, second, top;
  std::vector<char> is_top;  ///< per node
};

/// The top separators are taken off the tree (the roots down) while one subtree holds more than
/// kDominantShare of the work left; the subtrees below them go, largest first, each to the
/// lighter group. `parent[v]` > v, or -1 at a root; `work[v]` >= 0 is node v's own. None when a
/// group would hold less than kSmallestGroupShare of the groups' work (the split is not worth a
/// thread).
std::optional<Parts> split(const std::vector<int>& parent, const std::vector<double>& work);

constexpr double kDominantShare = 0.6;
constexpr double kSmallestGroupShare = 0.25;

}  // namespace ricci::tree_split
