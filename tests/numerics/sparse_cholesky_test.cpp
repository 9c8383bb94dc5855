#include "ricci/numerics/sparse_cholesky.hpp"

#include <dlfcn.h>
#include <link.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "ricci/errors.hpp"
#include "support/scoped_threads.hpp"
#include "support/test_matrices.hpp"

namespace ricci {
namespace {

using testing::sine_rhs;
using testing::torus_laplacian;

/// solve() on one thread and on two (RICCI_NUM_THREADS), check(x, threads) on each: the same
/// bits both times.
template <class Solve, class Check>
void same_bits_on_one_and_two_threads(Solve&& solve, Check&& check) {
  Eigen::VectorXd first;
  for (const char* threads : {"1", "2"}) {
    const testing::ScopedThreads scoped(threads);
    const Eigen::VectorXd x = solve();
    check(x, threads);
    if (first.size() == 0) {
      first = x;
    } else {
      EXPECT_TRUE((x.array() == first.array()).all()) << threads;
    }
  }
}

TEST(SparseCholesky, SolvesBothBackends) {
  const Eigen::SparseMatrix<double> A = torus_laplacian(20);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 1.0);
  for (const CholeskyBackend backend : {CholeskyBackend::Cholmod, CholeskyBackend::Eigen}) {
    SparseCholesky cholesky(backend);
    EXPECT_FALSE(cholesky.analyzed());
    cholesky.factorize(A);  // analyses first
    EXPECT_TRUE(cholesky.analyzed());
    const Eigen::VectorXd x = cholesky.solve(b);
    // Condition number of this Laplacian about 1e3: residual at round-off.
    EXPECT_LT((A * x - b).cwiseAbs().maxCoeff(), 1e-11) << cholesky.backend();
  }
}

/// A + diag(d), d given at `changes`.
Eigen::SparseMatrix<double> with_diagonal(Eigen::SparseMatrix<double> A,
                                          const std::vector<std::pair<int, double>>& changes) {
  for (const auto& [i, d] : changes) A.coeffRef(i, i) += d;
  return A;
}

// Rank-one updates and downdates of CHOLMOD's factor solve as a factorisation of the modified
// matrix does, round after round (each changing the previous round's matrix), and the factor
// can be factorised afresh afterwards (for the supernodes again).
TEST(SparseCholesky, DiagonalUpdatesSolveAsAFactorisationOfTheNewMatrix) {
  if (!SparseCholesky::cholmod_available()) GTEST_SKIP() << "built without CHOLMOD";
  Eigen::SparseMatrix<double> A = torus_laplacian(120);  // 7199 rows
  const Eigen::VectorXd b = sine_rhs(A.rows());
  SparseCholesky updated(CholeskyBackend::Cholmod);
  updated.factorize(A);
  ASSERT_TRUE(updated.solves_on_two_threads());
  const std::vector<std::vector<std::pair<int, double>>> rounds = {
      {{5, 3.0}, {4000, 0.5}, {7198, 2.0}},               // updates only
      {{5, -3.0}, {17, 1.0}, {4000, -0.25}, {900, 7.0}},  // and downdates of the last round's
      {{17, -1.0}, {900, -7.0}, {4000, -0.25}, {6000, 1e3}},
  };
  for (std::size_t r = 0; r < rounds.size(); ++r) {
    A = with_diagonal(A, rounds[r]);
    ASSERT_TRUE(updated.update_diagonal(rounds[r])) << "round " << r;
    EXPECT_FALSE(updated.solves_on_two_threads());  // a simplicial factor now
    SparseCholesky fresh(CholeskyBackend::Cholmod);
    fresh.factorize(A);
    const Eigen::VectorXd x = fresh.solve(b), y = updated.solve(b);
    EXPECT_LT((y - x).cwiseAbs().maxCoeff(), 1e-10 * x.cwiseAbs().maxCoeff()) << "round " << r;
    EXPECT_LT((A * y - b).cwiseAbs().maxCoeff(), 1e-10) << "round " << r;
  }
  // A downdate past positive definiteness is refused; a factorisation afterwards starts over.
  EXPECT_FALSE(updated.update_diagonal({{10, -1e6}}));
  updated.factorize(A);
  EXPECT_TRUE(updated.solves_on_two_threads());
  EXPECT_LT((A * updated.solve(b) - b).cwiseAbs().maxCoeff(), 1e-10);
}

// Eigen's backend has no updates: it says so and keeps its factor.
TEST(SparseCholesky, DiagonalUpdatesAreRefusedByEigensBackend) {
  const Eigen::SparseMatrix<double> A = torus_laplacian(20);
  const Eigen::VectorXd b = sine_rhs(A.rows());
  SparseCholesky cholesky(CholeskyBackend::Eigen);
  EXPECT_FALSE(cholesky.update_diagonal({{0, 1.0}}));  // nothing factorised yet
  cholesky.factorize(A);
  EXPECT_FALSE(cholesky.update_diagonal({{0, 1.0}}));
  EXPECT_LT((A * cholesky.solve(b) - b).cwiseAbs().maxCoeff(), 1e-11);
}

TEST(SparseCholesky, RefusesAnIndefiniteMatrix) {
  Eigen::SparseMatrix<double> A = torus_laplacian(10);
  A.coeffRef(3, 3) = -1.0;
  for (const CholeskyBackend backend : {CholeskyBackend::Cholmod, CholeskyBackend::Eigen}) {
    SparseCholesky cholesky(backend);
    EXPECT_THROW(cholesky.factorize(A), SolverError) << cholesky.backend();
  }
}

/// Tests of OpenBLAS's thread control (found in the process, as sparse_cholesky.cpp finds it):
/// skipped without CHOLMOD or with another BLAS; the thread count is restored afterwards.
class OpenBlasThreads : public ::testing::Test {
 protected:
  using SetThreads = void (*)(int);
  using GetThreads = int (*)();
  void SetUp() override {
    if (!SparseCholesky::cholmod_available()) GTEST_SKIP() << "built without CHOLMOD";
    if (!SparseCholesky::blas_threads_pinned()) GTEST_SKIP() << "the BLAS is not OpenBLAS";
    set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    get = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
    ASSERT_NE(set, nullptr);
    ASSERT_NE(get, nullptr);
    initial = get();
  }
  void TearDown() override {
    if (set != nullptr) set(initial);
  }
  SetThreads set = nullptr;
  GetThreads get = nullptr;
  int initial = 1;
};

// OpenBLAS's threaded kernels sum in a thread-count-dependent order: without the pinning in
// sparse_cholesky.cpp, CHOLMOD's supernodal solution of this system differs by ~1e-13 between 1 and
// 2 OpenBLAS threads (measured). With it, the results must be bit-identical and the caller's thread
// count must be back in place afterwards.
TEST_F(OpenBlasThreads, CholmodIsBitIdenticalAcrossThreadCounts) {
  const Eigen::SparseMatrix<double> A = torus_laplacian(60);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 1.0);
  std::vector<Eigen::VectorXd> solutions;
  for (int threads : {1, 2, 4}) {
    set(threads);
    SparseCholesky cholesky(CholeskyBackend::Cholmod);
    cholesky.factorize(A);
    ASSERT_STREQ(cholesky.backend(), "cholmod-supernodal");
    solutions.push_back(cholesky.solve(b));
    EXPECT_EQ(get(), threads) << "the caller's BLAS thread count is restored";
  }
  for (std::size_t k = 1; k < solutions.size(); ++k) {
    // Bit for bit: == on doubles, no tolerance.
    EXPECT_TRUE((solutions[k].array() == solutions[0].array()).all())
        << "max difference " << (solutions[k] - solutions[0]).cwiseAbs().maxCoeff();
  }
}

