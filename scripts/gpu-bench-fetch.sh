#!/usr/bin/env bash
# Prepares a GPU benchmark on a machine that has a compiler, CMake and OpenCL but no package
# registry (such as the NVIDIA machine of our device tool): downloads, here, the Debian packages
# that tileshade's measurement build needs into .deps/ (ignored by git), to be carried there and
# used by scripts/gpu-bench.sh. Needs apt-get (a Debian 12 machine with its registry).
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p .deps
cd .deps
apt-get download libglm-dev libtinygltf-dev libtinygltf2d libstb0 libcli11-dev \
  nlohmann-json3-dev libimath-dev >/dev/null
# --raster gl (the forward techniques' rows): libepoxy and the GLVND dispatchers it dlopens
# (libEGL.so.1, libOpenGL.so.0); the GPU's own EGL vendor library comes with its driver.
apt-get download libepoxy0 libepoxy-dev libegl-dev libgl-dev libegl1 libopengl0 libglvnd0 \
  >/dev/null
ls -1 *.deb
