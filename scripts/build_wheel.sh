#!/usr/bin/env bash
# Builds the wheel of the Python package libbrdf (pyproject.toml: scikit-build-core + pybind11,
# pinned) for CPython 3.11, the Python of Blender 4.2 - 5.0, and prints its path.
# Usage: scripts/build_wheel.sh OUT_DIR
# The CMake build is kept in build/wheel-build (scikit-build-core's build-dir), so a second run
# recompiles only what changed. Python: the pinned venv of scripts/python_env.sh wheel.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:?usage: scripts/build_wheel.sh OUT_DIR}
mkdir -p "$out"
venv=$("$root/scripts/python_env.sh" wheel)
rm -f "$out"/libbrdf-*.whl
"$venv/bin/python" -m pip wheel --quiet --disable-pip-version-check --no-deps --wheel-dir "$out" \
  --config-settings=build-dir="$root/build/wheel-build" "$root" >&2
ls "$out"/libbrdf-*.whl
