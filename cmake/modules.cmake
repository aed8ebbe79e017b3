# The modules of src/ as CMake targets, and the one list of which module may use which.
#
# tileshade_module(NAME [DEPS module...] [LIBS target...] [EXCLUDE regex])
#   src/NAME/*.cpp (less those matching EXCLUDE) become the static library tileshade_NAME, or an
#   INTERFACE library when the module is headers only. DEPS are the modules whose headers it
#   includes (and whose symbols it uses), LIBS the third-party targets it uses itself. A new .cpp
#   in a module needs no edit; a new module is one call in the list below.
#
# The DEPS are the layering rule: cmake/check_layers.cmake (ctest -L layers) fails when a file
# includes a module that its module does not list, or when the list has a cycle. It reads the
# list from ${CMAKE_BINARY_DIR}/generated/module_deps.cmake, written here at configure time.

# What every module compiles with: the include roots (src/ for "module/file.h", the source tree
# for "kernels/..." and "shaders/...") and the definitions every object file must agree on
# (glm's vector layout; which optional libraries the build has).
add_library(tileshade_common INTERFACE)
target_include_directories(tileshade_common INTERFACE ${CMAKE_SOURCE_DIR}/src ${CMAKE_SOURCE_DIR}
                           ${CMAKE_SOURCE_DIR}/include ${CMAKE_BINARY_DIR}/generated)
target_compile_definitions(tileshade_common INTERFACE GLM_FORCE_XYZW_ONLY)
target_link_libraries(tileshade_common INTERFACE glm::glm)
if(NOT TILESHADE_WITH_OIIO)
  target_compile_definitions(tileshade_common INTERFACE TILESHADE_NO_OIIO)
endif()
if(NOT TILESHADE_WITH_GL)
  target_compile_definitions(tileshade_common INTERFACE TILESHADE_NO_GL)
endif()
if(NOT TILESHADE_WITH_EMBREE)
  target_compile_definitions(tileshade_common INTERFACE TILESHADE_NO_EMBREE)
endif()

# The warnings every target of ours compiles with (modules, the binary, tests, fuzzers);
# -DTILESHADE_WERROR=ON (or TILESHADE_WERROR=ON in the environment of the first configure, as
# .ci/run does) makes them errors.
set(TILESHADE_WERROR_DEFAULT OFF)
if("$ENV{TILESHADE_WERROR}")
  set(TILESHADE_WERROR_DEFAULT ON)
endif()
option(TILESHADE_WERROR "compiler warnings are errors (CI)" ${TILESHADE_WERROR_DEFAULT})
add_library(tileshade_warnings INTERFACE)
target_compile_options(tileshade_warnings INTERFACE -Wall -Wextra -Wno-ignored-attributes
                       $<$<BOOL:${TILESHADE_WERROR}>:-Werror>)

set(TILESHADE_MODULES "")
set(TILESHADE_MODULE_DEPS_TEXT "")

