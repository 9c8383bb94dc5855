#pragma once
/// \file
/// Internal: Eigen's simplicial LDL^T factorisation and its triangular solves on two threads.
/// Below 10k rows SparseCholesky factorises with Eigen's SimplicialLDLT (CHOLMOD's supernodal
/// blocks are too small there to pay: twice Eigen's time on a 5k-vertex mesh), and the cone
/// selection, the flow's preconditioner and the few-cone refinement solve with that factor
/// dozens of times a run (bob, 5.3k vertices, 4 cones: 63 solves of 0.24 ms, a quarter of the
/// run), on one core.
///
/// Row k of L (Eigen's up-looking factorisation) reads only the columns of k's descendants in
/// the elimination tree, and column j of L holds only j's ancestors. Below its top separators
/// the tree splits into two groups of subtrees; the rows of one group never read or write the
/// other's columns, so the groups' rows are factorised beside each other and the top rows
/// after them, and the same goes for the substitutions (forward: each group's columns update
/// their own rows, then the top rows take every column's updates in column order; backward: the
/// top first, then the groups beside each other). Every entry sees the same operations in the
/// same order as in Eigen's sequential loops, so the factor and the solutions are Eigen's, bit
/// for bit, on any thread count (tests/numerics/simplicial_split_test.cpp pins it). bob: factor
/// 5.3 -> about 4 ms (the top separators' rows are the densest), a solve 0.25 -> 0.18 ms.

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <vector>

namespace ricci::simplicial {

using Ldlt = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>;

/// Eigen's SimplicialLDLT (its analysis, its storage and its own solve stay usable), with a
/// factorisation and a solve that run the split's two groups beside each other.
class SplitLdlt : public Ldlt {
 public:
  /// analyzePattern, then the split of the elimination tree: none when L holds fewer than
  /// `min_values` values or no two groups of subtrees below the top separators hold at least a
  /// quarter of the work each.
  void analyze_split(const Eigen::SparseMatrix<double>& A, double min_values);
  /// Whether the last analysis found a split (factorize_split and solve_split then use it).
  bool has_split() const { return !first_.empty(); }
  /// The same factor as factorize(A) (info() reports as Eigen's), the groups' rows beside each
  /// other. \pre analyze_split on A's pattern
  void factorize_split(const Eigen::SparseMatrix<double>& A);
  /// The same x as solve(b), the groups' substitutions beside each other. \pre a factorisation
  /// that succeeded
  Eigen::VectorXd solve_split(const Eigen::VectorXd& b) const;

 private:
  /// Rows of one part in increasing order (the rows of whole subtrees for the groups).
  void factorize_rows(const Eigen::SparseMatrix<double>& ap, const std::vector<int>& rows,
                      bool& ok);
  /// The forward substitution's updates from column j, its entries [from, to); the backward
  /// substitution's row j.
  void forward(Eigen::VectorXd& x, int j, int from, int to) const;
  void backward(Eigen::VectorXd& x, int j) const;

  std::vector<int> first_, second_, top_;  ///< columns (= rows) of each part, increasing
  std::vector<char> is_top_;
  /// Per column of the groups: its first entry in a top row (entries are in row order, and a
  /// column's ancestors in the top come after those in its group); found at the first
  /// factorisation after the analysis.
  std::vector<int> first_top_entry_;
};

}  // namespace ricci::simplicial
