#pragma once
/// \file
/// Sparse Cholesky for symmetric positive definite systems: CHOLMOD's supernodal factorisation
/// for large matrices when ricci was built with it (the library is loaded at the first such
/// matrix, not with the program), Eigen's SimplicialLDLT otherwise. The symbolic analysis (fill-
/// reducing ordering, elimination tree) is separate from the numeric factorisation so that a
/// solver can analyse once and refactorise as long as the sparsity pattern holds.
///
/// Results are bit-identical whatever the BLAS thread count: CHOLMOD's factorisation and solves
/// run with OpenBLAS held at one thread (found at run time; restored afterwards), because
/// OpenBLAS's threaded kernels sum in an order that depends on the thread count.

#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace ricci {

/// Which factorisation SparseCholesky runs.
enum class CholeskyBackend {
  /// CHOLMOD for a matrix of at least SparseCholesky::kCholmodMinRows rows, or of at least
  /// kCholmodDenseMinRows rows with more than kCholmodDenseRowNonzeros nonzeros a row; Eigen's
  /// otherwise. Mesh Laplacians (about 7 nonzeros a row) of 3k-30k rows factorise within 20 %
  /// with either, and loading CHOLMOD with its BLAS costs 3-5 ms, more than a small mesh's whole
  /// flow; denser patterns (the squared Laplacians of free seams, 19 a row) fill in more, and
  /// there CHOLMOD's supernodes are 2-5 times faster from 3k rows on (punctured torus: 8.7
  /// against 43 ms).
  Automatic,
  Cholmod,  ///< CHOLMOD whatever the size (Eigen's solver when CHOLMOD cannot be loaded)
  Eigen,    ///< Eigen's SimplicialLDLT
};

/// Factorises and solves A x = b for symmetric positive definite A (both triangles stored).
class SparseCholesky {
 public:
  /// Automatic takes CHOLMOD from this many rows on,
  static constexpr int kCholmodMinRows = 10000;
  /// and from this many rows on when a row holds more than kCholmodDenseRowNonzeros on average.
  static constexpr int kCholmodDenseMinRows = 1000;
  static constexpr int kCholmodDenseRowNonzeros = 10;

  explicit SparseCholesky(CholeskyBackend backend = CholeskyBackend::Automatic);
  /// \param use_cholmod Automatic when true, Eigen's solver when false
  explicit SparseCholesky(bool use_cholmod);
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;

  /// Symbolic analysis of A's pattern. \throw SolverError when it fails
  void analyze(const Eigen::SparseMatrix<double>& A);
  /// Numeric factorisation of A (same pattern as analysed).
  /// \throw SolverError when A is not positive definite
  void factorize(const Eigen::SparseMatrix<double>& A);
  /// The factor of A + diag(d) from the last factorisation's, of A, where d is 0 but at
  /// `changes` (index, d_i): CHOLMOD's rank-one updates (d_i > 0) and downdates (d_i < 0) of
  /// the factor (Davis and Hager), which touch only the columns on each index's path to the
  /// root of the elimination tree. A few changes on a large factor cost a small fraction of a
  /// factorisation; the factor is then a simplicial LDL^T, solved by CHOLMOD on one thread, and
  /// the next factorize() analyses afresh. Returns false when it cannot: Eigen's backend or a
  /// CHOLMOD built without its Modify module (the factor stays A's), no factorisation yet, or
  /// CHOLMOD refused (a downdate that leaves the matrix not positive definite; the factor is
  /// then lost): the caller factorises the new matrix instead.
  bool update_diagonal(const std::vector<std::pair<int, double>>& changes);
  /// Solves A x = b with the last factorisation.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  /// A^-1 b to about single precision (1e-7 relative), for preconditioners: a large CHOLMOD
  /// factor (the one solve() splits on two threads) is copied to single precision at the first
  /// call after each factorisation, which halves the memory traffic that bounds its solves (igea,
  /// 9.2M values: 13 -> 7 ms); other factors solve as solve() does. The same bits on one thread
  /// or two.
  Eigen::VectorXd solve_approximately(const Eigen::VectorXd& b) const;
  /// Solves A X = B for every column of B at once: CHOLMOD's supernodal solve then works on
  /// blocks of columns (BLAS 3), several times faster per column than one solve each; a column
  /// may differ from solve()'s in the last bits. Eigen's solver takes the columns on several
  /// threads (each column's bits the same).
  Eigen::MatrixXd solve_columns(const Eigen::MatrixXd& B) const;

  bool analyzed() const;
  /// Whether CholeskyBackend::Automatic takes CHOLMOD for a matrix of `rows` rows and
  /// `nonzeros` stored entries (the rule above; whether CHOLMOD can be loaded is another matter).
  static bool automatic_takes_cholmod(Eigen::Index rows, Eigen::Index nonzeros);
  /// Whether solve() runs on two threads: a CHOLMOD factor of at least 2M values whose
  /// elimination tree splits in two (src/numerics/detail/supernodal_split.hpp); the same bits
  /// on one thread or two either way.
  bool solves_on_two_threads() const;
  /// "cholmod-supernodal" or "eigen-simplicial-ldlt": the backend of the last analysis.
  const char* backend() const;
  /// Whether CHOLMOD was compiled in and can be loaded (loads it).
  static bool cholmod_available();
  /// Whether CHOLMOD has been loaded into the process (does not load it).
  static bool cholmod_loaded();
  /// Whether the BLAS under CHOLMOD is OpenBLAS and is held at one thread while CHOLMOD factorises
  /// and solves (false with another BLAS, whose thread count is left alone, or without CHOLMOD,
  /// or before CHOLMOD was loaded).
  static bool blas_threads_pinned();
  /// For a process that calls the BLAS only through this class (the command line): sets
  /// OpenBLAS to one thread for good and stops its worker threads (true when there were OpenBLAS
  /// threads to stop). OpenBLAS starts them when it loads, and each spins in sched_yield for
  /// about 2^28 cycles (0.1 s) before it sleeps; since the calls here run on one thread (above),
  /// they never get work, and on a 2-core machine the spinning one competes with ricci's own
  /// threads for the whole of a small run. Later openblas_set_num_threads calls start them again.
  /// Before CHOLMOD is loaded it returns false and does this right after the load.
  static bool release_blas_threads();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ricci
