#!/usr/bin/env bash
# Configures and builds libbrdf (Release). Usage: scripts/build.sh [build-dir] [target ...]
# (no targets: everything, tests and benchmarks included; run.sh builds only `brdf`).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
shift $(( $# > 0 ? 1 : 0 ))
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j"$(nproc)" "${targets[@]}"
