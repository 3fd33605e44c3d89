"""Paths shared by the Blender test scripts, imported first (a script's own directory is on
sys.path): this directory, tests/ (checks.py) and the add-on's directory go on sys.path; ROOT is
the repository (env LIBBRDF_ROOT), BRDF the brdf executable (env BRDF_EXE)."""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.environ.get("LIBBRDF_ROOT", os.path.normpath(os.path.join(HERE, "..", "..")))
BRDF = os.environ.get("BRDF_EXE", "brdf")
for path in (os.path.dirname(HERE), os.path.join(ROOT, "blender_addon"), HERE):
    if path not in sys.path:
        sys.path.insert(0, path)
