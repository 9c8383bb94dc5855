#include "ricci/numerics/sparse_cholesky.hpp"

#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/SparseCholesky>

#ifdef RICCI_HAVE_CHOLMOD
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>

#include "numerics/detail/cholmod_library.hpp"
#include "numerics/detail/parallel.hpp"
#include "numerics/detail/supernodal_split.hpp"
#endif

#include "numerics/detail/simplicial_split.hpp"
#include "ricci/errors.hpp"

#if defined(RICCI_HAVE_CHOLMOD) && defined(__linux__)
#include <dlfcn.h>
#include <link.h>

#include <string>
#define RICCI_PIN_BLAS_THREADS 1
#endif

namespace ricci {

namespace {

#ifdef RICCI_PIN_BLAS_THREADS
// Determinism across thread counts. CHOLMOD's supernodal factorisation hands its dense blocks to
// the BLAS and LAPACK (dsyrk, dgemm, dtrsm, dpotrf); OpenBLAS splits those among its threads in a
// way that changes the order of the sums, so OPENBLAS_NUM_THREADS=1 and =2 give factors (and flow
// results) that differ in the last bits. Pinning OpenBLAS to one thread for the factorisation and
// the solves makes them bit-identical whatever the process's thread count; on the 1M-face torus
// this costs less than CHOLMOD's simplicial factorisation, which needs no BLAS but is several
// times slower (docs/architecture.md, "Robustness", has the figures).
//
// OpenBLAS's thread control is looked up at run time, so that ricci links only the generic BLAS
// and runs unchanged on the reference BLAS or another implementation (which are then left alone).

using SetThreads = void (*)(int);
using GetThreads = int (*)();
using StopThreads = int (*)();

void* find_loaded_symbol(const char* name) {
  if (void* symbol = dlsym(RTLD_DEFAULT, name)) return symbol;
  // Not in the global scope: ricci was loaded with RTLD_LOCAL (a Python extension module), and
  // its BLAS with it. Look in every loaded object; dlopen is called only after the iteration,
  // which holds the loader's lock.
  std::vector<std::string> objects;
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* names) {
        if (info->dlpi_name != nullptr && info->dlpi_name[0] != '\0') {
          static_cast<std::vector<std::string>*>(names)->emplace_back(info->dlpi_name);
        }
        return 0;
      },
      &objects);
  for (const std::string& object : objects) {
    void* handle = dlopen(object.c_str(), RTLD_LAZY | RTLD_NOLOAD);
    if (handle == nullptr) continue;
    void* symbol = dlsym(handle, name);
    dlclose(handle);  // balances this dlopen; the object stays loaded
    if (symbol != nullptr) return symbol;
  }
  return nullptr;
}

/// A setting's setter and getter where the process loaded them: both, or neither.
template <class Set, class Get>
struct LoadedControl {
  Set set = nullptr;
  Get get = nullptr;
};

template <class Set, class Get>
LoadedControl<Set, Get> find_control(const char* set_name, const char* get_name) {
  LoadedControl<Set, Get> c;
  c.set = reinterpret_cast<Set>(find_loaded_symbol(set_name));
  c.get = reinterpret_cast<Get>(find_loaded_symbol(get_name));
  if (c.set == nullptr || c.get == nullptr) return {};
  return c;
}

struct OpenBlasThreadControl : LoadedControl<SetThreads, GetThreads> {
  // blas_thread_shutdown_: not in OpenBLAS's documented API, but exported by every 0.3 release
  // (its fork handler calls it); optional, so a BLAS without it only misses the saving.
  StopThreads stop = nullptr;
};

const OpenBlasThreadControl& openblas_thread_control() {
  static const OpenBlasThreadControl control = [] {
    OpenBlasThreadControl c;
    static_cast<LoadedControl<SetThreads, GetThreads>&>(c) = find_control<SetThreads, GetThreads>(
        "openblas_set_num_threads", "openblas_get_num_threads");
    if (c.set != nullptr) {
      c.stop = reinterpret_cast<StopThreads>(find_loaded_symbol("blas_thread_shutdown_"));
    }
    return c;
  }();
  return control;
}

