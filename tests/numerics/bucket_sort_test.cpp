#include "numerics/detail/bucket_sort.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace ricci::numerics_detail {
namespace {

TEST(BucketSort, GivesStdSortsOrderForKeysLedByTheirBucket) {
  std::mt19937 random(7);
  // Halfedge keys as the connectivity checks make them: (smaller << 32 | larger, halfedge), with
  // repeated keys (the two halfedges of an edge) and a few vertices of high valence (a bucket
  // past the insertion sort's size).
  const int nv = 300;
  std::uniform_int_distribution<int> vertex(0, nv - 1), hub(0, 2);
  std::vector<std::pair<std::uint64_t, int>> keys;
  for (int h = 0; h < 4000; ++h) {
    const int a = h % 7 == 0 ? hub(random) : vertex(random);
    const int b = vertex(random);
    const auto lo = static_cast<std::uint64_t>(std::min(a, b));
    const auto hi = static_cast<std::uint64_t>(std::max(a, b));
    keys.emplace_back((lo << 32) | hi, h);
    if (h % 3 == 0) keys.emplace_back((lo << 32) | hi, h + 100000);
  }
  std::shuffle(keys.begin(), keys.end(), random);
  auto expected = keys;
  std::sort(expected.begin(), expected.end());
  bucket_sort(keys, nv, [](const std::pair<std::uint64_t, int>& k) {
    return static_cast<int>(k.first >> 32);
  });
  EXPECT_EQ(keys, expected);
}

TEST(BucketSort, SortsFaceKeysAndEmptyAndSingleBuckets) {
  std::vector<std::array<int, 4>> faces = {{5, 6, 7, 3}, {0, 1, 2, 9}, {5, 6, 7, 1}, {0, 1, 3, 2}};
  auto expected = faces;
  std::sort(expected.begin(), expected.end());
  bucket_sort(faces, 8, [](const std::array<int, 4>& f) { return f[0]; });
  EXPECT_EQ(faces, expected);
  std::vector<std::array<int, 4>> none;
  bucket_sort(none, 0, [](const std::array<int, 4>& f) { return f[0]; });
  EXPECT_TRUE(none.empty());
}

TEST(BucketSort, SortSmallSortsShortAndLongRanges) {
  std::mt19937 random(3);
  for (const int n : {0, 1, 2, 16, 17, 200}) {
    std::vector<int> v(static_cast<std::size_t>(n));
    for (int& x : v) x = static_cast<int>(random() % 50);
    auto expected = v;
    std::sort(expected.begin(), expected.end());
    sort_small(v.begin(), v.end());
    EXPECT_EQ(v, expected) << n << " values";
  }
}

}  // namespace
}  // namespace ricci::numerics_detail
