# What `cmake --install build [--prefix P]` writes (docs/architecture.md, "Using microbrdf from C++"):
#   bin/microbrdf                                    the command line (the library linked in)
#   lib/libmicrobrdf.so.<soversion>                  the library, for other programs
#   include/microbrdf/*.hpp                          its public headers
#   lib/cmake/microbrdf/                             find_package(microbrdf CONFIG) -> microbrdf::microbrdf
#   lib/pkgconfig/microbrdf.pc                       pkg-config --cflags --libs microbrdf
#   lib/python3.X/dist-packages/microbrdf/           the Python module, the library linked in
#                                                    (lib/python3/dist-packages under /usr; python/)
# Everything is relocatable: the CMake package and the .pc file find the prefix from where they lie.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(TARGETS microbrdf_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

# Sanitiser and fuzzing builds are not installed as a library (their objects need the
# sanitiser runtime); they keep only the rule above.
if(MICROBRDF_SANITIZE OR MICROBRDF_BUILD_FUZZ)
  return()
endif()

# The shared library, linked from the objects the static archive holds (no second compile).
# Its interface is what the public headers need (Eigen, nlohmann_json, C++20); every other
# dependency is private, recorded in the library itself (DT_NEEDED), so a program that links
# microbrdf needs only the -dev packages of Eigen and nlohmann_json.
add_library(microbrdf_shared SHARED $<TARGET_OBJECTS:microbrdf_objects>)
target_include_directories(microbrdf_shared PUBLIC $<BUILD_INTERFACE:${CMAKE_SOURCE_DIR}/include>
                                                   $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
target_compile_features(microbrdf_shared PUBLIC cxx_std_20)
target_link_libraries(microbrdf_shared PUBLIC ${MICROBRDF_HEADER_DEPS}
                                       PRIVATE OpenMP::OpenMP_CXX fmt::fmt ${MICROBRDF_PRIVATE_DEPS})
# A symbol left undefined would only show when another program links: fail here instead.
target_link_options(microbrdf_shared PRIVATE LINKER:--no-undefined)
# While the version is 0.x every minor release may change the ABI, so the SONAME carries it.
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(MICROBRDF_SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
else()
  set(MICROBRDF_SOVERSION ${PROJECT_VERSION_MAJOR})
endif()
set_target_properties(microbrdf_shared PROPERTIES OUTPUT_NAME microbrdf EXPORT_NAME microbrdf
                                                  VERSION ${PROJECT_VERSION} SOVERSION ${MICROBRDF_SOVERSION})

install(TARGETS microbrdf_shared EXPORT microbrdfTargets LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
# ndf_model_template.hpp is for models built into microbrdf itself: it differentiates with
# ceres::Jet, a dependency the package does not hand on (docs/architecture.md, adding a model).
install(DIRECTORY ${CMAKE_SOURCE_DIR}/include/microbrdf DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        PATTERN "ndf_model_template.hpp" EXCLUDE)

# CMake package: microbrdfConfig.cmake (finds Eigen3 and nlohmann_json, then the target),
# microbrdfTargets*.cmake and a version file (same major.minor while 0.x, same major after).
set(MICROBRDF_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/microbrdf)
install(EXPORT microbrdfTargets NAMESPACE microbrdf:: DESTINATION ${MICROBRDF_CMAKE_DIR})
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/microbrdfConfig.cmake.in
                              ${CMAKE_BINARY_DIR}/cmake/microbrdfConfig.cmake INSTALL_DESTINATION ${MICROBRDF_CMAKE_DIR})
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(MICROBRDF_COMPATIBILITY SameMinorVersion)
else()
  set(MICROBRDF_COMPATIBILITY SameMajorVersion)
endif()
write_basic_package_version_file(${CMAKE_BINARY_DIR}/cmake/microbrdfConfigVersion.cmake
                                 COMPATIBILITY ${MICROBRDF_COMPATIBILITY})
install(FILES ${CMAKE_BINARY_DIR}/cmake/microbrdfConfig.cmake ${CMAKE_BINARY_DIR}/cmake/microbrdfConfigVersion.cmake
        DESTINATION ${MICROBRDF_CMAKE_DIR})

# pkg-config: the prefix is found from the .pc file's own place (${pcfiledir}), so the file is
# right under any --prefix and in the Debian package.
set(MICROBRDF_PC_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")  # a libdir given as an absolute path pins the prefix
  set(MICROBRDF_PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
else()  # ${pcfiledir}/../.. for lib/pkgconfig
  file(RELATIVE_PATH up /p/${MICROBRDF_PC_DIR} /p)
  string(REGEX REPLACE "/$" "" up "${up}")
  set(MICROBRDF_PC_PREFIX "\${pcfiledir}/${up}")
endif()
foreach(kind LIBDIR INCLUDEDIR)
  if(IS_ABSOLUTE "${CMAKE_INSTALL_${kind}}")
    set(MICROBRDF_PC_${kind} "${CMAKE_INSTALL_${kind}}")
  else()
    set(MICROBRDF_PC_${kind} "\${prefix}/${CMAKE_INSTALL_${kind}}")
  endif()
endforeach()
configure_file(${CMAKE_SOURCE_DIR}/cmake/microbrdf.pc.in ${CMAKE_BINARY_DIR}/cmake/microbrdf.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/cmake/microbrdf.pc DESTINATION ${MICROBRDF_PC_DIR})
