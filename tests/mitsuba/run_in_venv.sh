#!/usr/bin/env bash
# Runs a Mitsuba test script with the pinned venv's Python (scripts/python_env.sh mitsuba:
# Mitsuba 3, numpy, scipy). Exit 77 (ctest: skipped) with the reason when no venv can be made
# (no CPython 3.11 or no package index reachable: python_env.sh exits 3).
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
reason=$(mktemp)
trap 'rm -f "$reason"' EXIT
venv=$("$root/scripts/python_env.sh" mitsuba 2>"$reason")
status=$?
if [[ $status -eq 3 ]]; then
  echo "SKIPPED: no Mitsuba venv: $(tail -n 1 "$reason")"
  exit 77
elif [[ $status -ne 0 ]]; then
  cat "$reason" >&2
  exit "$status"
fi
"$venv/bin/python" "$@"
