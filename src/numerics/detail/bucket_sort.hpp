#pragma once
/// \file
/// Internal: sorting edge and face keys by a counting sort on their smallest vertex, then each
/// bucket (about a vertex's valence of keys) on its own. Linear time where std::sort over the
/// whole list takes n log n comparisons: the connectivity checks sort 3 #F halfedges, and on a
/// 28k-face mesh that was a third of reading it.

#include <algorithm>
#include <vector>

namespace ricci::numerics_detail {

/// Sorts [first, last) ascending: std::sort when large, else insertion sort (a bucket holds a
/// handful of keys).
template <class Iterator>
void sort_small(Iterator first, Iterator last) {
  if (last - first < 2) return;  // (first + 1 would step past an empty range's end)
  if (last - first > 16) {
    std::sort(first, last);
    return;
  }
  for (Iterator i = first + 1; i < last; ++i) {
    auto x = std::move(*i);
    Iterator j = i;
    for (; j > first && x < *(j - 1); --j) *j = std::move(*(j - 1));
    *j = std::move(x);
  }
}

/// Sorts items ascending, given that bucket(item), an int in [0, buckets), orders them first:
/// a < b whenever bucket(a) < bucket(b) (a key that leads with its smallest vertex). The result
/// is std::sort's.
template <class T, class Bucket>
void bucket_sort(std::vector<T>& items, int buckets, const Bucket& bucket) {
  std::vector<int> start(static_cast<std::size_t>(buckets) + 1, 0);
  for (const T& x : items) ++start[bucket(x) + 1];
  for (int b = 0; b < buckets; ++b) start[b + 1] += start[b];
  std::vector<T> sorted(items.size());
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (T& x : items) sorted[fill[bucket(x)]++] = std::move(x);
  for (int b = 0; b < buckets; ++b)
    sort_small(sorted.begin() + start[b], sorted.begin() + start[b + 1]);
  items = std::move(sorted);
}

}  // namespace ricci::numerics_detail