function(tileshade_module name)
  cmake_parse_arguments(PARSE_ARGV 1 M "" "EXCLUDE" "DEPS;LIBS")
  foreach(dep IN LISTS M_DEPS)
    if(NOT TARGET tileshade_${dep})
      message(FATAL_ERROR "module ${name}: dependency ${dep} is no module declared before it")
    endif()
  endforeach()
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/${name}/*.cpp)
  if(M_EXCLUDE)
    list(FILTER sources EXCLUDE REGEX "${M_EXCLUDE}")
  endif()
  list(TRANSFORM M_DEPS PREPEND tileshade_ OUTPUT_VARIABLE dep_targets)
  if(sources)
    add_library(tileshade_${name} STATIC ${sources})
    # Linked into libtileshade.so as well as into the executable.
    set_target_properties(tileshade_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    target_link_libraries(tileshade_${name} PUBLIC tileshade_common ${dep_targets} ${M_LIBS}
                          PRIVATE tileshade_warnings)
  else()
    add_library(tileshade_${name} INTERFACE)
    target_link_libraries(tileshade_${name} INTERFACE tileshade_common ${dep_targets} ${M_LIBS})
  endif()
  set(TILESHADE_MODULES ${TILESHADE_MODULES} ${name} PARENT_SCOPE)
  string(REPLACE ";" " " deps_text "${M_DEPS}")
  set(TILESHADE_MODULE_DEPS_TEXT
      "${TILESHADE_MODULE_DEPS_TEXT}set(TILESHADE_DEPS_${name} ${deps_text})\n" PARENT_SCOPE)
endfunction()

# The lowest layer first: a module depends only on modules declared before it (so no cycle).
set(TILESHADE_GL_SOURCES "/(gl_|egl_)[^/]*\\.cpp$")
if(TILESHADE_WITH_GL)
  set(TILESHADE_GL_SOURCES "")
  set(TILESHADE_GL_LIBS PkgConfig::EPOXY)
endif()
if(TILESHADE_WITH_OIIO)
  set(TILESHADE_OIIO_LIBS PkgConfig::OIIO)
endif()
tileshade_module(util LIBS CLI11::CLI11 nlohmann_json::nlohmann_json Threads::Threads
                      ${CMAKE_DL_LIBS})
tileshade_module(shading)
tileshade_module(cl DEPS util LIBS OpenCL::OpenCL)
target_compile_definitions(tileshade_cl PUBLIC
  CL_HPP_TARGET_OPENCL_VERSION=120 CL_HPP_MINIMUM_OPENCL_VERSION=120 CL_HPP_ENABLE_EXCEPTIONS)
target_include_directories(tileshade_cl PUBLIC ${OPENCL_CLHPP_INCLUDE})
tileshade_module(scene DEPS util shading
                 LIBS TinyGLTF::TinyGLTF nlohmann_json::nlohmann_json Threads::Threads
                      ${TILESHADE_OIIO_LIBS})
tileshade_module(gbuffer DEPS util scene shading LIBS ${TILESHADE_OIIO_LIBS})
tileshade_module(raster DEPS util cl gbuffer scene shading LIBS Threads::Threads ${TILESHADE_GL_LIBS}
                 EXCLUDE "${TILESHADE_GL_SOURCES}")
tileshade_module(reference DEPS util gbuffer shading LIBS Threads::Threads)
tileshade_module(techniques DEPS util cl gbuffer raster scene shading)
tileshade_module(render DEPS util cl gbuffer raster reference scene shading techniques
                 LIBS nlohmann_json::nlohmann_json ${TILESHADE_OIIO_LIBS})
# Exact visibility through Embree: the scene's triangles against the G-buffer's points, and the
# shadow maps measured against it (the references of render/).
tileshade_module(visibility DEPS util gbuffer reference render scene
                 LIBS ${TILESHADE_EMBREE_LIBS} Threads::Threads nlohmann_json::nlohmann_json)
tileshade_module(bench DEPS util cl gbuffer raster reference render scene shading techniques
                 visibility
                 LIBS CLI11::CLI11 nlohmann_json::nlohmann_json)
tileshade_module(check DEPS util cl gbuffer reference render scene shading techniques
                 LIBS CLI11::CLI11 nlohmann_json::nlohmann_json Threads::Threads)
# The public C++ API (include/tileshade/tileshade.h) over the modules below it.
tileshade_module(api DEPS util cl gbuffer raster reference render scene shading techniques bench
                 LIBS OpenCL::OpenCL)
# The command line's own code: what `tileshade render` does with the API's results (table, files).
tileshade_module(cli DEPS util api gbuffer reference render scene shading techniques visibility
                 LIBS nlohmann_json::nlohmann_json)

# A directory of src/ that is no module would build into nothing (and fail only at link time).
file(GLOB TILESHADE_SRC_ENTRIES RELATIVE ${CMAKE_SOURCE_DIR}/src ${CMAKE_SOURCE_DIR}/src/*)
foreach(entry IN LISTS TILESHADE_SRC_ENTRIES)
  if(IS_DIRECTORY ${CMAKE_SOURCE_DIR}/src/${entry} AND NOT entry IN_LIST TILESHADE_MODULES)
    message(FATAL_ERROR "src/${entry}/ is no module: add tileshade_module(${entry} DEPS ...) to "
                        "cmake/modules.cmake")
  endif()
endforeach()

# Everything: the binary, the tests and the fuzzers link this.
add_library(tileshade_core INTERFACE)
list(TRANSFORM TILESHADE_MODULES PREPEND tileshade_ OUTPUT_VARIABLE TILESHADE_MODULE_TARGETS)
target_link_libraries(tileshade_core INTERFACE ${TILESHADE_MODULE_TARGETS})

file(WRITE ${CMAKE_BINARY_DIR}/generated/module_deps.cmake.new
     "# Written by cmake/modules.cmake: the modules and their declared dependencies.\n"
     "set(TILESHADE_MODULES ${TILESHADE_MODULES})\n" "${TILESHADE_MODULE_DEPS_TEXT}")
# Rewritten only when it changes, so a reconfigure does not touch it.
file(COPY_FILE ${CMAKE_BINARY_DIR}/generated/module_deps.cmake.new
     ${CMAKE_BINARY_DIR}/generated/module_deps.cmake ONLY_IF_DIFFERENT)
file(REMOVE ${CMAKE_BINARY_DIR}/generated/module_deps.cmake.new)

# The layering check: seconds, host only, no build needed (cmake/check_layers.cmake).
if(TILESHADE_BUILD_TESTS)
  enable_testing()
  add_test(NAME Layers.IncludesFollowModuleDeps
           COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${CMAKE_SOURCE_DIR}
                   -DMODULE_DEPS=${CMAKE_BINARY_DIR}/generated/module_deps.cmake
                   -P ${CMAKE_SOURCE_DIR}/cmake/check_layers.cmake)
  set_tests_properties(Layers.IncludesFollowModuleDeps PROPERTIES LABELS layers TIMEOUT 60)
endif()

# The code's layout (.clang-format) with clang-format 14; skipped (77) where that is absent.
if(TILESHADE_BUILD_TESTS)
  add_test(NAME Format.ClangFormat COMMAND bash ${CMAKE_SOURCE_DIR}/scripts/format_check.sh)
  set_tests_properties(Format.ClangFormat PROPERTIES LABELS "layers;format" TIMEOUT 120
                       SKIP_RETURN_CODE 77)
endif()
