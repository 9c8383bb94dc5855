// Eigen's simplicial LDL^T on two threads (numerics/detail/simplicial_split.hpp) and the tree
// split behind it and the supernodal solves (numerics/detail/tree_split.hpp).

#include "numerics/detail/simplicial_split.hpp"

#include <cstring>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "numerics/detail/tree_split.hpp"
#include "support/scoped_threads.hpp"
#include "support/test_matrices.hpp"

namespace ricci {
namespace {

using simplicial::Ldlt;
using simplicial::SplitLdlt;
using testing::sine_rhs;
using testing::torus_laplacian;

bool same_bits(const double* a, const double* b, Eigen::Index n) {
  return std::memcmp(a, b, sizeof(double) * static_cast<std::size_t>(n)) == 0;
}

/// The factor of `split` is Eigen's own factor of A, bit for bit: pattern, L's values and D.
void expect_eigens_factor(const SplitLdlt& split, const Ldlt& eigen) {
  ASSERT_EQ(split.info(), Eigen::Success);
  const auto& a = split.matrixL().nestedExpression();
  const auto& b = eigen.matrixL().nestedExpression();
  ASSERT_EQ(a.nonZeros(), b.nonZeros());
  const Eigen::Index n = a.cols();
  EXPECT_EQ(std::memcmp(a.outerIndexPtr(), b.outerIndexPtr(), sizeof(int) * (n + 1)), 0);
  EXPECT_EQ(std::memcmp(a.innerIndexPtr(), b.innerIndexPtr(), sizeof(int) * a.nonZeros()), 0);
  EXPECT_TRUE(same_bits(a.valuePtr(), b.valuePtr(), a.nonZeros()));
  EXPECT_TRUE(same_bits(split.vectorD().data(), eigen.vectorD().data(), n));
}

/// A with the torus Laplacian's pattern, other values (a refactorisation's).
Eigen::SparseMatrix<double> reweighted(Eigen::SparseMatrix<double> A) {
  for (int k = 0; k < A.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, k); it; ++it) {
      if (it.row() != it.col()) it.valueRef() *= 1.0 + 0.01 * ((it.row() + it.col()) % 7);
    }
  }
  for (int k = 0; k < A.rows(); ++k) A.coeffRef(k, k) = 0;
  Eigen::VectorXd degree = -(A * Eigen::VectorXd::Ones(A.rows()));
  for (int k = 0; k < A.rows(); ++k) A.coeffRef(k, k) = degree[k] + 0.1;
  return A;
}

// Factorised and solved in two groups, on one thread or two, the factor and the solutions are
// Eigen's sequential ones to the last bit, for a refactorisation too; right-hand sides with
// zeros (whose updates Eigen skips) included.
TEST(SimplicialSplit, FactorAndSolvesAreEigensBitForBit) {
  const Eigen::SparseMatrix<double> A = torus_laplacian(90);  // 4049 rows
  for (const char* threads : {"1", "2"}) {
    SCOPED_TRACE(threads);
    const testing::ScopedThreads scoped(threads);
    SplitLdlt split;
    split.analyze_split(A, 0);
    ASSERT_TRUE(split.has_split());
    for (const Eigen::SparseMatrix<double>& M : {A, reweighted(A)}) {
      split.factorize_split(M);
      Ldlt eigen(M);
      expect_eigens_factor(split, eigen);
      Eigen::VectorXd b = sine_rhs(M.rows());
      Eigen::VectorXd sparse = Eigen::VectorXd::Zero(M.rows());
      sparse[7] = 1;
      sparse[M.rows() - 3] = -2;
      for (const Eigen::VectorXd& rhs : {b, sparse}) {
        const Eigen::VectorXd x = split.solve_split(rhs), y = eigen.solve(rhs);
        EXPECT_TRUE(same_bits(x.data(), y.data(), x.size()));
        EXPECT_LT((M * x - rhs).norm(), 1e-9 * rhs.norm());
      }
    }
  }
}

