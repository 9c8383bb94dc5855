#include "render/detail/cairo_library.hpp"

#include <mutex>
#include <string>

#include "numerics/detail/shared_library.hpp"
#include "ricci/errors.hpp"

namespace ricci::render_detail {

namespace {

/// Opens Cairo; the error, when it cannot, in `error`.
CairoLibrary open_cairo(std::string& error) {
  // The soname first (the library the system has now), then the file CMake found at build time.
  std::string why;
  void* handle =
      shared_library::open({RICCI_CAIRO_SONAME, RICCI_CAIRO_PATH}, RTLD_NOW | RTLD_LOCAL, why);
  if (handle == nullptr) {
    error = std::string("pictures need Cairo, which cannot be opened (") + RICCI_CAIRO_SONAME +
            "): " + why + "; install it (apt install libcairo2)";
    return {};
  }
  CairoLibrary l;
#define RICCI_CAIRO_FIND(name)                                                     \
  if (!shared_library::find(handle, "cairo_" #name, l.name)) {                     \
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
