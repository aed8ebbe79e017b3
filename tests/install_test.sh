#!/usr/bin/env bash
# The install test (CTest: Install.PrefixAndDebianPackage, label `install`; cmake/install.cmake).
# Usage: install_test.sh BUILD_DIR [CMAKE [CPACK]]
#  1. `cmake --install` into a scratch prefix, moved elsewhere so that no absolute build path can
#     serve: render (small frame, --check) and `check --case` from the moved binary; the binary
#     copied without its share/ must fail naming the install path (no source-tree fallback).
#  2. the Debian package (cpack -G DEB): its control fields and file list, then extracted with
#     dpkg-deb -x into a scratch root and run from there.
#  3. with CI=true only (CI runs as root on a throwaway machine): apt-get install of the .deb,
#     /usr/bin/tileshade render and check, apt-get remove. Never outside CI.
# In 1 and 2 (and 3), examples/shade_gbuffer is configured with find_package(tileshade) against
# the installed tree (-DCMAKE_PREFIX_PATH, a copy of the example away from the checkout), built
# and run: the API's library, headers and CMake package as an engine sees them.
# Exits 77 (skipped) without cmake, cpack, dpkg-deb or dpkg-shlibdeps (dpkg-dev).
set -euo pipefail
build=$(cd "$1" && pwd)
cmake=${2:-cmake}
cpack=${3:-cpack}
for tool in "$cmake" "$cpack" dpkg-deb dpkg-shlibdeps; do
  command -v "$tool" >/dev/null || { echo "SKIP: $tool not found"; exit 77; }
done