// A block of right-hand sides solved at once gives each column's solution (to rounding), with
// CHOLMOD and with Eigen's solver.
TEST(SparseCholesky, SolvesColumnsAtOnce) {
  const Eigen::SparseMatrix<double> A = torus_laplacian(30);
  Eigen::MatrixXd B(A.rows(), 5);
  for (int j = 0; j < 5; ++j) B.col(j) = Eigen::VectorXd::LinSpaced(A.rows(), -1.0 - j, 2.0 * j);
  for (const CholeskyBackend backend : {CholeskyBackend::Cholmod, CholeskyBackend::Eigen}) {
    SparseCholesky cholesky(backend);
    cholesky.factorize(A);
    const Eigen::MatrixXd X = cholesky.solve_columns(B);
    ASSERT_EQ(X.rows(), A.rows());
    ASSERT_EQ(X.cols(), 5);
    for (int j = 0; j < 5; ++j) {
      const Eigen::VectorXd x = cholesky.solve(B.col(j));
      EXPECT_LT((X.col(j) - x).norm(), 1e-12 * x.norm()) << cholesky.backend() << " column " << j;
      EXPECT_LT((A * X.col(j) - B.col(j)).norm(), 1e-9 * B.col(j).norm());
    }
  }
}

// A large factor solves on two threads (its elimination tree split in two groups of subtrees):
// the solution is CHOLMOD's own to rounding, and the same bits on one thread or two. A small
// one keeps CHOLMOD's solve.
TEST(SparseCholesky, LargeFactorsSolveOnTwoThreadsWithTheSameBits) {
  if (!SparseCholesky::cholmod_available()) GTEST_SKIP() << "built without CHOLMOD";
  SparseCholesky small(CholeskyBackend::Cholmod);
  small.factorize(torus_laplacian(20));
  EXPECT_FALSE(small.solves_on_two_threads());
  const Eigen::SparseMatrix<double> A = torus_laplacian(400);
  SparseCholesky cholesky;
  cholesky.factorize(A);
  ASSERT_TRUE(cholesky.solves_on_two_threads());
  const Eigen::VectorXd b = sine_rhs(A.rows());
  const Eigen::VectorXd cholmod = cholesky.solve_columns(b);  // CHOLMOD's solve
  same_bits_on_one_and_two_threads([&] { return cholesky.solve(b); },
                                   [&](const Eigen::VectorXd& x, const char* threads) {
                                     EXPECT_LT((x - cholmod).norm(), 1e-12 * cholmod.norm())
                                         << threads;
                                     EXPECT_LT((A * x - b).norm(), 1e-9 * b.norm()) << threads;
                                   });
  // A refactorisation (same pattern, other values) keeps the split and solves with the new
  // values.
  const Eigen::SparseMatrix<double> twice = 2 * A;
  cholesky.factorize(twice);
  EXPECT_TRUE(cholesky.solves_on_two_threads());
  EXPECT_LT((cholesky.solve(b) - 0.5 * cholmod).norm(), 1e-12 * cholmod.norm());
}

