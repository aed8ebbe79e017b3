# `cmake --install build --prefix P` and the Debian package (CPack DEB) made from the same rules.
# The paths are fixed (not GNUInstallDirs') because the binary and the library find their data at
# <exe or lib>/../share/tileshade (src/util/data_dir.h).
install(TARGETS tileshade RUNTIME DESTINATION bin)
# The API (docs/api.md): libtileshade.so, its headers and a CMake package, so that
# find_package(tileshade) gives the target tileshade::tileshade.
install(TARGETS tileshade_library EXPORT tileshadeTargets
        LIBRARY DESTINATION lib
        INCLUDES DESTINATION include)
install(FILES ${CMAKE_SOURCE_DIR}/include/tileshade/tileshade.h
              ${CMAKE_SOURCE_DIR}/include/tileshade/error.h
              ${CMAKE_BINARY_DIR}/generated/tileshade/version.h
        DESTINATION include/tileshade)
install(EXPORT tileshadeTargets NAMESPACE tileshade:: DESTINATION lib/cmake/tileshade)
include(CMakePackageConfigHelpers)
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/tileshadeConfig.cmake.in
                              ${CMAKE_BINARY_DIR}/generated/tileshadeConfig.cmake
                              INSTALL_DESTINATION lib/cmake/tileshade)
# Before 1.0 a minor version may change the API: only the same major.minor is compatible.
write_basic_package_version_file(${CMAKE_BINARY_DIR}/generated/tileshadeConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/generated/tileshadeConfig.cmake
              ${CMAKE_BINARY_DIR}/generated/tileshadeConfigVersion.cmake
        DESTINATION lib/cmake/tileshade)
install(DIRECTORY ${CMAKE_SOURCE_DIR}/kernels/ DESTINATION share/tileshade/kernels)
if(TILESHADE_WITH_GL)
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/shaders/ DESTINATION share/tileshade/shaders)
endif()
# README's links to docs/ keep working in the installed copy.
install(FILES ${CMAKE_SOURCE_DIR}/README.md ${CMAKE_SOURCE_DIR}/LICENSE ${CMAKE_SOURCE_DIR}/NOTICE
        DESTINATION share/doc/tileshade)
install(DIRECTORY ${CMAKE_SOURCE_DIR}/docs/ DESTINATION share/doc/tileshade/docs)
# Debian's machine-readable copyright file: the licence and the third-party data's notices.
install(FILES ${CMAKE_SOURCE_DIR}/cmake/debian-copyright DESTINATION share/doc/tileshade
        RENAME copyright)

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME tileshade)
set(CPACK_PACKAGE_VENDOR "tileshade developers")
set(CPACK_PACKAGE_CONTACT "tileshade developers")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "tiled shading of a G-buffer in OpenCL, and a lab that measures light-culling techniques")
set(CPACK_PACKAGE_DESCRIPTION
    "Renders a G-buffer and shades it with light-culling techniques (tiled, tiled-single, clustered, deferred, deferred-stencil, brute force in OpenCL; tiled forward with and without a depth pre-pass in OpenGL on the same OpenCL light grid, multi-pass and single-pass forward on per-batch light lists), checks each against a double-precision reference and measures speed and error. Includes the C++ library (libtileshade, find_package(tileshade)) and the Python module.")
set(CPACK_RESOURCE_FILE_LICENSE ${CMAKE_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
# The linked libraries' packages (OpenCL ICD loader, OpenImageIO, libepoxy, tinygltf, libstdc++)
# come from dpkg-shlibdeps; what is only loaded at run time is named here: an OpenCL driver
# (any ICD; PoCL runs on the CPU) and, for --raster gl, EGL (libepoxy dlopens it) with a vendor.
set(TILESHADE_DEB_RUNTIME "pocl-opencl-icd | opencl-icd")
if(TILESHADE_WITH_GL)
  string(APPEND TILESHADE_DEB_RUNTIME ", libegl1, libegl-mesa0 | libegl-vendor")
endif()
# The Python module's interpreter and numpy (python/CMakeLists.txt), when it is built.
if(TILESHADE_DEB_PYTHON_DEPENDS)
  string(APPEND TILESHADE_DEB_RUNTIME ", ${TILESHADE_DEB_PYTHON_DEPENDS}")
endif()
set(CPACK_DEBIAN_PACKAGE_DEPENDS "${TILESHADE_DEB_RUNTIME}")
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
include(CPack)

# The install test (tests/install_test.sh): install, package, run from both with the source tree
# out of reach. Label `install`; skipped (77) without cpack, dpkg-deb or dpkg-shlibdeps. Not in a
# sanitizer build: nobody packages one, and scripts/test.sh's release stage runs it already.
if(TILESHADE_BUILD_TESTS AND NOT TILESHADE_SANITIZE)
  add_test(NAME Install.PrefixAndDebianPackage
           COMMAND bash ${CMAKE_SOURCE_DIR}/tests/install_test.sh ${CMAKE_BINARY_DIR}
                   ${CMAKE_COMMAND} ${CMAKE_CPACK_COMMAND})
  set_tests_properties(Install.PrefixAndDebianPackage PROPERTIES LABELS install
                       SKIP_RETURN_CODE 77 TIMEOUT 300)
endif()
