# Libraries loaded with dlopen when first used instead of linked (src/core/runtime_library.hpp):
# their soname and the Debian package that ships it are compiled into the loader source, and the
# package is added to the .deb's Depends (dpkg-shlibdeps cannot see a dlopen).
#
# microbrdf_load_at_run_time(<PREFIX> <library file> <loader source>)
#   defines MICROBRDF_<PREFIX>_SONAME and MICROBRDF_<PREFIX>_PACKAGE for <loader source> and
#   appends the package to MICROBRDF_RUNTIME_PACKAGES.
function(microbrdf_load_at_run_time prefix library source)
  execute_process(COMMAND objdump -p ${library} OUTPUT_VARIABLE dyn RESULT_VARIABLE rc ERROR_QUIET)
  string(REGEX MATCH "SONAME +([^ \n]+)" line "${dyn}")
  if(NOT rc EQUAL 0 OR NOT CMAKE_MATCH_1)
    message(FATAL_ERROR "cannot read the soname of ${library} (objdump -p)")
  endif()
  set(soname "${CMAKE_MATCH_1}")
  get_filename_component(real "${library}" REALPATH)
  get_filename_component(dir "${real}" DIRECTORY)
  execute_process(COMMAND dpkg -S "${dir}/${soname}" OUTPUT_VARIABLE owner RESULT_VARIABLE rc
                  ERROR_QUIET)
  set(package "")
  if(rc EQUAL 0 AND owner MATCHES "^([^:]+):")
    set(package "${CMAKE_MATCH_1}")
  endif()
  message(STATUS "${soname}: loaded when first used (Debian package ${package})")
  set_property(SOURCE ${source} APPEND PROPERTY COMPILE_DEFINITIONS
               MICROBRDF_${prefix}_SONAME="${soname}")
  if(package)
    set_property(SOURCE ${source} APPEND PROPERTY COMPILE_DEFINITIONS
                 MICROBRDF_${prefix}_PACKAGE="the Debian package ${package}")
    set(MICROBRDF_RUNTIME_PACKAGES ${MICROBRDF_RUNTIME_PACKAGES} ${package} PARENT_SCOPE)
  endif()
endfunction()
