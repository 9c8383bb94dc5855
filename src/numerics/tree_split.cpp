#include "numerics/detail/tree_split.hpp"

#include <algorithm>
#include <cstddef>

namespace ricci::tree_split {

std::optional<Parts> split(const std::vector<int>& parent, const std::vector<double>& work) {
  const int n = static_cast<int>(parent.size());
  std::vector<double> subtree(work);
  std::vector<std::vector<int>> children(static_cast<std::size_t>(n));
  std::vector<int> frontier;
  for (int v = 0; v < n; ++v) {  // (parents come after their children)
    if (parent[v] < 0) {
      frontier.push_back(v);
      continue;
    }
    subtree[parent[v]] += subtree[v];
    children[parent[v]].push_back(v);
  }
  double left = 0;
  for (int r : frontier) left += subtree[r];
  Parts parts;
  parts.is_top.assign(static_cast<std::size_t>(n), 0);
  for (;;) {
    const auto largest = std::max_element(frontier.begin(), frontier.end(),
                                          [&](int a, int b) { return subtree[a] < subtree[b]; });
    if (largest == frontier.end() || subtree[*largest] <= kDominantShare * left) break;
    const int t = *largest;
    frontier.erase(largest);
    parts.is_top[t] = 1;
    left -= work[t];
    frontier.insert(frontier.end(), children[t].begin(), children[t].end());
  }
  // Largest subtrees first, each to the lighter group.
  std::sort(frontier.begin(), frontier.end(), [&](int a, int b) {
    return subtree[a] != subtree[b] ? subtree[a] > subtree[b] : a < b;
  });
  std::vector<int> group(static_cast<std::size_t>(n), -1);
  double weight[2] = {0, 0};
  for (int r : frontier) {
    const int g = weight[0] <= weight[1] ? 0 : 1;
    group[r] = g;
    weight[g] += subtree[r];
  }
  const double total = weight[0] + weight[1];
  if (!(total > 0) || std::min(weight[0], weight[1]) < kSmallestGroupShare * total) {
    return std::nullopt;
  }
  // Below a subtree's root, each node in its parent's group (parents first: they come after).
  for (int v = n - 1; v >= 0; --v) {
    if (group[v] < 0 && !parts.is_top[v]) group[v] = group[parent[v]];
  }
  for (int v = 0; v < n; ++v) {
    if (parts.is_top[v]) {
      parts.top.push_back(v);
    } else {
      (group[v] == 0 ? parts.first : parts.second).push_back(v);
    }
  }
  return parts;
}

}  // namespace ricci::tree_split