/// Holds OpenBLAS at one thread while alive and restores the previous count afterwards.
/// Holders in several threads at once share one save and one restore (the last one out
/// restores). While any holder lives, other BLAS calls of the process also run on one thread.
class SingleThreadedBlas {
 public:
  SingleThreadedBlas() {
    const OpenBlasThreadControl& blas = openblas_thread_control();
    if (blas.set == nullptr) return;
    const std::lock_guard<std::mutex> lock(mutex());
    State& s = state();
    if (s.holders++ == 0) {
      s.saved = blas.get();
      if (s.saved != 1) blas.set(1);
    }
  }
  ~SingleThreadedBlas() {
    const OpenBlasThreadControl& blas = openblas_thread_control();
    if (blas.set == nullptr) return;
    const std::lock_guard<std::mutex> lock(mutex());
    State& s = state();
    if (--s.holders == 0 && s.saved != 1) blas.set(s.saved);
  }
  SingleThreadedBlas(const SingleThreadedBlas&) = delete;
  SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;

 private:
  struct State {
    int holders = 0;
    int saved = 1;
  };
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  static State& state() {
    static State s;
    return s;
  }
};

// Speed. CHOLMOD's supernodal factorisation clears and fills its workspace and each supernode in
// OpenMP loops whose thread count is fixed when CHOLMOD is built (num_threads(4) in Debian's
// build), whatever the machine has and whatever OMP_NUM_THREADS says. On two cores, four threads
// woken and put to sleep around every supernode of more than 1024 values cost more than the
// factorisation itself: a 4.6k-vertex Laplacian took 8.6-13 ms to factorise, 3.9-5.5 ms with
// those loops on one thread; a 134k-vertex one 470 -> 235 ms. The loops only write disjoint
// entries (no sums), so the factor is the same bit for bit on any number of threads.
//
// With max-active-levels at 0 in the calling thread, every parallel region it opens runs on that
// thread alone (the OpenMP ICV belongs to the calling thread's data environment, so other threads
// of the process keep theirs). The runtime's entry points are looked up where CHOLMOD loaded them.
using SetMaxActiveLevels = void (*)(int);
using GetMaxActiveLevels = int (*)();

using OpenMpLevelsControl = LoadedControl<SetMaxActiveLevels, GetMaxActiveLevels>;

const OpenMpLevelsControl& openmp_levels_control() {
  static const OpenMpLevelsControl control = find_control<SetMaxActiveLevels, GetMaxActiveLevels>(
      "omp_set_max_active_levels", "omp_get_max_active_levels");
  return control;
}

/// Runs the OpenMP regions the calling thread opens while alive on that thread alone, and
/// restores its max-active-levels afterwards.
class SerialOpenMp {
 public:
  SerialOpenMp() {
    const OpenMpLevelsControl& omp = openmp_levels_control();
    if (omp.set == nullptr) return;
    saved_ = omp.get();
    if (saved_ != 0) omp.set(0);
  }
  ~SerialOpenMp() {
    const OpenMpLevelsControl& omp = openmp_levels_control();
    if (omp.set != nullptr && saved_ != 0) omp.set(saved_);
  }
  SerialOpenMp(const SerialOpenMp&) = delete;
  SerialOpenMp& operator=(const SerialOpenMp&) = delete;

 private:
  int saved_ = 0;
};
#else
// Without CHOLMOD (Eigen's own solver) or off Linux: nothing to pin.
class SingleThreadedBlas {};
class SerialOpenMp {};
#endif

}  // namespace

