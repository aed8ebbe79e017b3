#!/usr/bin/env bash
# Builds the Debian package of the Release build: ./build/tileshade_<version>_<arch>.deb, with its
# dependencies from dpkg-shlibdeps (cmake/install.cmake). Install it with
# `sudo apt install ./build/tileshade_*.deb`. Extra arguments go to the CMake configure step
# (e.g. -DTILESHADE_WITH_GL=OFF; then -DTILESHADE_BUILD_TESTS=OFF skips the tests' build too).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build -j "$(nproc)"
(cd build && cpack -G DEB)
ls build/tileshade_*.deb
