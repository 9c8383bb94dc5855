#pragma once
/// \file
/// The library's one union-find: components of faces, fans of corners, charts, cycles of a cut.

#include <algorithm>
#include <numeric>
#include <vector>

namespace ricci {

/// Union-find with path halving; the smaller index becomes the root, so that roots (and every
/// numbering taken from them) are deterministic.
class DisjointSets {
 public:
  explicit DisjointSets(int n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int find(int x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  /// Joins the sets of a and b; true when they were apart.
  bool unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    parent_[std::max(a, b)] = std::min(a, b);
    return true;
  }
  int size() const { return static_cast<int>(parent_.size()); }

 private:
  std::vector<int> parent_;
};

}  // namespace ricci