#ifdef RICCI_HAVE_CHOLMOD
namespace {

/// CHOLMOD's supernodal L L^T of a matrix's lower triangle, through the entry points loaded by
/// cholmod_library.hpp (the settings Eigen's CholmodSupernodalLLT uses, so the factor is the one
/// it made: final_asis, supernodal).
class CholmodFactorisation {
 public:
  explicit CholmodFactorisation(const cholmod_detail::Library& library) : lib_(&library) {
    lib_->start(&common_);
    common_.final_asis = 1;
    common_.supernodal = CHOLMOD_SUPERNODAL;
    common_.print = 0;  // the library never prints: CHOLMOD's status is read here
  }
  ~CholmodFactorisation() {
    if (factor_ != nullptr) lib_->free_factor(&factor_, &common_);
    lib_->finish(&common_);
  }
  CholmodFactorisation(const CholmodFactorisation&) = delete;
  CholmodFactorisation& operator=(const CholmodFactorisation&) = delete;

  bool analyze(const Eigen::SparseMatrix<double>& A) {
    if (factor_ != nullptr) lib_->free_factor(&factor_, &common_);
    cholmod_sparse view = lower_view(A);
    factor_ = lib_->analyze(&view, &common_);
    return factor_ != nullptr;
  }
  /// False when A is not positive definite (or CHOLMOD failed).
  bool factorize(const Eigen::SparseMatrix<double>& A) {
    cholmod_sparse view = lower_view(A);
    double beta[2] = {0, 0};
    const int ok = lib_->factorize_p(&view, beta, nullptr, 0, factor_, &common_);
    return ok != 0 && factor_->minor == factor_->n;
  }
  /// Whether this CHOLMOD has its Modify module (update_diagonal).
  bool can_update() const { return lib_->updown != nullptr && lib_->change_factor != nullptr; }
  /// The factor of A + diag(d), d given at `changes` (SparseCholesky::update_diagonal): the
  /// updates first, so that the matrix stays positive definite through the downdates. False
  /// when CHOLMOD fails (the factor is then not to be used).
  bool update_diagonal(const std::vector<std::pair<int, double>>& changes) {
    if (!can_update() || factor_ == nullptr || factor_->xtype != CHOLMOD_REAL ||
        factor_->itype != CHOLMOD_INT) {
      return false;
    }
    const int n = static_cast<int>(factor_->n);
    for (const auto& [index, d] : changes) {
      if (index < 0 || index >= n || !std::isfinite(d)) return false;  // (the factor untouched)
    }
    // (A supernodal L L^T becomes a simplicial LDL^T, the kind CHOLMOD modifies.)
    if ((factor_->is_super || factor_->is_ll) &&
        lib_->change_factor(CHOLMOD_REAL, /*to_ll=*/0, /*to_super=*/0, /*to_packed=*/0,
                            /*to_monotonic=*/0, factor_, &common_) == 0) {
      return false;
    }
    // C's rows are L's, the permuted ones: row k of L is row Perm[k] of A.
    const int* perm = static_cast<const int*>(factor_->Perm);
    std::vector<int> row_of(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) row_of[static_cast<std::size_t>(perm == nullptr ? k : perm[k])] = k;
    for (const bool update : {true, false}) {
      // One column sqrt|d_i| e_i a change: a sparse n x m matrix, one entry a column.
      std::vector<int> p{0}, rows;
      std::vector<double> values;
      for (const auto& [index, d] : changes) {
        if (d == 0 || (d > 0) != update) continue;
        rows.push_back(row_of[static_cast<std::size_t>(index)]);
        values.push_back(std::sqrt(std::abs(d)));
        p.push_back(static_cast<int>(rows.size()));
      }
      if (rows.empty()) continue;
      cholmod_sparse c{};
      c.nrow = static_cast<std::size_t>(n);
      c.ncol = rows.size();
      c.nzmax = rows.size();
      c.p = p.data();
      c.i = rows.data();
      c.x = values.data();
      c.stype = 0;
      c.itype = CHOLMOD_INT;
      c.xtype = CHOLMOD_REAL;
      c.dtype = CHOLMOD_DOUBLE;
      c.sorted = 1;
      c.packed = 1;
      if (lib_->updown(update ? 1 : 0, &c, factor_, &common_) == 0 ||
          factor_->minor != factor_->n || factor_->xtype != CHOLMOD_REAL) {
        return false;
      }
    }
    // CHOLMOD's LDL^T takes a negative D as it comes: a downdate too large shows there.
    const int* column_start = static_cast<const int*>(factor_->p);
    const double* values = static_cast<const double*>(factor_->x);
    for (int j = 0; j < n; ++j) {
      if (!(values[column_start[j]] > 0)) return false;
    }
    return true;
  }

