# The test install_and_find_package (cmake -P): installs the built project into a prefix inside
# the build tree, checks what landed there, then configures, builds and runs
# examples/find_package against that prefix with find_package(ricci).
#
# -D variables (tests/CMakeLists.txt passes them):
#   RICCI_SOURCE_DIR, RICCI_BINARY_DIR  the project's source and build trees
#   RICCI_WORK_DIR                      scratch directory: WORK/prefix, WORK/example-build
#   RICCI_CONFIG                        build type to install and to build the example with
#   RICCI_VERSION                       the project's version (checked against `ricci --version`)
#   RICCI_LIBDIR, RICCI_BINDIR, RICCI_INCLUDEDIR   GNUInstallDirs' relative directories
#   RICCI_LIB_NAME, RICCI_EXE_NAME      file names of the library and of the command (libricci.a)
#   RICCI_EXE_SUFFIX                    suffix of executables (empty but on Windows)
#   RICCI_GENERATOR, RICCI_MAKE_PROGRAM, RICCI_CXX_COMPILER, RICCI_EIGEN3_DIR  for the example

foreach(var RICCI_SOURCE_DIR RICCI_BINARY_DIR RICCI_WORK_DIR RICCI_VERSION RICCI_LIBDIR
            RICCI_BINDIR RICCI_INCLUDEDIR RICCI_GENERATOR RICCI_LIB_NAME RICCI_EXE_NAME)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "test_install.cmake: -D${var}=... is required")
  endif()
endforeach()
if(NOT RICCI_CONFIG)
  set(RICCI_CONFIG Release)
endif()

set(prefix "${RICCI_WORK_DIR}/prefix")
set(example_build "${RICCI_WORK_DIR}/example-build")
set(package_dir "${prefix}/${RICCI_LIBDIR}/cmake/ricci")

# Runs a command, fails the test with its output when it fails.
function(run_step what)
  execute_process(COMMAND ${ARGN}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${ARGN}\n--- stdout\n${out}\n--- stderr\n${err}")
  endif()
  message(STATUS "${what}: ok")
  set(step_output "${out}${err}" PARENT_SCOPE)
endfunction()

# Start clean, so that a stale install cannot hide a missing file.
file(REMOVE_RECURSE "${prefix}" "${example_build}")

# 1. Install.
run_step("install into ${prefix}"
  "${CMAKE_COMMAND}" --install "${RICCI_BINARY_DIR}" --prefix "${prefix}" --config "${RICCI_CONFIG}")

# 2. What must be there.
foreach(file
    "${RICCI_LIBDIR}/${RICCI_LIB_NAME}"
    "${RICCI_BINDIR}/${RICCI_EXE_NAME}"
    "${RICCI_INCLUDEDIR}/ricci/errors.hpp"
    "${RICCI_INCLUDEDIR}/ricci/mesh/mesh.hpp"
    "${RICCI_INCLUDEDIR}/ricci/flow/mesh_flow.hpp"
    "${RICCI_LIBDIR}/cmake/ricci/ricciConfig.cmake"
    "${RICCI_LIBDIR}/cmake/ricci/ricciConfigVersion.cmake"
    "${RICCI_LIBDIR}/cmake/ricci/ricciTargets.cmake")
  if(NOT EXISTS "${prefix}/${file}")
    message(FATAL_ERROR "not installed: ${prefix}/${file}")
  endif()
endforeach()

# The package must not point back into the source or build tree.
file(GLOB package_files "${package_dir}/*.cmake")
foreach(file IN LISTS package_files)
  file(READ "${file}" text)
  foreach(tree "${RICCI_SOURCE_DIR}" "${RICCI_BINARY_DIR}")
    string(FIND "${text}" "${tree}" at)
    if(NOT at EQUAL -1)
      message(FATAL_ERROR "${file} refers to ${tree}: the package is not relocatable")
    endif()
  endforeach()
endforeach()
# Link dependencies are targets (Eigen3::Eigen, ricci::cholmod) that ricciConfig.cmake finds on
# the consumer's machine, not library paths from the build machine.
file(READ "${package_dir}/ricciTargets.cmake" text)
if(text MATCHES "[\";]/[^\";]*\\.(so|a|dylib|lib)[\";]")
  message(FATAL_ERROR "ricciTargets.cmake links a library by its path on the build machine: "
                      "${CMAKE_MATCH_0}")
endif()
message(STATUS "installed files and package: ok")

# 3. The installed command runs.
run_step("installed ricci --version" "${prefix}/${RICCI_BINDIR}/${RICCI_EXE_NAME}" --version)
string(FIND "${step_output}" "${RICCI_VERSION}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "`ricci --version` printed '${step_output}', expected version ${RICCI_VERSION}")
endif()

# 4. Configure the example against the prefix only (no user package registry).
set(configure_args
  -S "${RICCI_SOURCE_DIR}/examples/find_package" -B "${example_build}"
  -G "${RICCI_GENERATOR}"
  "-DCMAKE_PREFIX_PATH=${prefix}"
  "-DCMAKE_BUILD_TYPE=${RICCI_CONFIG}"
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
if(RICCI_MAKE_PROGRAM)
  list(APPEND configure_args "-DCMAKE_MAKE_PROGRAM=${RICCI_MAKE_PROGRAM}")
endif()
if(RICCI_CXX_COMPILER)
  list(APPEND configure_args "-DCMAKE_CXX_COMPILER=${RICCI_CXX_COMPILER}")
endif()
if(RICCI_EIGEN3_DIR)
  list(APPEND configure_args "-DEigen3_DIR=${RICCI_EIGEN3_DIR}")
endif()
run_step("configure examples/find_package" "${CMAKE_COMMAND}" ${configure_args})

# It must have found this install, not another ricci on the machine.
file(STRINGS "${example_build}/CMakeCache.txt" found_dir REGEX "^ricci_DIR:")
string(REGEX REPLACE "^ricci_DIR:[A-Z]+=" "" found_dir "${found_dir}")
file(REAL_PATH "${found_dir}" found_dir)
file(REAL_PATH "${package_dir}" expected_dir)
if(NOT found_dir STREQUAL expected_dir)
  message(FATAL_ERROR "the example found ricci in '${found_dir}', not in '${expected_dir}'")
endif()

# 5. Build and run it.
run_step("build examples/find_package"
  "${CMAKE_COMMAND}" --build "${example_build}" --config "${RICCI_CONFIG}")
set(example "${example_build}/ricci_example${RICCI_EXE_SUFFIX}")
if(NOT EXISTS "${example}")
  set(example "${example_build}/${RICCI_CONFIG}/ricci_example${RICCI_EXE_SUFFIX}")
endif()
run_step("run the example" "${example}")
message(STATUS "${step_output}")
