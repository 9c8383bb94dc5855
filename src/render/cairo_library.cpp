#include "render/detail/cairo_library.hpp"

#include <dlfcn.h>

#include <mutex>
#include <string>

#include "ricci/errors.hpp"

namespace ricci::render_detail {

namespace {

template <class Function>
Function find(void* handle, const char* name) {
  return reinterpret_cast<Function>(dlsym(handle, name));
}

/// Opens Cairo; the error, when it cannot, in `error`.
CairoLibrary open_cairo(std::string& error) {
  // The soname first (the library the system has now), then the file CMake found at build time.
  void* handle = dlopen(RICCI_CAIRO_SONAME, RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) handle = dlopen(RICCI_CAIRO_PATH, RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* why = dlerror();
    error = std::string("pictures need Cairo, which cannot be opened (") + RICCI_CAIRO_SONAME +
            "): " + (why != nullptr ? why : "not found") + "; install it (apt install libcairo2)";
    return {};
  }
  CairoLibrary l;
#define RICCI_CAIRO_FIND(name)                                                     \
  l.name = find<decltype(&cairo_##name)>(handle, "cairo_" #name);                  \
  if (l.name == nullptr) {                                                         \
    error = std::string("Cairo (") + RICCI_CAIRO_SONAME + ") has no cairo_" #name; \
    return {};                                                                     \
  }
  RICCI_CAIRO_FUNCTIONS(RICCI_CAIRO_FIND)
#undef RICCI_CAIRO_FIND
  return l;  // the handle stays open for the process's lifetime
}

}  // namespace

const CairoLibrary& cairo_api() {
  static std::once_flag once;
  static CairoLibrary library;
  static std::string error;
  std::call_once(once, [] { library = open_cairo(error); });
  if (library.create == nullptr) throw IoError(error);
  return library;
}

}  // namespace ricci::render_detail