  /// A X = B (column-major B); throws SolverError when CHOLMOD fails.
  Eigen::MatrixXd solve(const Eigen::Ref<const Eigen::MatrixXd>& B) const {
    cholmod_dense b;
    b.nrow = static_cast<std::size_t>(B.rows());
    b.ncol = static_cast<std::size_t>(B.cols());
    b.nzmax = b.nrow * b.ncol;
    b.d = static_cast<std::size_t>(B.outerStride());
    b.x = const_cast<double*>(B.data());  // read only: CHOLMOD_A solves into a new matrix
    b.z = nullptr;
    b.xtype = CHOLMOD_REAL;
    b.dtype = CHOLMOD_DOUBLE;
    cholmod_dense* x = lib_->solve(CHOLMOD_A, factor_, &b, &common_);
    if (x == nullptr) throw SolverError("SparseCholesky: CHOLMOD's solve failed");
    Eigen::MatrixXd out =
        Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(x->x), B.rows(), B.cols());
    lib_->free_dense(&x, &common_);
    return out;
  }

  /// The factor as supernodal::solve reads it, or none when CHOLMOD did not leave a supernodal
  /// L L^T with int indices.
  std::optional<supernodal::Factor> factor() const {
    const cholmod_factor* L = factor_;
    if (L == nullptr || !L->is_super || !L->is_ll || L->xtype != CHOLMOD_REAL ||
        L->itype != CHOLMOD_INT || L->dtype != CHOLMOD_DOUBLE || L->x == nullptr) {
      return std::nullopt;
    }
    supernodal::Factor f;
    f.n = static_cast<int>(L->n);
    f.num_super = static_cast<int>(L->nsuper);
    f.super = static_cast<const int*>(L->super);
    f.pi = static_cast<const int*>(L->pi);
    f.px = static_cast<const int*>(L->px);
    f.s_index = static_cast<const int*>(L->s);
    f.perm = static_cast<const int*>(L->Perm);
    f.values = static_cast<const double*>(L->x);
    return f;
  }

 private:
  /// A's lower triangle as CHOLMOD reads it (stype -1), borrowed.
  static cholmod_sparse lower_view(const Eigen::SparseMatrix<double>& A) {
    cholmod_sparse v;
    v.nrow = static_cast<std::size_t>(A.rows());
    v.ncol = static_cast<std::size_t>(A.cols());
    v.nzmax = static_cast<std::size_t>(A.nonZeros());
    v.p = const_cast<int*>(A.outerIndexPtr());
    v.i = const_cast<int*>(A.innerIndexPtr());
    v.nz = A.isCompressed() ? nullptr : const_cast<int*>(A.innerNonZeroPtr());
    v.x = const_cast<double*>(A.valuePtr());
    v.z = nullptr;
    v.stype = -1;
    v.itype = CHOLMOD_INT;
    v.xtype = CHOLMOD_REAL;
    v.dtype = CHOLMOD_DOUBLE;
    v.sorted = 1;
    v.packed = A.isCompressed() ? 1 : 0;
    return v;
  }

  const cholmod_detail::Library* lib_;
  // CHOLMOD's solves write into the common workspace: callers hold Impl::solve_mutex.
  mutable cholmod_common common_{};
  cholmod_factor* factor_ = nullptr;
};

/// Factors of at least this many values solve on two threads (supernodal_split.hpp), and their
/// approximate solves in single precision. 2e6 while the second thread was started for each
/// solve (40-50 us); with a helper at hand (numerics/detail/helper_threads.hpp), param with 4
/// cones ran 1.09x as fast on bunny (a factor of 5.2e5 values), 1.06x on camelhead (3.8e5) and
/// 1.10x on face (7.1e5), paired.
constexpr double kSplitSolveValues = 2e5;

}  // namespace
#endif

