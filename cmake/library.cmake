# libtileshade.so: the public API (include/tileshade/, src/api/) with the internal modules linked
# in, as the CMake target tileshade::tileshade (here and, installed, through find_package). The
# tileshade executable links the static modules itself (one self-contained binary, no RPATH to
# keep right when the install tree moves); the library is for engines and the Python module.
file(GLOB TILESHADE_API_SOURCES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/api/*.cpp)
add_library(tileshade_library SHARED ${TILESHADE_API_SOURCES})
add_library(tileshade::tileshade ALIAS tileshade_library)
set_target_properties(tileshade_library PROPERTIES
  OUTPUT_NAME tileshade
  EXPORT_NAME tileshade
  VERSION ${PROJECT_VERSION}
  # Before 1.0 a minor version may change the API (docs/api.md): the soname carries it.
  SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
target_include_directories(tileshade_library PUBLIC
  $<BUILD_INTERFACE:${CMAKE_SOURCE_DIR}/include>
  $<BUILD_INTERFACE:${CMAKE_BINARY_DIR}/generated>
  $<INSTALL_INTERFACE:include>)
# tileshade.h includes <CL/cl.h>: OpenCL is part of the interface.
target_link_libraries(tileshade_library PUBLIC OpenCL::OpenCL
                      PRIVATE tileshade_api tileshade_warnings)
# The modules' symbols stay inside: only what the API needs is pulled in, and no internal symbol
# leaks into the engine's namespace of symbols.
target_link_options(tileshade_library PRIVATE -Wl,--exclude-libs,ALL)
