# CTest entries beyond the GoogleTest cases discovered in tests/CMakeLists.txt (included from there).

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
target_include_directories(tileshade_check_tests PRIVATE ${CMAKE_SOURCE_DIR}/tests/support)
target_compile_definitions(tileshade_check_tests PRIVATE TILESHADE_BINARY="$<TARGET_FILE:tileshade>"
                           TILESHADE_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
add_dependencies(tileshade_check_tests tileshade)
gtest_discover_tests(tileshade_check_tests DISCOVERY_TIMEOUT 60
                     PROPERTIES LABELS check ENVIRONMENT "TILESHADE_SOURCE_DIR=${CMAKE_SOURCE_DIR}")

# Every kernel under Oclgrind (tests/oclgrind_run.sh), label `oclgrind`, on tiny frames: each
# technique in each G-buffer layout with lanes 1 and 16, the dump's
# decoder, tiled-single's local list overflowing into chunks, odd tile sizes, a device limit of
# 64 work-items, and the test binary's exit. Zero reports of out-of-bounds or uninitialised
# accesses, data races or barrier divergence. Oclgrind 21.10's --uninitialized needs
# -cl-opt-disable (it stops at LLVM's freeze) and reports false uses after a 4-byte
# clEnqueueFillBuffer (tiled's and clustered's list clears) and when several techniques share a
# process: those runs check the other reports only, one technique per process where it counts.
set(TILESHADE_OCLGRIND_RUN ${CMAKE_SOURCE_DIR}/tests/oclgrind_run.sh)
set(TILESHADE_OCLGRIND_FRAME --device oclgrind --width 40 --height 24 --light-count 30 --check
    --out @OUT@)
function(tileshade_oclgrind_test name options)
  add_test(NAME Oclgrind.${name} COMMAND bash ${TILESHADE_OCLGRIND_RUN} "${options}" ${ARGN})
  set_tests_properties(Oclgrind.${name} PROPERTIES LABELS oclgrind SKIP_RETURN_CODE 77
    ENVIRONMENT "TILESHADE_SOURCE_DIR=${CMAKE_SOURCE_DIR}")
endfunction()
# Every run unoptimised: Oclgrind 21.10 cannot run the llvm.experimental.noalias.scope.decl that
# LLVM's inliner leaves behind.
set(TILESHADE_OCLGRIND_NOOPT "--build-options -cl-opt-disable")
set(TILESHADE_OCLGRIND_ALL "--data-races --uninitialized ${TILESHADE_OCLGRIND_NOOPT}")
# Every registered technique, read from its one list (techniqueRegistry, whose entries open with
# {"name",), so that registering a technique stays one line there.
set(TILESHADE_REGISTRY ${CMAKE_SOURCE_DIR}/src/techniques/registry.cpp)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${TILESHADE_REGISTRY})
file(STRINGS ${TILESHADE_REGISTRY} TILESHADE_REGISTRY_ENTRIES REGEX "^ *{\"[a-z-]+\",")
set(TILESHADE_TECHNIQUES)
foreach(entry ${TILESHADE_REGISTRY_ENTRIES})
  string(REGEX MATCH "{\"([a-z-]+)\"," unused "${entry}")
  list(APPEND TILESHADE_TECHNIQUES ${CMAKE_MATCH_1})
endforeach()
if(NOT "tiled" IN_LIST TILESHADE_TECHNIQUES OR NOT "brute" IN_LIST TILESHADE_TECHNIQUES)
  message(FATAL_ERROR "tests/extra_tests.cmake found no technique entries in ${TILESHADE_REGISTRY} "
                      "(got '${TILESHADE_TECHNIQUES}'): did the entries' layout change?")
endif()
foreach(layout fp32 fp16 packed)
  foreach(lanes 1 16)
    foreach(technique ${TILESHADE_TECHNIQUES})
      if(technique MATCHES "forward")
        # The forward family draws with OpenGL (--raster gl); its OpenCL kernels are tiled's,
        # run here under tiled's name.
        continue()
      endif()
      set(options ${TILESHADE_OCLGRIND_ALL})
      if(technique STREQUAL "tiled" OR technique STREQUAL "clustered")
        # the fill-buffer false reports, above
        set(options "--data-races ${TILESHADE_OCLGRIND_NOOPT}")
      endif()
      set(extra)
      if(technique STREQUAL "brute")
        set(extra --dump)  # kernels/dump.cl's decoder, in this layout
      endif()
      tileshade_oclgrind_test(${technique}.${layout}.lanes${lanes} "${options}"
        $<TARGET_FILE:tileshade> render ${TILESHADE_OCLGRIND_FRAME} --technique ${technique}
        --gbuffer ${layout} --lanes ${lanes} ${extra})
    endforeach()
  endforeach()
endforeach()
# --msaa in tiled and clustered (kernels/msaa_edges.h, shade_tiled_edge_samples,
# shade_clustered_edge_samples) in every layout, lanes 1 and 16 (the second, lane-less builds of
# tiled.cl and clustered.cl): through the test binary, whose frame's samples
# need no OpenGL (llvmpipe and Oclgrind crash in one process, as for the forward family).
tileshade_oclgrind_test(tiled.msaa "--data-races ${TILESHADE_OCLGRIND_NOOPT}"
  $<TARGET_FILE:tileshade_tests> --gtest_filter=TiledMsaaKernels.*)
