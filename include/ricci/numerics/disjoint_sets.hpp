#pragma once
// Private to the mesh module: union-find and edge naming shared by topology and validation.

#include <algorithm>
#include <numeric>
#include <string>
#include <vector>

namespace ricci::mesh_detail {

/// Union-find with path halving; the smaller index becomes the root, so roots are deterministic.
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
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

/// "(a, b)" with the smaller index first.
inline std::string edge_name(int a, int b) {
  return "(" + std::to_string(std::min(a, b)) + ", " + std::to_string(std::max(a, b)) + ")";
}

}  // namespace ricci::mesh_detail