scratch=$(mktemp -d "${TMPDIR:-/tmp}/tileshade-install.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
device=${TILESHADE_DEVICE:-cpu}
with_oiio=$(sed -n 's/^TILESHADE_WITH_OIIO:BOOL=//p' "$build/CMakeCache.txt")
with_gl=$(sed -n 's/^TILESHADE_WITH_GL:BOOL=//p' "$build/CMakeCache.txt")
fail() { echo "FAIL: $*" >&2; exit 1; }

# examples/shade_gbuffer built against the installed package at prefix $1 (a copy of the example
# away from the source tree), run: it shades its own G-buffer and checks it.
build_example() {
  local prefix=$1 work=$2
  mkdir -p "$work"
  cp -r "$(dirname "$0")/../examples/shade_gbuffer" "$work/src"
  "$cmake" -S "$work/src" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
    ${prefix:+-DCMAKE_PREFIX_PATH="$prefix"} >"$work/configure.log" 2>&1 ||
    { cat "$work/configure.log"; fail "the example did not configure against $prefix"; }
  "$cmake" --build "$work/build" >"$work/build.log" 2>&1 ||
    { cat "$work/build.log"; fail "the example did not build against $prefix"; }
  "$work/build/shade_gbuffer" "$device" >"$work/run.log" 2>&1 ||
    { cat "$work/run.log"; fail "the example built against $prefix failed"; }
  grep -qx "ok" "$work/run.log" || { cat "$work/run.log"; fail "the example printed no ok"; }
}

# render + check from one installed binary, its output kept for the failure message.
run_installed() {
  local exe=$1 out=$2
  "$exe" --version | grep -qx "tileshade [0-9]*\.[0-9]*\.[0-9]*" || fail "$exe --version"
  "$exe" render --device "$device" --width 64 --height 36 --light-count 20 --technique tiled \
    --check --out "$out" >"$out.log" 2>&1 || { cat "$out.log"; fail "$exe render"; }
  grep -q "tiled" "$out.log" || { cat "$out.log"; fail "$exe render printed no table"; }
  "$exe" check --device "$device" --case resolution-1x1 --technique tiled --gbuffer fp32 \
    --lanes 1 >"$out.check.log" 2>&1 || { cat "$out.check.log"; fail "$exe check"; }
  [ "$with_gl" = ON ] || return 0
  # The shaders too; a machine where no OpenGL context can be made says so and goes on (as the
  # GL tests skip there), but a shader that is not found fails.
  if ! "$exe" render --device "$device" --raster gl --width 32 --height 18 --technique tiled \
       --out "$out-gl" >"$out.gl.log" 2>&1; then
    if grep -q "shader source" "$out.gl.log"; then cat "$out.gl.log"; fail "$exe --raster gl"; fi
    echo "note: --raster gl not run, no OpenGL context here: $(tail -1 "$out.gl.log")"
  fi
}

echo "== cmake --install into a scratch prefix, then moved"
"$cmake" --install "$build" --prefix "$scratch/prefix" >/dev/null
for f in bin/tileshade share/tileshade/kernels/shading.h share/tileshade/kernels/tiled.cl \
         share/doc/tileshade/LICENSE share/doc/tileshade/NOTICE share/doc/tileshade/copyright \
         share/doc/tileshade/README.md; do
  [ -f "$scratch/prefix/$f" ] || fail "not installed: $f"
done
if [ "$with_gl" = ON ]; then
  [ -f "$scratch/prefix/share/tileshade/shaders/gbuffer.vert" ] || fail "shaders not installed"
fi
for f in include/tileshade/tileshade.h include/tileshade/error.h include/tileshade/version.h \
         lib/cmake/tileshade/tileshadeConfig.cmake lib/cmake/tileshade/tileshadeConfigVersion.cmake \
         lib/cmake/tileshade/tileshadeTargets.cmake; do
  [ -f "$scratch/prefix/$f" ] || fail "not installed: $f"
done
ls "$scratch"/prefix/lib/libtileshade.so.* >/dev/null 2>&1 || fail "not installed: lib/libtileshade.so"
mv "$scratch/prefix" "$scratch/moved"
run_installed "$scratch/moved/bin/tileshade" "$scratch/prefix-out"
build_example "$scratch/moved" "$scratch/example-prefix"

# The binary alone, away from any share/ and any build folder: one error line naming the
# install path it looked in, not a silent fallback to the source tree.
mkdir -p "$scratch/alone/bin"
cp "$scratch/moved/bin/tileshade" "$scratch/alone/bin/"
if "$scratch/alone/bin/tileshade" render --device "$device" --width 16 --height 16 \
     --out "$scratch/alone-out" >"$scratch/alone.log" 2>&1; then
  fail "a binary without its kernels rendered"
fi
grep -q "tileshade: error: cannot read kernel source $scratch/alone/share/tileshade/kernels/" \
  "$scratch/alone.log" || { cat "$scratch/alone.log"; fail "unexpected error without kernels"; }
# ... and $TILESHADE_KERNEL_DIR still points it at kernels elsewhere.
TILESHADE_KERNEL_DIR="$scratch/moved/share/tileshade/kernels" "$scratch/alone/bin/tileshade" \
  render --device "$device" --width 16 --height 16 --technique tiled --out "$scratch/env-out" \
  >/dev/null 2>&1 || fail "TILESHADE_KERNEL_DIR not used"

echo "== the Debian package"
(cd "$scratch" && "$cpack" -G DEB --config "$build/CPackConfig.cmake" -B "$scratch/deb" >cpack.log 2>&1) ||
  { cat "$scratch/cpack.log"; fail "cpack"; }
deb=$(ls "$scratch"/deb/tileshade_*.deb)
dpkg-deb -I "$deb" >/dev/null || fail "dpkg-deb -I $deb"
version=$("$scratch/moved/bin/tileshade" --version | cut -d' ' -f2)
field() { dpkg-deb -f "$deb" "$1"; }
[ "$(field Package)" = tileshade ] || fail "Package: $(field Package)"
[ "$(field Version)" = "$version" ] || fail "Version: $(field Version), binary says $version"
depends=$(field Depends)
wanted=("ocl-icd-libopencl1" "pocl-opencl-icd | opencl-icd" "libtinygltf" "libstdc++6" "libc6")
[ "$with_oiio" = ON ] && wanted+=(libopenimageio)
[ "$with_gl" = ON ] && wanted+=(libepoxy0 libegl1)
for dep in "${wanted[@]}"; do
  case "$depends" in *"$dep"*) ;; *) fail "Depends lacks '$dep': $depends" ;; esac
