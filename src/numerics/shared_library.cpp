#include "numerics/detail/shared_library.hpp"

namespace ricci::shared_library {

void* open(std::initializer_list<const char*> files, int flags, std::string& error) {
  error = "not found";
  for (const char* file : files) {
    if (void* handle = dlopen(file, flags)) return handle;
    const char* why = dlerror();
    if (why != nullptr) error = why;
  }
  return nullptr;
}

}  // namespace ricci::shared_library