foreach(lanes 1 16)
  # 1100 lights reaching every tile: tiled-single's 1024-light local list shades in two chunks, in
  # tiles that cross the frame's edge (issue #12's heap corruption on PoCL).
  tileshade_oclgrind_test(tiled-single.chunks.lanes${lanes} "${TILESHADE_OCLGRIND_ALL}"
    $<TARGET_FILE:tileshade> render --device oclgrind --width 18 --height 6 --light-count 1100
    --light-range 1000 --check --out @OUT@ --technique tiled-single --lanes ${lanes})
endforeach()
foreach(tile 7x5 24x8)
  foreach(technique tiled tiled-single clustered)
    tileshade_oclgrind_test(${technique}.tile${tile} "--data-races ${TILESHADE_OCLGRIND_NOOPT}"
      $<TARGET_FILE:tileshade> render ${TILESHADE_OCLGRIND_FRAME} --technique ${technique}
      --gbuffer fp16 --lanes 16 --tile ${tile})
  endforeach()
endforeach()
foreach(lanes 1 16)
  # A device allowing 64 work-items per group: every launch's shape from the limits.
  tileshade_oclgrind_test(all.max-wgsize-64.lanes${lanes} "--data-races --max-wgsize 64 ${TILESHADE_OCLGRIND_NOOPT}"
    $<TARGET_FILE:tileshade> render ${TILESHADE_OCLGRIND_FRAME} --technique all --lanes ${lanes}
    --tile 24x8)
endforeach()
# Shading with shadow maps (kernels/shadows.h; TS_HAS_SHADOWS builds): the atrium's four lights of
# largest range cast, a 5x5 filter reaching past the faces' edges (clamped), per-pixel and lanes.
foreach(lanes 1 16)
  tileshade_oclgrind_test(deferred.shadows.lanes${lanes} "${TILESHADE_OCLGRIND_ALL}"
    $<TARGET_FILE:tileshade> render ${TILESHADE_OCLGRIND_FRAME} --technique deferred
    --shadows 4 --shadow-map-size 16 --shadow-filter pcf5 --lanes ${lanes})
  # The receiver-plane bias's branch (its gradient and per-tap depths).
  tileshade_oclgrind_test(deferred.shadows-receiver.lanes${lanes} "${TILESHADE_OCLGRIND_ALL}"
    $<TARGET_FILE:tileshade> render ${TILESHADE_OCLGRIND_FRAME} --technique deferred
    --shadows 4 --shadow-map-size 16 --shadow-filter pcf5 --shadow-bias receiver,0.5
    --lanes ${lanes})
endforeach()
# tiled's binning on both of its paths (a work-item per light, a work-group per big light; the
# default run above takes one path per device), its lists against the host's.
tileshade_oclgrind_test(tiled.binning-paths "--data-races ${TILESHADE_OCLGRIND_NOOPT}"
  $<TARGET_FILE:tileshade_tests> --gtest_filter=TileLightGrid.TinyFrame*)
# The test binary under Oclgrind: its kernels, and its exit (the process-wide context used to be
# released after the OpenCL runtime's exit handlers, an abort at exit).
tileshade_oclgrind_test(tests.exit "--data-races ${TILESHADE_OCLGRIND_NOOPT}" $<TARGET_FILE:tileshade_tests>
  --gtest_filter=TiledSingleChunks.OnePixel*)

# bench's shard recipes end to end (bench/README.md, "Sweeps beyond one process"): three shards as
# separate processes, merged, equal one unsharded run; the GNU parallel one is skipped (77) where
# `parallel` is absent, the Slurm array script runs as its tasks would without Slurm.
foreach(mode parallel slurm)
  add_test(NAME BenchShards.${mode}
           COMMAND bash ${CMAKE_SOURCE_DIR}/tests/bench/bench_shards_test.sh ${mode}
                   $<TARGET_FILE:tileshade> ${CMAKE_SOURCE_DIR})
  set_tests_properties(BenchShards.${mode} PROPERTIES SKIP_RETURN_CODE 77
    ENVIRONMENT "TILESHADE_SOURCE_DIR=${CMAKE_SOURCE_DIR}")
endforeach()

# The CPU-native yardstick agrees with `tiled` and the reference on a tiny dump
# (tests/bench/yardstick_test.sh; the dump's images need OpenImageIO).
if(TILESHADE_WITH_OIIO)
  add_test(NAME BenchYardstick.AgreesWithTiledAndReference
           COMMAND bash ${CMAKE_SOURCE_DIR}/tests/bench/yardstick_test.sh $<TARGET_FILE:tileshade>
                   $<TARGET_FILE:tileshade-yardstick>)
  set_tests_properties(BenchYardstick.AgreesWithTiledAndReference PROPERTIES TIMEOUT 120)
endif()