done
files=$(dpkg-deb -c "$deb" | awk '{print $6}')
for f in ./usr/bin/tileshade ./usr/share/tileshade/kernels/shading.h \
         ./usr/share/doc/tileshade/copyright ./usr/share/doc/tileshade/LICENSE \
         ./usr/include/tileshade/tileshade.h ./usr/lib/cmake/tileshade/tileshadeConfig.cmake; do
  grep -qx "$f" <<<"$files" || fail "not in the package: $f"
done
if grep -v -e '^\./usr/$' -e '^\./usr/bin/' -e '^\./usr/share/' -e '^\./usr/include/' \
     -e '^\./usr/lib/' -e '^\./$' <<<"$files" | grep -q .; then
  fail "files outside /usr/{bin,share,include,lib}: $(grep -v -e '^\./usr/' <<<"$files")"
fi
dpkg-deb -x "$deb" "$scratch/root"
run_installed "$scratch/root/usr/bin/tileshade" "$scratch/root-out"
build_example "$scratch/root/usr" "$scratch/example-deb"
dpkg-deb -f "$deb" Package Version Architecture Depends

if [ "${CI:-}" = true ]; then
  echo "== apt-get install (CI)"
  apt-get install -y "$deb" >"$scratch/apt.log" 2>&1 || { cat "$scratch/apt.log"; fail "apt-get install"; }
  status=0
  (run_installed /usr/bin/tileshade "$scratch/system-out") || status=$?  # removed either way
  ( cd / && tileshade --version )
  (build_example "" "$scratch/example-system") || status=$?  # /usr: found without a prefix path
  apt-get remove -y tileshade >/dev/null 2>&1 || fail "apt-get remove"
  [ "$status" = 0 ] || fail "the installed package did not run"
fi
# The Python module (python/, docs/python.md), when the build made it: imported from the moved
# prefix and from the extracted package with only their dist-packages on PYTHONPATH, from a scratch
# folder (no source tree, no build folder, no TILESHADE_KERNEL_DIR), rendering and checking a frame
# with the kernels of that install tree; with CI=true also from the apt-installed package.
python=$(sed -n 's/^Python3_EXECUTABLE:FILEPATH=//p' "$build/CMakeCache.txt")
if [ -n "$python" ] && compgen -G "$build/python/tileshade*.so" >/dev/null; then
  echo "== the Python module"
  import_installed() {  # import_installed DIST_PACKAGES ("": the interpreter's own path)
    (cd "$scratch" && env -u TILESHADE_KERNEL_DIR PYTHONPATH="$1" "$python" -c '
import sys, numpy, tileshade
where, device = sys.argv[1], sys.argv[2]
assert tileshade.__file__.startswith(where), tileshade.__file__ + " is not under " + where
image, stats = tileshade.render(width=32, height=18, light_count=10, check=True, device=device)
assert image.shape == (18, 32, 3) and numpy.isfinite(image).all() and image.max() > 0
assert stats["check"]["missed"] == 0, stats["check"]
print("python3 -c \"import tileshade\":", tileshade.__version__, stats["device"], tileshade.__file__)
' "${1:-/usr/lib/python3/dist-packages}" "$device") || fail "import tileshade from ${1:-the system}"
  }
  import_installed "$scratch/moved/lib/python3/dist-packages"
  import_installed "$scratch/root/usr/lib/python3/dist-packages"
  if [ "${CI:-}" = true ]; then
    apt-get install -y "$deb" >"$scratch/apt-python.log" 2>&1 || { cat "$scratch/apt-python.log"; fail "apt-get install"; }
    status=0
    (import_installed "") || status=$?
    apt-get remove -y tileshade >/dev/null 2>&1 || fail "apt-get remove"
    [ "$status" = 0 ] || fail "the apt-installed module did not run"
  fi
fi
echo "install test passed"
