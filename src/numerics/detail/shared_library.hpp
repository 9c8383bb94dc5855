#pragma once
/// \file
/// Internal: libraries opened at run time (dlopen) instead of linked, so that a run loads only
/// what it uses: CHOLMOD (numerics/detail/cholmod_library.hpp), Cairo
/// (render/detail/cairo_library.hpp), libzip (`ricci blender-addon`) and the MPI module
/// (`ricci batch` under mpirun). Each caller keeps its functions in a table of its own.

#include <dlfcn.h>

#include <initializer_list>
#include <string>

namespace ricci::shared_library {

/// The first of `files` (sonames or paths, tried in order) that dlopen opens with `flags`, kept
/// open for the process's lifetime; nullptr when none opens, with the loader's last message in
/// `error`.
void* open(std::initializer_list<const char*> files, int flags, std::string& error);

/// Sets `function` to the symbol `name` of `handle`; false when there is none.
template <class Function>
bool find(void* handle, const char* name, Function& function) {
  function = reinterpret_cast<Function>(dlsym(handle, name));
  return function != nullptr;
}

}  // namespace ricci::shared_library
