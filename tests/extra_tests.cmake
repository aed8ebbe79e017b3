# CTest entries beyond the GoogleTest cases discovered in CMakeLists.txt (included from there).

# tiled-single's chunk loop under PoCL's `loops` work-group method too: PoCL 3.1 miscompiled it
# (issue #12, kernels/tiled_single.cl) into writes past the image with its default method (a
# crash) and into unwritten pixels with `loops` (an error the test sees). PoCL's kernel cache
# does not key on the method, hence POCL_KERNEL_CACHE=0 (5 kernel builds: the issue's frame only). Other OpenCL implementations ignore both.
add_test(NAME TiledSingleChunks.PoclLoopsMethod
         COMMAND tileshade_tests --gtest_filter=TiledSingleChunks.IssueFrame*)
set_tests_properties(TiledSingleChunks.PoclLoopsMethod PROPERTIES
  ENVIRONMENT "TILESHADE_SOURCE_DIR=${CMAKE_SOURCE_DIR};POCL_WORK_GROUP_METHOD=loops;POCL_KERNEL_CACHE=0")
