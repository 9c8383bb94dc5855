#include "numerics/detail/weighted_square.hpp"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "numerics/detail/parallel.hpp"

namespace ricci::numerics_detail {

namespace {

using Sparse = Eigen::SparseMatrix<double>;

void require_square_compressed(const Sparse& A, const char* who) {
  if (A.rows() != A.cols() || !A.isCompressed()) {
    throw std::invalid_argument(std::string(who) + ": A must be square and compressed");
  }
}

}  // namespace

Sparse square_pattern(const Sparse& A) {
  require_square_compressed(A, "square_pattern");
  const auto n = static_cast<int>(A.cols());
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  std::vector<int> starts(static_cast<std::size_t>(n) + 1, 0);
  std::vector<int> rows;
  rows.reserve(static_cast<std::size_t>(A.nonZeros()) * 3);
  // mark[i] == j: row i is already in column j.
  std::vector<int> mark(static_cast<std::size_t>(n), -1);
  for (int j = 0; j < n; ++j) {
    const std::size_t start = rows.size();
    mark[j] = j;
    rows.push_back(j);
    for (int p = outer[j]; p < outer[j + 1]; ++p) {
      const int k = inner[p];
      for (int q = outer[k]; q < outer[k + 1]; ++q) {
        const int i = inner[q];
        if (mark[i] != j) {
          mark[i] = j;
          rows.push_back(i);
        }
      }
    }
    // (A column holds a few dozen rows: insertion sort.)
    for (std::size_t a = start + 1; a < rows.size(); ++a) {
      const int r = rows[a];
      std::size_t b = a;
      for (; b > start && rows[b - 1] > r; --b) rows[b] = rows[b - 1];
      rows[b] = r;
    }
    starts[j + 1] = static_cast<int>(rows.size());
  }
  Sparse pattern(n, n);
  pattern.resizeNonZeros(static_cast<Eigen::Index>(rows.size()));
  std::copy(starts.begin(), starts.end(), pattern.outerIndexPtr());
  std::copy(rows.begin(), rows.end(), pattern.innerIndexPtr());
  std::fill_n(pattern.valuePtr(), rows.size(), 0.0);
  return pattern;
}

void set_weighted_square(const Sparse& A, const Eigen::VectorXd& d, Sparse& into) {
  require_square_compressed(A, "set_weighted_square");
  require_square_compressed(into, "set_weighted_square");
  const auto n = static_cast<int>(A.cols());
  if (into.cols() != n || d.size() != n) {
    throw std::invalid_argument("set_weighted_square: sizes differ");
  }
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const double* value = A.valuePtr();
  const int* into_outer = into.outerIndexPtr();
  const int* into_inner = into.innerIndexPtr();
  double* into_value = into.valuePtr();
  // Columns are independent: chunks of them on the helpers, each with its own row -> slot map.
  parallel::for_chunks(n, [&](std::int64_t begin, std::int64_t end, int) {
    std::vector<int> slot(static_cast<std::size_t>(n), -1);
    for (auto j = static_cast<int>(begin); j < end; ++j) {
      for (int p = into_outer[j]; p < into_outer[j + 1]; ++p) {
        slot[into_inner[p]] = p;
        into_value[p] = 0;
      }
      for (int p = outer[j]; p < outer[j + 1]; ++p) {
        const int k = inner[p];
        const double a_kj = value[p];
        for (int q = outer[k]; q < outer[k + 1]; ++q) {
          const int s = slot[inner[q]];
          if (s < 0) throw std::invalid_argument("set_weighted_square: pattern lacks A A's");
          into_value[s] += (value[q] * a_kj) * d[k];
        }
      }
      for (int p = into_outer[j]; p < into_outer[j + 1]; ++p) slot[into_inner[p]] = -1;
    }
  });
}

void add_into_pattern(const Sparse& A, double scale, Sparse& into) {
  require_square_compressed(A, "add_into_pattern");
  require_square_compressed(into, "add_into_pattern");
  if (into.cols() != A.cols()) throw std::invalid_argument("add_into_pattern: sizes differ");
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    Sparse::InnerIterator target(into, j);
    for (Sparse::InnerIterator a(A, j); a; ++a) {
      while (target && target.row() < a.row()) ++target;
      if (!target || target.row() != a.row()) {
        throw std::invalid_argument("add_into_pattern: the pattern lacks an entry of A");
      }
      target.valueRef() += scale * a.value();
    }
  }
}

}  // namespace ricci::numerics_detail
