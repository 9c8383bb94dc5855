# `ricci blender-addon` (apps/ricci/blender_addon_command.cpp): the add-on's Python files
# (blender/ricci_uv) compiled into the program by cmake/embed_files.cmake, so that it needs no
# data folder at run time, and libzip to write the zip (opened on demand, below). Without libzip
# there is no such command.
# (pkg-config: Debian's libzip CMake package names tools from another package, /usr/bin/zipcmp.)
find_package(PkgConfig REQUIRED)
pkg_check_modules(LIBZIP IMPORTED_TARGET libzip)
if(NOT LIBZIP_FOUND)
  message(STATUS "ricci: libzip not found: no `ricci blender-addon` (apt install libzip-dev)")
  return()
endif()
message(STATUS "ricci: libzip found: `ricci blender-addon` writes the Blender add-on")
set(ricci_addon_dir "${PROJECT_SOURCE_DIR}/blender/ricci_uv")
# The names here and in blender_addon_command.cpp's table go together.
set(ricci_addon_files "${ricci_addon_dir}/__init__.py|${ricci_addon_dir}/operator.py|${ricci_addon_dir}/unwrap.py")
string(REPLACE "|" ";" ricci_addon_depends "${ricci_addon_files}")
add_custom_command(
  OUTPUT "${CMAKE_BINARY_DIR}/generated/blender_addon_files.cpp"
  COMMAND "${CMAKE_COMMAND}"
    "-DOUTPUT=${CMAKE_BINARY_DIR}/generated/blender_addon_files.cpp"
    "-DNAMESPACE=ricci::cli::addon"
    "-DNAMES=kInit|kOperator|kUnwrap"
    "-DFILES=${ricci_addon_files}"
    -P "${PROJECT_SOURCE_DIR}/cmake/embed_files.cmake"
  DEPENDS "${PROJECT_SOURCE_DIR}/cmake/embed_files.cmake" ${ricci_addon_depends}
  COMMENT "Embedding the Blender add-on"
  VERBATIM)
target_sources(ricci PRIVATE apps/ricci/blender_addon_command.cpp
                             "${CMAKE_BINARY_DIR}/generated/blender_addon_files.cpp")
# libzip is opened when the command runs (dlopen), not loaded with the program: it brings
# libcrypto, whose relocations cost every other command about 3 ms of start-up. Its headers
# give the functions' types; its soname, from the library found here, is what is opened.
ricci_runtime_library("${LIBZIP_LINK_LIBRARIES}" ricci_libzip_soname ricci_libzip_file)
target_include_directories(ricci PRIVATE ${LIBZIP_INCLUDE_DIRS})
target_link_libraries(ricci PRIVATE ${CMAKE_DL_LIBS})
target_compile_definitions(ricci PRIVATE RICCI_HAVE_BLENDER_ADDON=1
                                         RICCI_LIBZIP_SONAME="${ricci_libzip_soname}")
