#pragma once
/// \file
/// Internal: the triangular solves of a supernodal Cholesky factor L L^T (CHOLMOD's layout) on
/// two threads. A solve with a large factor is memory bound and single-threaded in CHOLMOD (BLAS
/// 2 per supernode): the elimination tree below its top separators splits into two groups of
/// subtrees that never write each other's unknowns, so each group's forward and backward
/// substitutions run beside the other's. igea (134k vertices, 9.2M factor values): 21 -> 13 ms a
/// solve; a factor below about 2M values (a few ms a solve, in the cache) gains nothing.
///
/// The split depends on the factor's structure alone and the sums run in one order whatever the
/// thread count (the second group's updates of the top separators are kept apart and added after
/// the first's), so a solve gives the same bits on one thread or two.

#include <optional>
#include <vector>

#include <Eigen/Core>

namespace ricci::supernodal {

/// A supernodal L L^T factor as CHOLMOD stores it (cholmod_factor with is_super and is_ll, real,
/// int indices), borrowed: supernode s holds columns super[s] to super[s + 1] - 1; its row
/// indices are s_index[pi[s]] to s_index[pi[s + 1] - 1] (its own columns first) and its values
/// the column-major block of those rows and columns at values + px[s]. perm: L factors P A P^T,
/// (P b)[k] = b[perm[k]].
struct Factor {
  int n = 0;
  int num_super = 0;
  const int* super = nullptr;
  const int* pi = nullptr;
  const int* px = nullptr;
  const int* s_index = nullptr;
  const int* perm = nullptr;
  const double* values = nullptr;
};

/// Supernodes in the order each part processes them in the forward solve (increasing, a union of
/// whole subtrees for the groups; the ancestors of those subtrees for the top).
struct Split {
  std::vector<int> first, second, top;
  std::vector<char> top_column;  ///< per column of L: whether a top supernode holds it
  int widest_below = 0;          ///< most rows below a supernode's own columns (work space)
};

/// The split of factor's elimination tree, or none when the factor holds fewer than min_values
/// values or its tree has no two parts of at least a quarter of the work each.
std::optional<Split> split_factor(const Factor& factor, double min_values);

/// x = A^-1 b = P^T L^-T L^-1 P b with the factor's current values, the two groups beside each
/// other when a thread is available (parallel::run_pair).
Eigen::VectorXd solve(const Factor& factor, const Split& split, const Eigen::VectorXd& b);

/// The factor's values rounded to single precision (for solve_single).
std::vector<float> single_values(const Factor& factor);

/// solve with the single-precision values `single` (single_values of the factor): the same
/// substitutions in float, half the memory traffic of solve (which bounds it), about 1e-7
/// relative accuracy. For preconditioners.
Eigen::VectorXd solve_single(const Factor& factor, const std::vector<float>& single,
                             const Split& split, const Eigen::VectorXd& b);

}  // namespace ricci::supernodal
