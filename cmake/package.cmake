# `make package` (cpack -G DEB): one Debian package, microbrdf_<version>_<arch>.deb, holding what
# `cmake --install` writes, under /usr. Its Depends are the Debian packages of the shared
# libraries the binaries load (dpkg-shlibdeps, from dpkg-dev) plus the interpreter the Python
# module was built for and numpy, which the module works on.
if(MICROBRDF_SANITIZE OR MICROBRDF_BUILD_FUZZ)
  return()
endif()

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME microbrdf)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "microbrdf maintainers")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "surface reflectance predicted from measured microgeometry")
string(CONCAT CPACK_PACKAGE_DESCRIPTION
       "microbrdf predicts how a surface reflects light from its measured microgeometry: it reads\n"
       "height maps from profilometers (x3p, Zygo, Sensofar, Digital Surf, Gwyddion, ...), estimates\n"
       "normal distribution functions (geometric and Kirchhoff), fits microfacet models, builds\n"
       "BRDFs, renders and exports them and writes HTML reports. This package holds the command\n"
       "line tool, the Python module, and the shared library with its headers, CMake package and\n"
       "pkg-config file.")
set(MICROBRDF_DEB_MAINTAINER "microbrdf maintainers <maintainers@users.noreply.h-seed-ec9e3186.example>"
    CACHE STRING "Maintainer field of the Debian package (make package)")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${MICROBRDF_DEB_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # microbrdf_0.1.0_amd64.deb
# CPack's DEB generator runs the install scripts with this prefix itself (staged through
# DESTDIR), so the Python rule sees /usr and picks lib/python3/dist-packages (python/CMakeLists.txt).
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# A shlibs file for libmicrobrdf.so.<soversion> (programs built on it get the right Depends) and
# the ldconfig calls that make the new library known. CPack warns that the Python extension has
# no SONAME: true, and it is rightly left out of the shlibs file.
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
if(MICROBRDF_PYTHON_VERSION)  # set by python/CMakeLists.txt
  string(REPLACE "." ";" v ${MICROBRDF_PYTHON_VERSION})
  list(GET v 0 major)
  list(GET v 1 minor)
  math(EXPR next_minor "${minor} + 1")
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3 (>= ${major}.${minor}), python3 (<< ${major}.${next_minor}), python3-numpy")
  # Removes the bytecode python3 writes beside the module when root imports it, so `dpkg -r`
  # leaves no folder behind (what py3clean does for Debian's own packages).
  set(MICROBRDF_DEB_PY_PACKAGE /usr/${MICROBRDF_PY_DIR_USR}/microbrdf)
  configure_file(${CMAKE_SOURCE_DIR}/cmake/deb-prerm.in ${CMAKE_BINARY_DIR}/cmake/deb/prerm @ONLY
                 FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
  set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${CMAKE_BINARY_DIR}/cmake/deb/prerm)
endif()
# The libraries loaded with dlopen when first used (cmake/runtime_libraries.cmake): dpkg-shlibdeps
# cannot see them, so their packages are named here.
foreach(p IN LISTS MICROBRDF_RUNTIME_PACKAGES)
  if(CPACK_DEBIAN_PACKAGE_DEPENDS)
    string(APPEND CPACK_DEBIAN_PACKAGE_DEPENDS ", ${p}")
  else()
    set(CPACK_DEBIAN_PACKAGE_DEPENDS "${p}")
  endif()
endforeach()
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
