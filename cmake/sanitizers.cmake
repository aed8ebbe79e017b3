# Sanitizer and fuzzing builds (tests/fuzz/README.md). Both go in their own build folder, e.g.
#   CXX=clang++ cmake -S . -B build-asan -DTILESHADE_SANITIZE=ON -DTILESHADE_FUZZ=ON
# TILESHADE_SANITIZE: every target with AddressSanitizer + UndefinedBehaviorSanitizer; any
#   undefined behaviour aborts (-fno-sanitize-recover), so a test that triggers it fails.
# TILESHADE_FUZZ (clang only): also the libFuzzer targets of tests/fuzz/, with the library
#   instrumented for coverage (-fsanitize=fuzzer-no-link); implies TILESHADE_SANITIZE.
option(TILESHADE_SANITIZE "build everything with AddressSanitizer + UndefinedBehaviorSanitizer" OFF)
option(TILESHADE_FUZZ "build the libFuzzer targets of tests/fuzz (clang; implies TILESHADE_SANITIZE)" OFF)

if(TILESHADE_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "TILESHADE_FUZZ needs clang (libFuzzer): configure with CXX=clang++")
  endif()
  set(TILESHADE_SANITIZE ON)
endif()

if(TILESHADE_SANITIZE)
  set(TILESHADE_SANITIZER_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=undefined
      -fno-omit-frame-pointer -g)
  if(TILESHADE_FUZZ)
    list(APPEND TILESHADE_SANITIZER_FLAGS -fsanitize=fuzzer-no-link)
  endif()
  add_compile_options(${TILESHADE_SANITIZER_FLAGS})
  add_link_options(-fsanitize=address,undefined)
  # -O1 keeps the instrumented build reasonably fast without hiding the stack traces.
  string(REPLACE "-O3" "-O1" CMAKE_CXX_FLAGS_RELEASE "${CMAKE_CXX_FLAGS_RELEASE}")
  string(REPLACE "-O2" "-O1" CMAKE_CXX_FLAGS_RELWITHDEBINFO "${CMAKE_CXX_FLAGS_RELWITHDEBINFO}")
endif()
