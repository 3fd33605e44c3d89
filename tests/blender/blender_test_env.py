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


# The Blenders the tests run in: Debian's program (3.4), and Blender 4.5 LTS / 5.0 as bpy from PyPI
# in pinned venvs (scripts/python_env.sh, requirements in scripts/requirements/).
BLENDER_VERSIONS = ("debian", "4.5", "5.0")
_VENVS = {"4.5": "bpy45", "5.0": "bpy50"}


def blender_program(version):
    """What runs a script in that Blender (render_check.blender_command takes either form):
    Debian's `blender` (env BLENDER), or the Python of the bpy venv, made on first use. Exits 77
    (ctest: skipped) with the reason where the venv cannot be made (no Python 3.11, no index)."""
    import subprocess

    if version == "debian":
        return os.environ.get("BLENDER", "blender")
    made = subprocess.run([os.path.join(ROOT, "scripts", "python_env.sh"), _VENVS[version]],
                          capture_output=True, text=True)
    if made.returncode == 3:
        print(f"SKIP: Blender {version} (bpy from PyPI) unavailable: {made.stderr.strip().splitlines()[-1]}")
        sys.exit(77)
    if made.returncode != 0:
        print(made.stderr[-2000:])
        raise SystemExit(f"scripts/python_env.sh {_VENVS[version]} failed (exit {made.returncode})")
    return os.path.join(made.stdout.strip().splitlines()[-1], "bin", "python")
