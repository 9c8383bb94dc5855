#include "numerics/detail/supernodal_split.hpp"

#include <algorithm>
#include <type_traits>
#include <utility>

#include <Eigen/Dense>

#include "numerics/detail/parallel.hpp"
#include "numerics/detail/tree_split.hpp"

namespace ricci::supernodal {
namespace {

template <class Scalar>
struct Block {
  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  int first_column, columns, rows_below;
  const int* below;  ///< row indices under the supernode's own columns
  Eigen::Map<const Matrix> values;
};

/// Supernode s of the factor's structure with the values at `values` (the factor's own, or a
/// copy of them in another precision).
template <class Scalar>
Block<Scalar> block_of(const Factor& f, const Scalar* values, int s) {
  const int first_column = f.super[s], columns = f.super[s + 1] - first_column;
  const int rows = f.pi[s + 1] - f.pi[s];
  return {first_column, columns, rows - columns, f.s_index + f.pi[s] + columns,
          Eigen::Map<const typename Block<Scalar>::Matrix>(values + f.px[s], rows, columns)};
}

template <class Scalar>
using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;

/// Forward substitution through supernode s: its unknowns, then its updates of the rows below
/// (into `elsewhere` for the top columns when it is given, into x otherwise).
template <class Scalar>
void forward(const Factor& f, const Scalar* values, int s, Scalar* x,
             std::type_identity_t<Scalar>* elsewhere, const std::vector<char>* top,
             Vector<Scalar>& work) {
  const Block<Scalar> b = block_of(f, values, s);
  Eigen::Map<Vector<Scalar>> y(x + b.first_column, b.columns);
  b.values.topRows(b.columns).template triangularView<Eigen::Lower>().solveInPlace(y);
  if (b.rows_below == 0) return;
  Eigen::Map<Vector<Scalar>> t(work.data(), b.rows_below);
  t.noalias() = b.values.bottomRows(b.rows_below) * y;
  for (int j = 0; j < b.rows_below; ++j) {
    const int row = b.below[j];
    if (elsewhere != nullptr && (*top)[row]) {
      elsewhere[row] -= t[j];
    } else {
      x[row] -= t[j];
    }
  }
}

/// Backward substitution through supernode s (the rows below it already solved).
template <class Scalar>
void backward(const Factor& f, const Scalar* values, int s, Scalar* x, Vector<Scalar>& work) {
  const Block<Scalar> b = block_of(f, values, s);
  Eigen::Map<Vector<Scalar>> y(x + b.first_column, b.columns);
  if (b.rows_below > 0) {
    Eigen::Map<Vector<Scalar>> g(work.data(), b.rows_below);
    for (int j = 0; j < b.rows_below; ++j) g[j] = x[b.below[j]];
    y.noalias() -= b.values.bottomRows(b.rows_below).transpose() * g;
  }
  b.values.topRows(b.columns).transpose().template triangularView<Eigen::Upper>().solveInPlace(y);
}

/// solve and solve_single: the substitutions in Scalar with the values at `values`.
template <class Scalar>
Eigen::VectorXd solve_in(const Factor& f, const Scalar* values, const Split& split,
                         const Eigen::VectorXd& b) {
  Vector<Scalar> x(f.n);
  for (int k = 0; k < f.n; ++k) x[k] = static_cast<Scalar>(b[f.perm[k]]);
  // The second group's updates of the top columns, added after the first group's.
  Vector<Scalar> elsewhere = Vector<Scalar>::Zero(f.n);
  Vector<Scalar> work_first(split.widest_below), work_second(split.widest_below);
  parallel::run_pair(
      [&] {
        for (int s : split.first) forward(f, values, s, x.data(), nullptr, nullptr, work_first);
      },
      [&] {
        for (int s : split.second) {
          forward(f, values, s, x.data(), elsewhere.data(), &split.top_column, work_second);
        }
      });
  for (int s : split.top) {
    for (int k = f.super[s]; k < f.super[s + 1]; ++k) x[k] += elsewhere[k];
  }
  for (int s : split.top) forward(f, values, s, x.data(), nullptr, nullptr, work_first);
  for (auto s = split.top.rbegin(); s != split.top.rend(); ++s) {
    backward(f, values, *s, x.data(), work_first);
  }
  const auto backward_group = [&](const std::vector<int>& group, Vector<Scalar>& work) {
    for (auto s = group.rbegin(); s != group.rend(); ++s) backward(f, values, *s, x.data(), work);
  };
  parallel::run_pair([&] { backward_group(split.first, work_first); },
                     [&] { backward_group(split.second, work_second); });
  Eigen::VectorXd out(f.n);
  for (int k = 0; k < f.n; ++k) out[f.perm[k]] = static_cast<double>(x[k]);
  return out;
}

}  // namespace

std::optional<Split> split_factor(const Factor& f, double min_values) {
  if (f.num_super < 3 || f.px[f.num_super] < min_values) return std::nullopt;
  std::vector<int> super_of_column(static_cast<std::size_t>(f.n));
  for (int s = 0; s < f.num_super; ++s) {
    for (int k = f.super[s]; k < f.super[s + 1]; ++k) super_of_column[k] = s;
  }
  // The supernodal elimination tree and the work (values) of each supernode.
  std::vector<int> parent(f.num_super, -1);
  std::vector<double> own(f.num_super);
  Split split;
  for (int s = 0; s < f.num_super; ++s) {
    const Block<double> b = block_of(f, f.values, s);
    own[s] = static_cast<double>(b.values.size());
    split.widest_below = std::max(split.widest_below, b.rows_below);
    if (b.rows_below > 0) parent[s] = super_of_column[b.below[0]];
  }
  std::optional<tree_split::Parts> parts = tree_split::split(parent, own);
  if (!parts) return std::nullopt;
  split.first = std::move(parts->first);
  split.second = std::move(parts->second);
  split.top = std::move(parts->top);
  split.top_column.assign(static_cast<std::size_t>(f.n), 0);
  for (int s : split.top) {
    for (int k = f.super[s]; k < f.super[s + 1]; ++k) split.top_column[k] = 1;
  }
  return split;
}

Eigen::VectorXd solve(const Factor& f, const Split& split, const Eigen::VectorXd& b) {
  return solve_in(f, f.values, split, b);
}

std::vector<float> single_values(const Factor& f) {
  const int count = f.px[f.num_super];
  std::vector<float> single(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) single[i] = static_cast<float>(f.values[i]);
  return single;
}

Eigen::VectorXd solve_single(const Factor& f, const std::vector<float>& single, const Split& split,
                             const Eigen::VectorXd& b) {
  return solve_in(f, single.data(), split, b);
}

}  // namespace ricci::supernodal
