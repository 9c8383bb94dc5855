#pragma once
/// \file
/// Internal: CHOLMOD's entry points, loaded when a factorisation first needs them.
///
/// Loading CHOLMOD with the program (its BLAS, LAPACK, OpenMP, METIS and Fortran runtimes: some
/// 15 libraries, OpenBLAS's 30 MB among them) took 3-5 ms of every run's start, more than a whole
/// flow on a mesh of a few thousand faces, whose factorisations Eigen's simplicial LDL^T does as
/// fast (src/numerics/sparse_cholesky.cpp has the figures). So ricci does not link CHOLMOD: the
/// first SparseCholesky that wants it loads it (dlopen, RTLD_DEEPBIND: its libraries resolve their
/// own symbols among themselves first, which spares OpenBLAS's 16000 self-references a walk
/// through every library of the process), and a machine without it gets Eigen's solver.
///
/// Where dlopen is missing (RICCI_CHOLMOD_LINKED) CHOLMOD is linked as usual and the table holds
/// its functions.

#include <cholmod.h>

namespace ricci::cholmod_detail {

/// The functions SparseCholesky calls (int indices, cholmod_common's defaults otherwise).
struct Library {
  decltype(&cholmod_start) start = nullptr;
  decltype(&cholmod_finish) finish = nullptr;
  decltype(&cholmod_analyze) analyze = nullptr;
  decltype(&cholmod_factorize_p) factorize_p = nullptr;
  decltype(&cholmod_solve) solve = nullptr;
  decltype(&cholmod_free_factor) free_factor = nullptr;
  decltype(&cholmod_free_dense) free_dense = nullptr;
  // The Modify module's, for rank-one updates: nullptr (both) where CHOLMOD was built without it.
  decltype(&cholmod_change_factor) change_factor = nullptr;
  decltype(&cholmod_updown) updown = nullptr;
};

/// CHOLMOD's functions, loaded at the first call (once per process, thread-safe); nullptr when
/// the library or one of them cannot be found.
const Library* library();

/// Whether library() has loaded CHOLMOD (does not try to).
bool loaded();

}  // namespace ricci::cholmod_detail
