# Start-up time of the `ricci` program: the BLAS first among the libraries it loads.
#
# OpenBLAS's core (libopenblas.so.0) carries about 16000 symbolic relocations, nearly all to its
# own functions, and the dynamic loader looks each one up through the global scope in load
# order: the program, its own libraries, theirs, ... OpenBLAS came third-level (ricci -> CHOLMOD
# -> libblas.so.3 -> libopenblas.so.0), behind some 30 libraries, and those lookups were the
# larger part of the program's 17 ms start (an empty program linked like ricci: 17 -> 8 ms of
# CPU with this order, the C-only MPI and libzip loaded on demand).
#
# The names are the runtime sonames Debian's alternatives resolve (liblapack.so.3, libblas.so.3,
# then libopenblas.so.0 where those are OpenBLAS's), in CHOLMOD's own order, so every BLAS and
# LAPACK symbol binds where it bound before: whichever implementation the alternatives select
# at run time. Nothing changes when they are not found, nor under the sanitizers (whose
# runtime, when shared, must come first).
if(NOT RICCI_HAVE_CHOLMOD OR RICCI_SANITIZE)
  return()
endif()
find_library(RICCI_LAPACK_RUNTIME NAMES liblapack.so.3)
find_library(RICCI_BLAS_RUNTIME NAMES libblas.so.3)
if(NOT RICCI_LAPACK_RUNTIME OR NOT RICCI_BLAS_RUNTIME)
  return()
endif()
set(ricci_first_libraries "${RICCI_LAPACK_RUNTIME}" "${RICCI_BLAS_RUNTIME}")
file(REAL_PATH "${RICCI_BLAS_RUNTIME}" ricci_blas_file)
find_library(RICCI_OPENBLAS_RUNTIME NAMES libopenblas.so.0)
if(ricci_blas_file MATCHES "openblas" AND RICCI_OPENBLAS_RUNTIME)
  list(APPEND ricci_first_libraries "${RICCI_OPENBLAS_RUNTIME}")
endif()
# Link options come before the objects on the link line, so these are the first DT_NEEDED
# entries; --no-as-needed keeps them although the program calls none of them directly.
target_link_options(ricci BEFORE PRIVATE "LINKER:--push-state,--no-as-needed"
                    ${ricci_first_libraries} "LINKER:--pop-state")
message(STATUS "ricci: loads first: ${ricci_first_libraries}")
