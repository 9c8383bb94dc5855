#pragma once
/// \file
/// Sparse Cholesky for symmetric positive definite systems: CHOLMOD's supernodal factorisation
/// when ricci was built with it, Eigen's SimplicialLDLT otherwise. The symbolic analysis (fill-
/// reducing ordering, elimination tree) is separate from the numeric factorisation so that a
/// solver can analyse once and refactorise as long as the sparsity pattern holds.
///
/// Results are bit-identical whatever the BLAS thread count: CHOLMOD's factorisation and solves
/// run with OpenBLAS held at one thread (found at run time; restored afterwards), because
/// OpenBLAS's threaded kernels sum in an order that depends on the thread count.

#include <memory>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace ricci {

/// Factorises and solves A x = b for symmetric positive definite A (both triangles stored).
class SparseCholesky {
 public:
  /// \param use_cholmod take CHOLMOD when available (false forces Eigen's solver)
  explicit SparseCholesky(bool use_cholmod = true);
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;

  /// Symbolic analysis of A's pattern. \throw SolverError when it fails
  void analyze(const Eigen::SparseMatrix<double>& A);
  /// Numeric factorisation of A (same pattern as analysed).
  /// \throw SolverError when A is not positive definite
  void factorize(const Eigen::SparseMatrix<double>& A);
  /// Solves A x = b with the last factorisation.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

  bool analyzed() const;
  /// "cholmod-supernodal" or "eigen-simplicial-ldlt".
  const char* backend() const;
  /// Whether CHOLMOD was compiled in.
  static bool cholmod_available();
  /// Whether the BLAS under CHOLMOD is OpenBLAS and is held at one thread while CHOLMOD factorises
  /// and solves (false with another BLAS, whose thread count is left alone, or without CHOLMOD).
  static bool blas_threads_pinned();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ricci