// solve_approximately: a large factor solves in single precision (near solve(), not equal to
// it, the same bits on one thread or two, refreshed by a refactorisation); a small one solves
// exactly as solve() does.
TEST(SparseCholesky, ApproximateSolvesAreSinglePrecisionOnLargeFactors) {
  if (!SparseCholesky::cholmod_available()) GTEST_SKIP() << "built without CHOLMOD";
  const Eigen::SparseMatrix<double> small_matrix = torus_laplacian(20);
  SparseCholesky small(CholeskyBackend::Cholmod);
  small.factorize(small_matrix);
  const Eigen::VectorXd small_b = Eigen::VectorXd::LinSpaced(small_matrix.rows(), -1.0, 1.0);
  EXPECT_TRUE((small.solve_approximately(small_b).array() == small.solve(small_b).array()).all());

  const Eigen::SparseMatrix<double> A = torus_laplacian(400);
  SparseCholesky cholesky;
  cholesky.factorize(A);
  ASSERT_TRUE(cholesky.solves_on_two_threads());
  const Eigen::VectorXd b = sine_rhs(A.rows());
  const Eigen::VectorXd exact = cholesky.solve(b);
  same_bits_on_one_and_two_threads(
      [&] { return cholesky.solve_approximately(b); },
      [&](const Eigen::VectorXd& x, const char* threads) {
        const double error = (x - exact).norm() / exact.norm();
        EXPECT_LT(error, 1e-4) << threads;   // single precision, conditioning about 1e4
        EXPECT_GT(error, 1e-13) << threads;  // not the double-precision solve
      });
  const Eigen::SparseMatrix<double> twice = 2 * A;
  cholesky.factorize(twice);
  EXPECT_LT((cholesky.solve_approximately(b) - 0.5 * exact).norm(), 1e-4 * exact.norm());
}

/// The number of threads of this process (Linux: the entries of /proc/self/task).
long thread_count() {
  const std::filesystem::directory_iterator tasks("/proc/self/task");
  return std::distance(std::filesystem::begin(tasks), std::filesystem::end(tasks));
}

