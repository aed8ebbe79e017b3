#!/usr/bin/env bash
# Runs python3 with the in-place module (CTest: Python.*, label `python`; python/CMakeLists.txt).
# Usage: run_python_test.sh MODULE_DIR PYTHON "MODULES NEEDED" ARGS...
# Exits 77 (skipped) when the module was not built or a Python package it needs is missing
# (Debian: python3-numpy, python3-pytest, python3-matplotlib).
set -euo pipefail
module_dir=$1 python=$2 needed=$3
shift 3
if ! compgen -G "$module_dir/tileshade*.so" >/dev/null; then
  echo "SKIP: the Python module was not built (no $module_dir/tileshade*.so; TILESHADE_PYTHON)"
  exit 77
fi
for m in $needed; do
  "$python" -c "import $m" 2>/dev/null || { echo "SKIP: $python has no module $m"; exit 77; }
done
export PYTHONPATH="$module_dir${PYTHONPATH:+:$PYTHONPATH}"
exec "$python" "$@"
