# ricci_runtime_library(LIBRARY SONAME_VAR FILE_VAR): what the program opens at run time (dlopen)
# for a library found at build time, instead of linking it: the soname (libcholmod.so.3 from
# libcholmod.so.3.0.14, the library the system has whenever it runs) and the file itself (to
# try when the soname is not found). Used for CHOLMOD, Cairo and libzip.
function(ricci_runtime_library library soname_var file_var)
  file(REAL_PATH "${library}" file)
  get_filename_component(name "${file}" NAME)
  if(name MATCHES "^(lib[^.]+\\.so\\.[0-9]+)")
    set(soname "${CMAKE_MATCH_1}")
  else()
    set(soname "${name}")
  endif()
  set(${soname_var} "${soname}" PARENT_SCOPE)
  set(${file_var} "${file}" PARENT_SCOPE)
endfunction()