// OpenBLAS's workers are stopped (the process loses them) and it stays at one thread; solves
// after that give the same bits as before, and OpenBLAS still computes on threads when a caller
// asks for them again.
TEST_F(OpenBlasThreads, ReleasedThreadsStopAndComeBackOnDemand) {
  set(2);  // starts a worker if OpenBLAS had none

  const Eigen::SparseMatrix<double> A = torus_laplacian(40);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 1.0);
  SparseCholesky before(CholeskyBackend::Cholmod);
  before.factorize(A);
  const Eigen::VectorXd x = before.solve(b);

  const long threads = thread_count();
  EXPECT_TRUE(SparseCholesky::release_blas_threads());
  EXPECT_LT(thread_count(), threads) << "the worker is gone";
  EXPECT_EQ(get(), 1);
  EXPECT_FALSE(SparseCholesky::release_blas_threads()) << "nothing left to stop";

  SparseCholesky after(CholeskyBackend::Cholmod);
  after.factorize(A);
  EXPECT_TRUE((after.solve(b).array() == x.array()).all());

  // Asked for threads again, OpenBLAS restarts its workers and dgemm on them is right.
  set(2);
  using Dgemm = void (*)(const char*, const char*, const int*, const int*, const int*,
                         const double*, const double*, const int*, const double*, const int*,
                         const double*, double*, const int*);
  const auto dgemm = reinterpret_cast<Dgemm>(dlsym(RTLD_DEFAULT, "dgemm_"));
  if (dgemm != nullptr) {
    const int n = 400;
    const Eigen::MatrixXd P = Eigen::MatrixXd::Random(n, n), Q = Eigen::MatrixXd::Random(n, n);
    Eigen::MatrixXd R = Eigen::MatrixXd::Zero(n, n);
    const double one = 1.0, zero = 0.0;
    dgemm("N", "N", &n, &n, &n, &one, P.data(), &n, Q.data(), &n, &zero, R.data(), &n);
    EXPECT_LT((R - P * Q).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_GE(thread_count(), threads) << "OpenBLAS started its worker again";
    EXPECT_EQ(get(), 2);
  }
}

// CHOLMOD's supernodal factorisation opens OpenMP regions of a thread count fixed when it was
// built (four in Debian's); on two cores they cost more than the factorisation. SparseCholesky
// runs them on the calling thread: a thread that factorises starts no OpenMP team of its own, and
// its OpenMP setting is as it was afterwards.
TEST(SparseCholesky, CholmodLoopsRunOnTheCallingThread) {
  if (!SparseCholesky::cholmod_available()) GTEST_SKIP() << "built without CHOLMOD";
  using GetLevels = int (*)();
  using SetLevels = void (*)(int);
  const auto get_levels =
      reinterpret_cast<GetLevels>(dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"));
  const auto set_levels =
      reinterpret_cast<SetLevels>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"));
  if (get_levels == nullptr || set_levels == nullptr) GTEST_SKIP() << "no OpenMP runtime loaded";
  // 20k unknowns: supernodes far above the 1024 values from which CHOLMOD's loops go parallel.
  const Eigen::SparseMatrix<double> A = torus_laplacian(200);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 1.0);
  SparseCholesky reference(CholeskyBackend::Cholmod);
  reference.factorize(A);  // here: whatever the BLAS starts, it has started
  const Eigen::VectorXd x = reference.solve(b);
  // A new thread has no OpenMP team yet; one started by CHOLMOD would stay (idle) until it ends.
  long before = 0, after = 0;
  int levels_after = -1;
  bool same_bits = false;
  std::thread fresh([&] {
    set_levels(3);
    before = thread_count();
    SparseCholesky cholesky(CholeskyBackend::Cholmod);
    cholesky.factorize(A);
    same_bits = (cholesky.solve(b).array() == x.array()).all();
    after = thread_count();
    levels_after = get_levels();
  });
  fresh.join();
  EXPECT_EQ(after, before) << "CHOLMOD started OpenMP threads";
  EXPECT_EQ(levels_after, 3) << "the caller's max-active-levels restored";
  EXPECT_TRUE(same_bits);
}

