# Installation and the CMake package config, so that another project can write
#
#   find_package(ricci REQUIRED)
#   target_link_libraries(app PRIVATE ricci::ricci)
#
# `cmake --install build --prefix P` puts in place:
#   P/lib/libricci.a                  the library (target ricci_lib, exported as ricci::ricci)
#   P/include/ricci/...               its headers
#   P/bin/ricci                       the command line
#   P/lib/cmake/ricci/ricciConfig.cmake, ricciConfigVersion.cmake, ricciTargets*.cmake
#
# Included at the end of the top-level CMakeLists.txt, so every target exists here.
# The picture library (ricci_render) and the Python module (_ricci) install themselves.

include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(RICCI_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/ricci"
    CACHE STRING "Where the CMake package config of ricci is installed (relative to the prefix)")
mark_as_advanced(RICCI_INSTALL_CMAKEDIR)

# Consumers see the library as ricci::ricci, as in-tree code does through the alias, and get
# C++20 from it (the public headers need it). INTERFACE only: ricci_lib's own build is unchanged.
set_target_properties(ricci_lib PROPERTIES EXPORT_NAME ricci)
target_compile_features(ricci_lib INTERFACE cxx_std_20)

# Where CHOLMOD is loaded on demand (RICCI_CHOLMOD_ON_DEMAND, every platform with dlopen) consumers
# link nothing of it. Otherwise:
# ricci_lib is static and links CHOLMOD privately, so its consumers must link CHOLMOD too: CMake
# records the build machine's path in INTERFACE_LINK_LIBRARIES (plain, as it is a path and not a
# target; $<LINK_ONLY:...> for a target). In the installed package that entry is replaced by
# ricci::cholmod, a target which ricciConfig.cmake defines after finding libcholmod again on the
# machine that uses the package. The build tree keeps the entry as it was.
set(RICCI_CONFIG_LINKS_CHOLMOD OFF)
if(RICCI_HAVE_CHOLMOD AND NOT RICCI_CHOLMOD_ON_DEMAND)
  set(RICCI_CONFIG_LINKS_CHOLMOD ON)
  get_target_property(_ricci_interface_libs ricci_lib INTERFACE_LINK_LIBRARIES)
  set(_ricci_cholmod_index -1)
  foreach(_ricci_entry "${CHOLMOD_LIBRARY}" "$<LINK_ONLY:${CHOLMOD_LIBRARY}>")
    if(_ricci_cholmod_index EQUAL -1)
      list(FIND _ricci_interface_libs "${_ricci_entry}" _ricci_cholmod_index)
      set(_ricci_cholmod_entry "${_ricci_entry}")
    endif()
  endforeach()
  if(_ricci_cholmod_index EQUAL -1)
    message(WARNING "ricci: install: CHOLMOD (${CHOLMOD_LIBRARY}) is not among the link "
                    "dependencies of ricci_lib; the installed package will not link it")
  else()
    list(REMOVE_AT _ricci_interface_libs ${_ricci_cholmod_index})
    list(INSERT _ricci_interface_libs ${_ricci_cholmod_index}
         "$<BUILD_INTERFACE:${_ricci_cholmod_entry}>"
         "$<INSTALL_INTERFACE:$<LINK_ONLY:ricci::cholmod>>")
    set_property(TARGET ricci_lib PROPERTY INTERFACE_LINK_LIBRARIES "${_ricci_interface_libs}")
  endif()
  # The config searches the build machine's directory too, after the usual places.
  get_filename_component(RICCI_CHOLMOD_LIBRARY_DIR "${CHOLMOD_LIBRARY}" DIRECTORY)
  unset(_ricci_interface_libs)
  unset(_ricci_entry)
  unset(_ricci_cholmod_entry)
  unset(_ricci_cholmod_index)
else()
  set(RICCI_CHOLMOD_LIBRARY_DIR "")
endif()

install(TARGETS ricci_lib
  EXPORT ricciTargets
  ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
  LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}"
  RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")

install(TARGETS ricci RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")

# The headers of the core library. include/ricci/render belongs to ricci_render, which is not
# part of this export set; its owner installs those headers together with that library.
install(DIRECTORY "${PROJECT_SOURCE_DIR}/include/ricci"
  DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}"
  FILES_MATCHING
    PATTERN "*.hpp"
    PATTERN "*.h"
    PATTERN "render" EXCLUDE)

install(EXPORT ricciTargets
  NAMESPACE ricci::
  FILE ricciTargets.cmake
  DESTINATION "${RICCI_INSTALL_CMAKEDIR}")

configure_package_config_file(
  "${CMAKE_CURRENT_LIST_DIR}/ricciConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/ricciConfig.cmake"
  INSTALL_DESTINATION "${RICCI_INSTALL_CMAKEDIR}")

# Before 1.0 a minor release may break the API: accept the same major.minor only.
write_basic_package_version_file(
  "${PROJECT_BINARY_DIR}/ricciConfigVersion.cmake"
  VERSION "${PROJECT_VERSION}"
  COMPATIBILITY SameMinorVersion)

install(FILES
  "${PROJECT_BINARY_DIR}/ricciConfig.cmake"
  "${PROJECT_BINARY_DIR}/ricciConfigVersion.cmake"
  DESTINATION "${RICCI_INSTALL_CMAKEDIR}")
