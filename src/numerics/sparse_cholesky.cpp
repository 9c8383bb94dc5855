#include "ricci/numerics/sparse_cholesky.hpp"

#include <Eigen/SparseCholesky>

#ifdef RICCI_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>

#include <memory>
#include <mutex>
#include <optional>

#include "numerics/detail/supernodal_split.hpp"
#endif

#include "ricci/errors.hpp"

#if defined(RICCI_HAVE_CHOLMOD) && defined(__linux__)
#include <dlfcn.h>
#include <link.h>

#include <string>
#include <vector>
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

/// Eigen's wrapper, with its factor in view (for the solves on two threads).
class CholmodLLT : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> {
 public:
  /// The factor as supernodal::solve reads it, or none when CHOLMOD did not leave a supernodal
  /// L L^T with int indices.
  std::optional<supernodal::Factor> factor() const {
    const cholmod_factor* L = m_cholmodFactor;
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
};

/// Factors of at least this many values solve on two threads (supernodal_split.hpp: below it a
/// solve sits in the cache and a second thread gains nothing).
constexpr double kSplitSolveValues = 2e6;

}  // namespace
#endif

struct SparseCholesky::Impl {
  bool use_cholmod = false;
  bool analyzed = false;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> eigen;
#ifdef RICCI_HAVE_CHOLMOD
  CholmodLLT cholmod;
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

SparseCholesky::SparseCholesky(bool use_cholmod) : impl_(std::make_unique<Impl>()) {
  impl_->use_cholmod = use_cholmod && cholmod_available();
#ifdef RICCI_HAVE_CHOLMOD
  // The library never prints: CHOLMOD reports through info(), not on stderr.
  impl_->cholmod.cholmod().print = 0;
#endif
}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

bool SparseCholesky::cholmod_available() {
#ifdef RICCI_HAVE_CHOLMOD
  return true;
#else
  return false;
#endif
}

bool SparseCholesky::blas_threads_pinned() {
#ifdef RICCI_PIN_BLAS_THREADS
  return openblas_thread_control().set != nullptr;
#else
  return false;
#endif
}

bool SparseCholesky::release_blas_threads() {
#ifdef RICCI_PIN_BLAS_THREADS
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

void SparseCholesky::analyze(const Eigen::SparseMatrix<double>& A) {
#ifdef RICCI_HAVE_CHOLMOD
  if (impl_->use_cholmod) {
    {
      [[maybe_unused]] const SerialOpenMp serial_loops;
      impl_->cholmod.analyzePattern(A);
    }
    impl_->split.reset();
    impl_->split_checked = false;
    if (impl_->cholmod.info() != Eigen::Success) {
      throw SolverError("SparseCholesky::analyze: CHOLMOD's symbolic analysis failed");
    }
    impl_->analyzed = true;
    return;
  }
#endif
  impl_->eigen.analyzePattern(A);
  if (impl_->eigen.info() != Eigen::Success) {
    throw SolverError("SparseCholesky::analyze: symbolic analysis failed");
  }
  impl_->analyzed = true;
}

void SparseCholesky::factorize(const Eigen::SparseMatrix<double>& A) {
  if (!impl_->analyzed) analyze(A);
#ifdef RICCI_HAVE_CHOLMOD
  if (impl_->use_cholmod) {
    {
      [[maybe_unused]] const SingleThreadedBlas one_thread;
      [[maybe_unused]] const SerialOpenMp serial_loops;
      impl_->cholmod.factorize(A);
    }
    {
      const std::lock_guard<std::mutex> lock(impl_->single_mutex);
      impl_->single.reset();
    }
    if (impl_->cholmod.info() != Eigen::Success) {
      throw SolverError(
          "SparseCholesky::factorize: the matrix is not positive definite "
          "(CHOLMOD's numeric factorisation failed)");
    }
    if (!impl_->split_checked) {
      const std::optional<supernodal::Factor> factor = impl_->cholmod.factor();
      if (factor) impl_->split = supernodal::split_factor(*factor, kSplitSolveValues);
      impl_->split_checked = true;
    }
    return;
  }
#endif
  impl_->eigen.factorize(A);
  if (impl_->eigen.info() != Eigen::Success || (impl_->eigen.vectorD().array() <= 0).any()) {
    throw SolverError("SparseCholesky::factorize: the matrix is not positive definite");
  }
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
    return impl.cholmod.solve(b);
  }
#endif
  return impl.eigen.solve(b);
}

}  // namespace

Eigen::VectorXd SparseCholesky::solve(const Eigen::VectorXd& b) const {
#ifdef RICCI_HAVE_CHOLMOD
  if (impl_->use_cholmod && impl_->split) {
    const std::optional<supernodal::Factor> factor = impl_->cholmod.factor();
    if (factor && b.size() == factor->n) return supernodal::solve(*factor, *impl_->split, b);
  }
#endif
  return solve_dense(*impl_, b);
}

Eigen::VectorXd SparseCholesky::solve_approximately(const Eigen::VectorXd& b) const {
#ifdef RICCI_HAVE_CHOLMOD
  if (impl_->use_cholmod && impl_->split) {
    const std::optional<supernodal::Factor> factor = impl_->cholmod.factor();
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
  return solve_dense(*impl_, B);
}

}  // namespace ricci
