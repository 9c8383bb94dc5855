#include "ricci/version.hpp"

#ifndef RICCI_VERSION
#error "RICCI_VERSION is defined by CMakeLists.txt"
#endif

namespace ricci {

const char* version() {
  return RICCI_VERSION;
}

}  // namespace ricci