namespace {

/// Eigen's simplicial factor is factorised and solved on two threads from this many values of
/// L (simplicial_split.hpp; spot, 2.9k vertices: 60k values, a solve 0.093 -> 0.061 ms; eight's
/// 4k values solve in 6 us, too little to hand half to another thread).
constexpr double kSplitSimplicialValues = 32768;

}  // namespace

struct SparseCholesky::Impl {
  CholeskyBackend requested = CholeskyBackend::Automatic;
  /// The backend of the current analysis (decided by analyze()).
  bool use_cholmod = false;
  bool analyzed = false;
  /// A factorisation of the analysed pattern is in hand (or one modified from it).
  bool factorised = false;
  /// update_diagonal changed the factor (a simplicial one now): the next factorisation
  /// analyses afresh.
  bool modified = false;
  /// Eigen's factor, factorised and solved on two threads where its tree splits.
  simplicial::SplitLdlt eigen;
#ifdef RICCI_HAVE_CHOLMOD
  /// Made at the first analysis that takes CHOLMOD (which loads it).
  std::unique_ptr<CholmodFactorisation> cholmod;
  /// CHOLMOD's solves write into its common workspace: one at a time (the split solve reads the
  /// factor only and needs none).
  mutable std::mutex solve_mutex;
  /// The factor's split for solves on two threads (from its structure: made at the first
  /// factorisation after an analysis), and whether it was looked for.
  std::optional<supernodal::Split> split;
  bool split_checked = false;
  /// The factor's values in single precision for solve_approximately, made at its first call
  /// after each factorisation (solves may run on several threads at once).
  mutable std::mutex single_mutex;
  mutable std::shared_ptr<const std::vector<float>> single;
#endif
};

namespace {

#ifdef RICCI_HAVE_CHOLMOD
/// Whether release_blas_threads() was asked for before CHOLMOD (and its OpenBLAS) was loaded:
/// then it runs right after the load, since OpenBLAS starts its threads as it loads.
std::atomic<bool> g_release_blas_threads_on_load{false};

/// CHOLMOD's functions, loading the library at the first call (and releasing OpenBLAS's threads
/// then when the command line asked for it); nullptr when it cannot be loaded.
const cholmod_detail::Library* cholmod_functions() {
  const bool was_loaded = cholmod_detail::loaded();
  const cholmod_detail::Library* library = cholmod_detail::library();
  if (library != nullptr && !was_loaded && g_release_blas_threads_on_load.exchange(false)) {
    SparseCholesky::release_blas_threads();
  }
  return library;
}
#endif

}  // namespace

SparseCholesky::SparseCholesky(CholeskyBackend backend) : impl_(std::make_unique<Impl>()) {
  impl_->requested = backend;
}
SparseCholesky::SparseCholesky(bool use_cholmod)
    : SparseCholesky(use_cholmod ? CholeskyBackend::Automatic : CholeskyBackend::Eigen) {}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

bool SparseCholesky::cholmod_available() {
#ifdef RICCI_HAVE_CHOLMOD
  return cholmod_functions() != nullptr;
#else
  return false;
#endif
}

bool SparseCholesky::cholmod_loaded() {
#ifdef RICCI_HAVE_CHOLMOD
  return cholmod_detail::loaded();
#else
  return false;
#endif
}

bool SparseCholesky::blas_threads_pinned() {
#ifdef RICCI_PIN_BLAS_THREADS
  return cholmod_detail::loaded() && openblas_thread_control().set != nullptr;
#else
  return false;
#endif
}

