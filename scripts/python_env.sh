#!/usr/bin/env bash
# Creates (once) and prints the path of a pinned Python virtual environment for the PyPI-only
# pieces: real Blender 4.5 LTS / 5.0 as a Python module (bpy) and Mitsuba 3.
# Usage: scripts/python_env.sh NAME     (NAME: a file scripts/requirements/NAME.txt, pinned)
# The venv lives in ${LIBBRDF_VENV_ROOT:-$HOME/.cache/libbrdf/venv}/NAME and is rebuilt when the
# requirements file changes (its hash is stored inside). Python: $LIBBRDF_VENV_PYTHON, else the
# first python3.11 on PATH (bpy and mitsuba ship wheels for CPython 3.11).
# Exit status 3 (and a one-line reason on stderr) when no Python 3.11 or no package index is
# reachable, so that callers can skip with that reason instead of failing.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
name=${1:?usage: scripts/python_env.sh NAME}
req="$root/scripts/requirements/$name.txt"
[[ -f $req ]] || { echo "python_env.sh: no requirements file $req" >&2; exit 2; }
venv_root=${LIBBRDF_VENV_ROOT:-$HOME/.cache/libbrdf/venv}
venv="$venv_root/$name"
want=$(sha256sum "$req" | cut -c1-16)
mkdir -p "$venv_root"
# One maker at a time (ctest runs tests in parallel that may ask for the same venv).
exec 9>"$venv_root/.$name.lock"
flock 9
if [[ -x $venv/bin/python && -f $venv/.requirements-hash && $(cat "$venv/.requirements-hash") == "$want" ]]; then
  echo "$venv"
  exit 0
fi
python=${LIBBRDF_VENV_PYTHON:-}
if [[ -z $python ]]; then
  for candidate in python3.11 python3; do
    if command -v "$candidate" >/dev/null &&
       "$candidate" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null &&
       "$candidate" -c 'import venv, ensurepip' 2>/dev/null; then
      python=$(command -v "$candidate"); break
    fi
  done
fi
[[ -n $python ]] || { echo "python_env.sh: no CPython 3.11 with venv and ensurepip on PATH (bpy and mitsuba need 3.11)" >&2; exit 3; }
# The hash is written last: a venv without it (an interrupted install) is rebuilt from scratch.
rm -rf "$venv"
"$python" -m venv "$venv" >&2
if ! "$venv/bin/python" -m pip install -q --disable-pip-version-check -r "$req" >&2; then
  rm -rf "$venv"
  echo "python_env.sh: pip could not install $req (no package index reachable?)" >&2
  exit 3
fi
echo "$want" >"$venv/.requirements-hash"
echo "$venv"