// Automatic: Eigen's solver below kCholmodMinRows rows (as fast there, and nothing to load)
// unless the rows are dense, CHOLMOD otherwise where it can be loaded; each analysis chooses
// again.
TEST(SparseCholesky, AutomaticTakesCholmodForLargeMatricesOnly) {
  const Eigen::SparseMatrix<double> small_matrix = torus_laplacian(20);
  const Eigen::SparseMatrix<double> large = torus_laplacian(142);  // 142 x 71 = 10082 rows
  ASSERT_LT(small_matrix.rows(), SparseCholesky::kCholmodMinRows);
  ASSERT_GE(large.rows(), SparseCholesky::kCholmodMinRows);
  const char* large_backend =
      SparseCholesky::cholmod_available() ? "cholmod-supernodal" : "eigen-simplicial-ldlt";
  // The squared Laplacian of a 4050-row grid: 19 nonzeros a row.
  const Eigen::SparseMatrix<double> base = torus_laplacian(90);
  const Eigen::SparseMatrix<double> dense = (base * base).pruned();
  ASSERT_LT(dense.rows(), SparseCholesky::kCholmodMinRows);
  ASSERT_GT(dense.nonZeros(), SparseCholesky::kCholmodDenseRowNonzeros * dense.rows());
  SparseCholesky cholesky;
  for (const Eigen::SparseMatrix<double>* A : {&small_matrix, &large, &base, &dense}) {
    cholesky.analyze(*A);
    cholesky.factorize(*A);
    const bool cholmod_wanted = A == &large || A == &dense;
    // (What callers read to load CHOLMOD ahead of the analysis: the same rule.)
    EXPECT_EQ(SparseCholesky::automatic_takes_cholmod(A->rows(), A->nonZeros()), cholmod_wanted);
    EXPECT_STREQ(cholesky.backend(), cholmod_wanted ? large_backend : "eigen-simplicial-ldlt");
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A->rows(), -1.0, 1.0);
    const Eigen::VectorXd x = cholesky.solve(b);
    // Backward stable: the residual at round-off of |A| |x| (the squared Laplacian's condition
    // number is about 1e7).
    const double scale = (A->cwiseAbs() * x.cwiseAbs()).maxCoeff();
    EXPECT_LT((*A * x - b).cwiseAbs().maxCoeff(), 1e-13 * scale) << cholesky.backend();
  }
}

/// Whether an object whose path contains `name` is loaded in this process.
bool loaded_in_process(const char* name) {
  struct Search {
    const char* name;
    bool found = false;
  } search{name};
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* data) {
        auto* s = static_cast<Search*>(data);
        if (info->dlpi_name != nullptr && std::strstr(info->dlpi_name, s->name) != nullptr) {
          s->found = true;
        }
        return 0;
      },
      &search);
  return search.found;
}

// CHOLMOD and its BLAS load with the first matrix that needs them, not with the program: small
// matrices leave them unloaded, and the command line's request to stop OpenBLAS's threads, made
// before, is carried out as they load (OpenBLAS starts its threads as it loads). ctest runs each
// test in a process of its own; in a process where an earlier test loaded CHOLMOD it is skipped.
TEST(SparseCholesky, CholmodLoadsWithTheFirstMatrixThatNeedsIt) {
  if (SparseCholesky::cholmod_loaded()) GTEST_SKIP() << "an earlier test loaded CHOLMOD";
  EXPECT_FALSE(loaded_in_process("libcholmod"));
  EXPECT_FALSE(SparseCholesky::release_blas_threads()) << "nothing to stop before the load";
  SparseCholesky small;
  small.factorize(torus_laplacian(20));
  EXPECT_FALSE(SparseCholesky::cholmod_loaded());
  EXPECT_FALSE(loaded_in_process("libcholmod"));

  SparseCholesky large;
  large.factorize(torus_laplacian(142));
  if (!SparseCholesky::cholmod_loaded()) GTEST_SKIP() << "CHOLMOD cannot be loaded here";
  EXPECT_TRUE(loaded_in_process("libcholmod"));
  EXPECT_STREQ(large.backend(), "cholmod-supernodal");
  using GetThreads = int (*)();
  const auto get = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  if (get != nullptr) {
    EXPECT_EQ(get(), 1) << "OpenBLAS's threads released as it loaded";
  }
}

}  // namespace
}  // namespace ricci