bool SparseCholesky::release_blas_threads() {
#ifdef RICCI_PIN_BLAS_THREADS
  if (!cholmod_detail::loaded()) {
    // Nothing loaded yet: OpenBLAS's threads start when CHOLMOD loads; stop them then.
    g_release_blas_threads_on_load.store(true);
    return false;
  }
  const OpenBlasThreadControl& blas = openblas_thread_control();
  if (blas.set == nullptr) return false;
  // One thread first: stopped workers are started again by openblas_set_num_threads with more
  // than one (SingleThreadedBlas's restore would do it mid-run, and they would spin again).
  const bool had_threads = blas.get() > 1;
  blas.set(1);
  if (blas.stop == nullptr || !had_threads) return false;
  blas.stop();
  return true;
#else
  return false;
#endif
}

const char* SparseCholesky::backend() const {
  return impl_->use_cholmod ? "cholmod-supernodal" : "eigen-simplicial-ldlt";
}

bool SparseCholesky::analyzed() const {
  return impl_->analyzed;
}

bool SparseCholesky::solves_on_two_threads() const {
#ifdef RICCI_HAVE_CHOLMOD
  return impl_->use_cholmod && impl_->split.has_value();
#else
  return false;
#endif
}

bool SparseCholesky::automatic_takes_cholmod(Eigen::Index rows, Eigen::Index nonzeros) {
  return rows >= kCholmodMinRows ||
         (rows >= kCholmodDenseMinRows && nonzeros > kCholmodDenseRowNonzeros * rows);
}

void SparseCholesky::analyze(const Eigen::SparseMatrix<double>& A) {
  impl_->analyzed = false;
  impl_->factorised = false;
  impl_->modified = false;
#ifdef RICCI_HAVE_CHOLMOD
  const CholeskyBackend wanted = impl_->requested;
  const cholmod_detail::Library* library =
      wanted == CholeskyBackend::Cholmod || (wanted == CholeskyBackend::Automatic &&
                                             automatic_takes_cholmod(A.rows(), A.nonZeros()))
          ? cholmod_functions()
          : nullptr;
  impl_->use_cholmod = library != nullptr;
  if (impl_->use_cholmod) {
    if (!impl_->cholmod) impl_->cholmod = std::make_unique<CholmodFactorisation>(*library);
    bool ok = false;
    {
      [[maybe_unused]] const SerialOpenMp serial_loops;
      ok = impl_->cholmod->analyze(A);
    }
    impl_->split.reset();
    impl_->split_checked = false;
    if (!ok) throw SolverError("SparseCholesky::analyze: CHOLMOD's symbolic analysis failed");
    impl_->analyzed = true;
    return;
  }
#endif
  impl_->eigen.analyze_split(A, kSplitSimplicialValues);
  if (impl_->eigen.info() != Eigen::Success) {
    throw SolverError("SparseCholesky::analyze: symbolic analysis failed");
  }
  impl_->analyzed = true;
}

bool SparseCholesky::update_diagonal(const std::vector<std::pair<int, double>>& changes) {
#ifdef RICCI_HAVE_CHOLMOD
  if (!impl_->analyzed || !impl_->use_cholmod || !impl_->factorised ||
      !impl_->cholmod->can_update()) {
    return false;  // (the factor stays the last factorisation's)
  }
  bool ok = false;
  {
    const std::lock_guard<std::mutex> one_call(impl_->solve_mutex);  // (CHOLMOD's workspace)
    ok = impl_->cholmod->update_diagonal(changes);
  }
  {
    const std::lock_guard<std::mutex> lock(impl_->single_mutex);
    impl_->single.reset();
  }
  // The factor is simplicial now (or lost): no split solves, and the next factorisation analyses
  // afresh, for CHOLMOD's supernodes again.
  impl_->split.reset();
  impl_->modified = true;
  impl_->factorised = ok;
  return ok;
#else
  (void)changes;
  return false;
#endif
}

