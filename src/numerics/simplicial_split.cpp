#include "numerics/detail/simplicial_split.hpp"

#include <cstddef>
#include <optional>
#include <utility>

#include "numerics/detail/parallel.hpp"
#include "numerics/detail/tree_split.hpp"

namespace ricci::simplicial {

void SplitLdlt::analyze_split(const Eigen::SparseMatrix<double>& A, double min_values) {
  first_.clear();
  second_.clear();
  top_.clear();
  is_top_.clear();
  first_top_entry_.clear();
  analyzePattern(A);
  if (info() != Eigen::Success) return;
  // The analysis sized each column of L (its values) and found the elimination tree.
  const int n = static_cast<int>(A.rows());
  const int* Lp = m_matrix.outerIndexPtr();
  if (n < 3 || Lp[n] < min_values) return;
  std::vector<int> parent(static_cast<std::size_t>(n));
  std::vector<double> work(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {
    parent[j] = m_parent[j];
    work[j] = static_cast<double>(Lp[j + 1] - Lp[j] + 1);
  }
  std::optional<tree_split::Parts> parts = tree_split::split(parent, work);
  if (!parts) return;
  first_ = std::move(parts->first);
  second_ = std::move(parts->second);
  top_ = std::move(parts->top);
  is_top_ = std::move(parts->is_top);
}

void SplitLdlt::factorize_rows(const Eigen::SparseMatrix<double>& ap, const std::vector<int>& rows,
                               bool& ok) {
  // Eigen's up-looking factorisation, row k of L from the columns of k's descendants: the
  // pattern of the row by the elimination tree from A's entries (in topological order), then a
  // sparse triangular solve that appends L(k, i) to each column i of the pattern. The same
  // operations in the same order as Eigen's factorize, for these rows only.
  const int n = static_cast<int>(ap.rows());
  const int* Lp = m_matrix.outerIndexPtr();
  int* Li = m_matrix.innerIndexPtr();
  double* Lx = m_matrix.valuePtr();
  int* count = m_nonZerosPerCol.data();
  const int* parent = m_parent.data();
  double* diagonal = m_diag.data();
  std::vector<double> y(static_cast<std::size_t>(n), 0.0);
  std::vector<int> pattern(static_cast<std::size_t>(n)), tags(static_cast<std::size_t>(n), -1);
  for (const int k : rows) {
    y[k] = 0;
    int top = n;
    tags[k] = k;
    count[k] = 0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(ap, k); it; ++it) {
      int i = static_cast<int>(it.index());
      if (i > k) continue;
      y[i] += it.value();
      int length = 0;
      for (; tags[i] != k; i = parent[i]) {
        pattern[length++] = i;
        tags[i] = k;
      }
      while (length > 0) pattern[--top] = pattern[--length];
    }
    double d = y[k] * m_shiftScale + m_shiftOffset;
    y[k] = 0;
    for (; top < n; ++top) {
      const int i = pattern[top];
      const double yi = y[i];
      y[i] = 0;
      const double l_ki = yi / diagonal[i];
      const int end = Lp[i] + count[i];
      int p = Lp[i];
      for (; p < end; ++p) y[Li[p]] -= Lx[p] * yi;
      d -= l_ki * yi;
      Li[p] = k;
      Lx[p] = l_ki;
      ++count[i];
    }
    diagonal[k] = d;
    if (d == 0) {
      ok = false;
      return;
    }
  }
}

void SplitLdlt::factorize_split(const Eigen::SparseMatrix<double>& A) {
  if (!has_split()) {
    factorize(A);
    return;
  }
  // A permuted as Eigen's factorize permutes it (its upper triangle).
  const Eigen::Index n = A.rows();
  Eigen::SparseMatrix<double> ap(n, n);
  ap.selfadjointView<Eigen::Upper>() = A.selfadjointView<Eigen::Lower>().twistedBy(m_P);
  m_diag.resize(n);
  bool ok_first = true, ok_second = true, ok_top = true;
  parallel::run_pair([&] { factorize_rows(ap, first_, ok_first); },
                     [&] { factorize_rows(ap, second_, ok_second); });
  if (ok_first && ok_second) factorize_rows(ap, top_, ok_top);
  const bool ok = ok_first && ok_second && ok_top;
  m_info = ok ? Eigen::Success : Eigen::NumericalIssue;
  m_factorizationIsOk = true;
  if (ok && first_top_entry_.empty()) {
    const int* Lp = m_matrix.outerIndexPtr();
    const int* Li = m_matrix.innerIndexPtr();
    first_top_entry_.assign(static_cast<std::size_t>(n), 0);
    for (Eigen::Index j = 0; j < n; ++j) {
      int p = Lp[j];
      while (p < Lp[j + 1] && !is_top_[Li[p]]) ++p;
      first_top_entry_[j] = p;
    }
  }
}

void SplitLdlt::forward(Eigen::VectorXd& x, int j, int from, int to) const {
  // (Eigen's unit lower solve skips a zero unknown's updates: so does this.)
  const double xj = x[j];
  if (xj == 0) return;
  const int* Li = m_matrix.innerIndexPtr();
  const double* Lx = m_matrix.valuePtr();
  for (int p = from; p < to; ++p) x[Li[p]] -= Lx[p] * xj;
}

void SplitLdlt::backward(Eigen::VectorXd& x, int j) const {
  const int* Lp = m_matrix.outerIndexPtr();
  const int* Li = m_matrix.innerIndexPtr();
  const double* Lx = m_matrix.valuePtr();
  double sum = x[j];
  for (int p = Lp[j]; p < Lp[j + 1]; ++p) sum -= Lx[p] * x[Li[p]];
  x[j] = sum;
}

Eigen::VectorXd SplitLdlt::solve_split(const Eigen::VectorXd& b) const {
  if (!has_split() || first_top_entry_.empty()) return solve(b);
  const int n = static_cast<int>(b.size());
  const int* Lp = m_matrix.outerIndexPtr();
  Eigen::VectorXd x = m_P * b;
  // Forward: each group's columns update their group's rows (the entries before their first
  // top entry) beside the other group's...
  const auto forward_group = [&](const std::vector<int>& columns) {
    for (const int j : columns) forward(x, j, Lp[j], first_top_entry_[j]);
  };
  parallel::run_pair([&] { forward_group(first_); }, [&] { forward_group(second_); });
  // ... then every column updates the top rows, in column order as Eigen's loop does.
  for (int j = 0; j < n; ++j) forward(x, j, is_top_[j] ? Lp[j] : first_top_entry_[j], Lp[j + 1]);
  x = m_diag.asDiagonal().inverse() * x;
  // Backward: the top rows first, then each group's beside the other's.
  for (auto j = top_.rbegin(); j != top_.rend(); ++j) backward(x, *j);
  const auto backward_group = [&](const std::vector<int>& columns) {
    for (auto j = columns.rbegin(); j != columns.rend(); ++j) backward(x, *j);
  };
  parallel::run_pair([&] { backward_group(first_); }, [&] { backward_group(second_); });
  return m_Pinv * x;
}

}  // namespace ricci::simplicial
