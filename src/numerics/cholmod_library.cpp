#include "numerics/detail/cholmod_library.hpp"

#include <atomic>
#include <mutex>

#ifndef RICCI_CHOLMOD_LINKED
#include <string>

#include "numerics/detail/shared_library.hpp"
#endif

namespace ricci::cholmod_detail {

namespace {

std::atomic<bool> g_loaded{false};

#ifdef RICCI_CHOLMOD_LINKED
Library load_library() {
  return {&cholmod_start,       &cholmod_finish,        &cholmod_analyze,
          &cholmod_factorize_p, &cholmod_solve,         &cholmod_free_factor,
          &cholmod_free_dense,  &cholmod_change_factor, &cholmod_updown};
}
#else
Library load_library() {
  // RTLD_GLOBAL: OpenBLAS's and OpenMP's controls (sparse_cholesky.cpp) and whoever else in the
  // process asks for them find them by name. RTLD_DEEPBIND (above) is left out under the
  // sanitizers, whose runtime must interpose malloc for every library.
  int flags = RTLD_NOW | RTLD_GLOBAL;
#if defined(RTLD_DEEPBIND) && !defined(RICCI_CHOLMOD_NO_DEEPBIND)
  flags |= RTLD_DEEPBIND;
#endif
  // The soname first (the library the system has now), then the file CMake found at build time.
  std::string error;  // no CHOLMOD: Eigen's solver, nothing to report
  void* handle = shared_library::open({RICCI_CHOLMOD_SONAME, RICCI_CHOLMOD_PATH}, flags, error);
  if (handle == nullptr) return {};
  using shared_library::find;
  Library l;
  const bool all = find(handle, "cholmod_start", l.start) &&
                   find(handle, "cholmod_finish", l.finish) &&
                   find(handle, "cholmod_analyze", l.analyze) &&
                   find(handle, "cholmod_factorize_p", l.factorize_p) &&
                   find(handle, "cholmod_solve", l.solve) &&
                   find(handle, "cholmod_free_factor", l.free_factor) &&
                   find(handle, "cholmod_free_dense", l.free_dense);
  // Optional: a CHOLMOD built without its GPL Modify module (NGPL) has no updates, and must still
  // factorise (SparseCholesky::update_diagonal then says no).
  if (all && !(find(handle, "cholmod_change_factor", l.change_factor) &&
               find(handle, "cholmod_updown", l.updown))) {
    l.change_factor = nullptr;
    l.updown = nullptr;
  }
  // Kept loaded for the process's lifetime either way (factors may outlive any owner here).
  return all ? l : Library{};
}
#endif

}  // namespace

const Library* library() {
  static std::once_flag once;
  static Library functions;
  std::call_once(once, [] {
    functions = load_library();
    g_loaded.store(functions.start != nullptr, std::memory_order_release);
  });
  return functions.start != nullptr ? &functions : nullptr;
}

bool loaded() {
  return g_loaded.load(std::memory_order_acquire);
}

}  // namespace ricci::cholmod_detail