void SparseCholesky::factorize(const Eigen::SparseMatrix<double>& A) {
  if (!impl_->analyzed || impl_->modified) analyze(A);
  impl_->factorised = false;
#ifdef RICCI_HAVE_CHOLMOD
  if (impl_->use_cholmod) {
    bool ok = false;
    {
      [[maybe_unused]] const SingleThreadedBlas one_thread;
      [[maybe_unused]] const SerialOpenMp serial_loops;
      ok = impl_->cholmod->factorize(A);
    }
    {
      const std::lock_guard<std::mutex> lock(impl_->single_mutex);
      impl_->single.reset();
    }
    if (!ok) {
      throw SolverError(
          "SparseCholesky::factorize: the matrix is not positive definite "
          "(CHOLMOD's numeric factorisation failed)");
    }
    if (!impl_->split_checked) {
      const std::optional<supernodal::Factor> factor = impl_->cholmod->factor();
      if (factor) impl_->split = supernodal::split_factor(*factor, kSplitSolveValues);
      impl_->split_checked = true;
    }
    impl_->factorised = true;
    return;
  }
#endif
  impl_->eigen.factorize_split(A);
  if (impl_->eigen.info() != Eigen::Success || (impl_->eigen.vectorD().array() <= 0).any()) {
    throw SolverError("SparseCholesky::factorize: the matrix is not positive definite");
  }
  impl_->factorised = true;
}

namespace {

/// A X = B with the last factorisation, B one column or several (Impl: SparseCholesky::Impl).
template <class Impl, class Dense>
Dense solve_dense(const Impl& impl, const Dense& b) {
#ifdef RICCI_HAVE_CHOLMOD
  if (impl.use_cholmod) {
    const std::lock_guard<std::mutex> one_solve(impl.solve_mutex);
    [[maybe_unused]] const SingleThreadedBlas one_thread;
    [[maybe_unused]] const SerialOpenMp serial_loops;
    return impl.cholmod->solve(b);
  }
#endif
  if constexpr (Dense::ColsAtCompileTime == 1) {
    return impl.eigen.solve_split(b);
  } else {
    return impl.eigen.solve(b);
  }
}

}  // namespace

Eigen::VectorXd SparseCholesky::solve(const Eigen::VectorXd& b) const {
#ifdef RICCI_HAVE_CHOLMOD
  if (impl_->use_cholmod && impl_->split) {
    const std::optional<supernodal::Factor> factor = impl_->cholmod->factor();
    if (factor && b.size() == factor->n) return supernodal::solve(*factor, *impl_->split, b);
  }
#endif
  return solve_dense(*impl_, b);
}

Eigen::VectorXd SparseCholesky::solve_approximately(const Eigen::VectorXd& b) const {
#ifdef RICCI_HAVE_CHOLMOD
  if (impl_->use_cholmod && impl_->split) {
    const std::optional<supernodal::Factor> factor = impl_->cholmod->factor();
    if (factor && b.size() == factor->n) {
      std::shared_ptr<const std::vector<float>> single;
      {
        const std::lock_guard<std::mutex> lock(impl_->single_mutex);
        if (!impl_->single) {
          impl_->single =
              std::make_shared<const std::vector<float>>(supernodal::single_values(*factor));
        }
        single = impl_->single;
      }
      return supernodal::solve_single(*factor, *single, *impl_->split, b);
    }
  }
#endif
  return solve(b);
}

Eigen::MatrixXd SparseCholesky::solve_columns(const Eigen::MatrixXd& B) const {
  // (A small factor's solves take microseconds: not worth a second thread.)
  constexpr Eigen::Index kSplitColumnsMinRows = 2000;
  if (impl_->use_cholmod || B.cols() < 2 || B.rows() < kSplitColumnsMinRows) {
    return solve_dense(*impl_, B);
  }
  // Eigen's solver substitutes one column after the other: the columns split across threads
  // give the same bits (spot's first cone, 8 candidates: 2 ms of a 45 ms run on one thread).
  Eigen::MatrixXd X(B.rows(), B.cols());
  parallel::for_chunks(
      B.cols(),
      [&](std::int64_t begin, std::int64_t end, int) {
        X.middleCols(begin, end - begin) = impl_->eigen.solve(B.middleCols(begin, end - begin));
      },
      1);
  return X;
}

}  // namespace ricci
