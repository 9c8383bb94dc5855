#pragma once
/// \file
/// Sparse symmetric positive definite matrices for the linear algebra's tests.

#include <cmath>
#include <vector>

#include <Eigen/SparseCore>

namespace ricci::testing {

/// The Laplacian of a triangulated a x a/2 periodic grid (a torus) with uneven positive weights,
/// its last row and column removed: symmetric positive definite, #V - 1 square, 7 entries a row.
inline Eigen::SparseMatrix<double> torus_laplacian(int a) {
  const int b = a / 2, n = a * b;
  std::vector<Eigen::Triplet<double>> entries;
  const auto id = [&](int i, int j) { return (i % a) * b + j % b; };
  const auto add = [&](int p, int q, double w) {
    entries.insert(entries.end(), {{p, q, -w}, {q, p, -w}, {p, p, w}, {q, q, w}});
  };
  for (int i = 0; i < a; ++i) {
    for (int j = 0; j < b; ++j) {
      add(id(i, j), id(i + 1, j), 1.0 + 0.1 * ((7 * i + j) % 5));
      add(id(i, j), id(i, j + 1), 1.0 + 0.05 * ((i + 3 * j) % 7));
      add(id(i, j), id(i + 1, j + 1), 0.3 + 0.01 * ((i + j) % 11));
    }
  }
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(entries.begin(), entries.end());
  return L.topLeftCorner(n - 1, n - 1);
}

/// b[i] = sin(0.01 i): a smooth right-hand side of n values.
inline Eigen::VectorXd sine_rhs(Eigen::Index n) {
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) b[i] = std::sin(0.01 * static_cast<double>(i));
  return b;
}

}  // namespace ricci::testing
