# CTest entries beyond the GoogleTest cases discovered in CMakeLists.txt (included from there).

# tiled-single's chunk loop under PoCL's `loops` work-group method too: PoCL 3.1 miscompiled it
# (issue #12, kernels/tiled_single.cl) into writes past the image with its default method (a
# crash) and into unwritten pixels with `loops` (an error the test sees). PoCL's kernel cache
# does not key on the method, hence POCL_KERNEL_CACHE=0 (5 kernel builds: the issue's frame only). Other OpenCL implementations ignore both.
add_test(NAME TiledSingleChunks.PoclLoopsMethod
         COMMAND tileshade_tests --gtest_filter=TiledSingleChunks.IssueFrame*)
set_tests_properties(TiledSingleChunks.PoclLoopsMethod PROPERTIES
  ENVIRONMENT "TILESHADE_SOURCE_DIR=${CMAKE_SOURCE_DIR};POCL_WORK_GROUP_METHOD=loops;POCL_KERNEL_CACHE=0")

# Every kernel compiled for a device without fp64, warnings as errors (tests/kernels_without_fp64.sh).
# Needs a clang with the SPIR target: PoCL's own clang (Debian's pocl depends on clang-15).
find_program(TILESHADE_OPENCL_CLANG NAMES clang-15 clang HINTS /usr/lib/llvm-15/bin)
if(TILESHADE_OPENCL_CLANG)
  add_test(NAME KernelsWithoutFp64
           COMMAND bash ${CMAKE_SOURCE_DIR}/tests/kernels_without_fp64.sh ${TILESHADE_OPENCL_CLANG}
                   ${CMAKE_SOURCE_DIR}/kernels)
  set_tests_properties(KernelsWithoutFp64 PROPERTIES LABELS portability)
else()
  message(STATUS "no clang found: the KernelsWithoutFp64 test is left out")
endif()

# The work-group limit tests with PoCL itself enforcing a limit of 64 (and reporting it, so the
# shapes come from the device's own limit): a launch that ignores it fails with
# CL_INVALID_WORK_GROUP_SIZE, as on a stricter device (issue #12). Other implementations ignore it.
add_test(NAME WorkGroupLimits.PoclEnforcesSixtyFour
         COMMAND tileshade_tests --gtest_filter=WorkGroupLimits.*:TiledSingleChunks.OnePixel*)
set_tests_properties(WorkGroupLimits.PoclEnforcesSixtyFour PROPERTIES
  ENVIRONMENT "TILESHADE_SOURCE_DIR=${CMAKE_SOURCE_DIR};POCL_MAX_WORK_GROUP_SIZE=64")

# The hard-case suite (`tileshade check`, docs/hard-cases.md), one CTest case per hard case with
# the label `check`: `ctest -L check` runs it alone.
add_executable(tileshade_check_tests ${CMAKE_SOURCE_DIR}/tests/check/hard_cases_test.cpp)
target_link_libraries(tileshade_check_tests PRIVATE tileshade_core GTest::gtest GTest::gtest_main)
target_compile_definitions(tileshade_check_tests PRIVATE TILESHADE_BINARY="$<TARGET_FILE:tileshade>")
add_dependencies(tileshade_check_tests tileshade)
gtest_discover_tests(tileshade_check_tests DISCOVERY_TIMEOUT 60
                     PROPERTIES LABELS check ENVIRONMENT "TILESHADE_SOURCE_DIR=${CMAKE_SOURCE_DIR}")