// Several components (a forest: one tree per block) split across their roots the same way.
TEST(SimplicialSplit, BlockDiagonalMatricesSplitAcrossTheirTrees) {
  const Eigen::SparseMatrix<double> a = torus_laplacian(60), b = torus_laplacian(50);
  std::vector<Eigen::Triplet<double>> entries;
  const auto append = [&](const Eigen::SparseMatrix<double>& block, Eigen::Index offset) {
    for (int k = 0; k < block.outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(block, k); it; ++it) {
        entries.emplace_back(it.row() + offset, it.col() + offset, it.value());
      }
    }
  };
  append(a, 0);
  append(b, a.rows());
  Eigen::SparseMatrix<double> A(a.rows() + b.rows(), a.rows() + b.rows());
  A.setFromTriplets(entries.begin(), entries.end());
  SplitLdlt split;
  split.analyze_split(A, 0);
  ASSERT_TRUE(split.has_split());
  split.factorize_split(A);
  const Ldlt eigen(A);
  expect_eigens_factor(split, eigen);
  const Eigen::VectorXd rhs = sine_rhs(A.rows());
  const Eigen::VectorXd x = split.solve_split(rhs), y = eigen.solve(rhs);
  EXPECT_TRUE(same_bits(x.data(), y.data(), x.size()));
}

// Below the size given, no split: factorize_split and solve_split are Eigen's own calls.
TEST(SimplicialSplit, SmallFactorsAreNotSplit) {
  const Eigen::SparseMatrix<double> A = torus_laplacian(12);
  SplitLdlt split;
  split.analyze_split(A, 1e9);
  EXPECT_FALSE(split.has_split());
  split.factorize_split(A);
  const Eigen::VectorXd rhs = sine_rhs(A.rows());
  const Eigen::VectorXd x = split.solve_split(rhs), y = Ldlt(A).solve(rhs);
  EXPECT_TRUE(same_bits(x.data(), y.data(), x.size()));
}

// A zero pivot stops the factorisation as Eigen's does (info: NumericalIssue).
TEST(SimplicialSplit, AZeroPivotIsANumericalIssue) {
  const Eigen::SparseMatrix<double> A = torus_laplacian(90);
  Eigen::SparseMatrix<double> singular = A;
  const Eigen::VectorXd row_sums = A * Eigen::VectorXd::Ones(A.rows());
  // Diagonal less the row sums: every row sums to 0, so the matrix is singular (its last pivot
  // is zero in exact arithmetic, and tiny or zero in rounding: Eigen and the split agree).
  for (int k = 0; k < A.rows(); ++k) singular.coeffRef(k, k) -= row_sums[k];
  SplitLdlt split;
  split.analyze_split(singular, 0);
  ASSERT_TRUE(split.has_split());
  split.factorize_split(singular);
  const Ldlt eigen(singular);
  EXPECT_EQ(split.info(), eigen.info());
  if (eigen.info() == Eigen::Success) expect_eigens_factor(split, eigen);
  // Row and column 0 explicit zeros: that pivot is exactly 0.
  Eigen::SparseMatrix<double> zero = torus_laplacian(90);
  for (int k = 0; k < zero.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(zero, k); it; ++it) {
      if (it.row() == 0 || it.col() == 0) it.valueRef() = 0;
    }
  }
  split.analyze_split(zero, 0);
  split.factorize_split(zero);
  EXPECT_EQ(split.info(), Eigen::NumericalIssue);
  EXPECT_EQ(Ldlt(zero).info(), Eigen::NumericalIssue);
}

// The tree split: the dominant chain at the top is peeled off, the subtrees below go to two
// groups of comparable work; a path (no two subtrees) has no split.
TEST(TreeSplit, PeelsTheTopChainAndBalancesTheGroups) {
  // 6 is the root, 5 its child; 1, 3 and 4 are 5's children, 0 is 1's and 2 is 3's.
  const std::vector<int> parent = {1, 5, 3, 5, 5, 6, -1};
  const std::vector<double> work = {2, 2, 2, 2, 3, 1, 1};
  const std::optional<tree_split::Parts> parts = tree_split::split(parent, work);
  ASSERT_TRUE(parts.has_value());
  EXPECT_EQ(parts->top, (std::vector<int>{5, 6}));
  // Subtrees {0, 1} (4), {2, 3} (4) and {4} (3): the first two go to different groups, then 4
  // to the lighter (the first, on a tie).
  EXPECT_EQ(parts->first, (std::vector<int>{0, 1, 4}));
  EXPECT_EQ(parts->second, (std::vector<int>{2, 3}));
  EXPECT_EQ(parts->is_top, (std::vector<char>{0, 0, 0, 0, 0, 1, 1}));
  EXPECT_FALSE(tree_split::split({1, 2, 3, -1}, {1, 1, 1, 1}).has_value());
  // A subtree too small for a thread of its own: no split.
  EXPECT_FALSE(tree_split::split({2, 2, -1}, {10, 1, 1}).has_value());
}

}  // namespace
}  // namespace ricci
