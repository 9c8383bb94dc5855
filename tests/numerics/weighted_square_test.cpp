// A D A into the pattern of A A (numerics/detail/weighted_square.hpp): the free seams' systems.

#include "numerics/detail/weighted_square.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "support/scoped_threads.hpp"
#include "support/test_matrices.hpp"

namespace ricci {
namespace {

using numerics_detail::add_into_pattern;
using numerics_detail::set_weighted_square;
using numerics_detail::square_pattern;
using Sparse = Eigen::SparseMatrix<double>;

/// A torus Laplacian with an empty last row and column appended (a vertex of no face).
Sparse laplacian_with_lone_vertex() {
  // (9.8k rows: two chunks of columns on two threads.)
  const Sparse L = testing::torus_laplacian(140);
  const Eigen::Index n = L.rows() + 1;
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index j = 0; j < L.outerSize(); ++j) {
    for (Sparse::InnerIterator it(L, j); it; ++it)
      entries.emplace_back(it.row(), it.col(), it.value());
  }
  Sparse A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  A.makeCompressed();
  return A;
}

/// Uneven weights, some of them 0 (the Dirichlet system's free vertices).
Eigen::VectorXd weights(Eigen::Index n) {
  Eigen::VectorXd d(n);
  for (Eigen::Index i = 0; i < n; ++i)
    d[i] = i % 5 == 0 ? 0.0 : 0.5 + 0.01 * static_cast<double>(i % 17);
  return d;
}

TEST(WeightedSquare, PatternHoldsEveryProductOfEntriesAndTheWholeDiagonal) {
  const Sparse A = laplacian_with_lone_vertex();
  const Sparse pattern = square_pattern(A);
  const Sparse product = A * A;  // (Eigen keeps the structural entries; none cancel here)
  const Eigen::Index n = A.rows();
  // Every entry of A A, and only those, plus the lone vertex's diagonal.
  EXPECT_EQ(pattern.nonZeros(), product.nonZeros() + 1);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Sparse::InnerIterator it(product, j); it; ++it) {
      EXPECT_TRUE(pattern.isCompressed());
      bool found = false;
      for (Sparse::InnerIterator p(pattern, j); p; ++p) found = found || p.row() == it.row();
      ASSERT_TRUE(found) << it.row() << ", " << j;
    }
  }
  EXPECT_EQ(pattern.coeff(n - 1, n - 1), 0.0);
  EXPECT_EQ(pattern.col(n - 1).nonZeros(), 1);
  // Rows sorted in every column (what CHOLMOD and Eigen's iterators assume).
  for (Eigen::Index j = 0; j < n; ++j) {
    const int* rows = pattern.innerIndexPtr() + pattern.outerIndexPtr()[j];
    const int count = pattern.outerIndexPtr()[j + 1] - pattern.outerIndexPtr()[j];
    for (int k = 1; k < count; ++k) ASSERT_LT(rows[k - 1], rows[k]);
  }
}

TEST(WeightedSquare, ValuesAreTheProductSymmetricToTheBitOnAnyThreadCount) {
  const Sparse A = laplacian_with_lone_vertex();
  const Eigen::VectorXd d = weights(A.rows());
  const Sparse expected = A * d.asDiagonal() * A;
  Sparse one = square_pattern(A), two = one;
  {
    const testing::ScopedThreads threads("1");
    set_weighted_square(A, d, one);
  }
  {
    const testing::ScopedThreads threads("2");
    set_weighted_square(A, d, two);
  }
  EXPECT_EQ(std::memcmp(one.valuePtr(), two.valuePtr(), sizeof(double) * one.nonZeros()), 0);
  EXPECT_LE((Sparse(one - expected)).norm(), 1e-13 * expected.norm());
  const Sparse transposed = one.transpose();
  EXPECT_EQ(std::memcmp(one.valuePtr(), transposed.valuePtr(), sizeof(double) * one.nonZeros()), 0);
  // Setting again replaces the values rather than adding to them.
  set_weighted_square(A, 2 * d, one);
  EXPECT_LE((Sparse(one - 2 * expected)).norm(), 1e-13 * expected.norm());
}

TEST(WeightedSquare, AddsIntoThePatternAndRefusesOneThatLacksAnEntry) {
  const Sparse A = laplacian_with_lone_vertex();
  Sparse into = square_pattern(A);
  add_into_pattern(A, 3.0, into);
  EXPECT_LE((Sparse(into - 3.0 * A)).norm(), 1e-15 * A.norm());
  // A's own pattern lacks the entries two steps apart.
  Sparse narrow = A;
  EXPECT_THROW(set_weighted_square(A, weights(A.rows()), narrow), std::invalid_argument);
  Sparse diagonal(A.rows(), A.cols());
  diagonal.setIdentity();
  EXPECT_THROW(add_into_pattern(A, 1.0, diagonal), std::invalid_argument);
  Sparse uncompressed = square_pattern(A);
  uncompressed.coeffRef(0, 0) += 1;
  uncompressed.insert(0, static_cast<int>(A.cols()) - 1) = 1;  // (leaves it uncompressed)
  EXPECT_THROW(square_pattern(uncompressed), std::invalid_argument);
}

}  // namespace
}  // namespace ricci
