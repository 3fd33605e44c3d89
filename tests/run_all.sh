#!/usr/bin/env bash
# Runs every test: C++ (GoogleTest), file-format and CLI checks, real POV-Ray and real Blender
# renders, and the main job at reduced size, all through ctest.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install_deps.sh" --with-renderers
"$root/scripts/build.sh" "$root/build"
cd "$root/build"
ctest --output-on-failure -j"$(nproc)" "$@"
