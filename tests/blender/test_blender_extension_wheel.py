"""The Blender 4.2+ extension with the libbrdf wheel bundled (issue 33, item 3): builds the wheel
(scripts/build_wheel.sh: pyproject.toml through scikit-build-core, for CPython 3.11), zips it into
the extension (blender_addon/package.py --extension --wheel), installs that with Install from Disk
(bpy.ops.extensions.package_install_files) into Blender 4.5 LTS and 5.0 (bpy from PyPI), gives the
add-on no `brdf` program, and renders LUT mode at seeded random scenes (test_blender_random.py): the
add-on must bake in Blender's own process and the renders must meet LUT mode's targets.
Exit 77 (skipped) with the reason where the wheel's build tools or bpy cannot be had (no index).
Usage: test_blender_extension_wheel.py [--blenders 4.5,5.0] [--scenes N]   (env BRDF_EXE, LIBBRDF_ROOT)
"""
import argparse
import os
import subprocess
import sys
import tempfile

import blender_test_env  # noqa: F401  (sys.path)
from blender_test_env import ROOT
import checks  # noqa: E402
from checks import check  # noqa: E402


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--blenders", default="4.5,5.0")
    parser.add_argument("--scenes", type=int, default=2)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="libbrdf_wheel_") as tmp:
        built = subprocess.run([os.path.join(ROOT, "scripts", "build_wheel.sh"), tmp], capture_output=True, text=True)
        if built.returncode == 3:
            print(f"SKIP: the wheel's Python environment is unavailable: {built.stderr.strip().splitlines()[-1]}")
            return 77
        wheels = built.stdout.split()
        if not check(built.returncode == 0 and len(wheels) == 1 and wheels[0].endswith(".whl"),
                     f"scripts/build_wheel.sh built one wheel ({wheels}){'' if built.returncode == 0 else built.stderr[-2000:]}"):
            checks.finish()
        print(f"     wheel {os.path.basename(wheels[0])}, {os.path.getsize(wheels[0]) / 1e6:.1f} MB")
        env = {k: v for k, v in os.environ.items() if k != "LIBBRDF_BRDF_EXE"}
        for version in args.blenders.split(","):
            run = subprocess.run([sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), "test_blender_random.py"),
                                  "--blender", version, "--scenes", str(args.scenes), "--extension", "--wheel", wheels[0]],
                                 env=env, capture_output=True, text=True)
            print(run.stdout.strip())
            if run.returncode == 77:
                print(f"SKIP: Blender {version}: {run.stdout.strip().splitlines()[-1:]}")
                return 77
            check(run.returncode == 0, f"Blender {version}: extension with the wheel installed, baked in process and "
                                       f"rendered LUT within the targets (exit {run.returncode}){run.stderr[-1500:]}")
    checks.finish("the extension with its libbrdf wheel bakes in process and renders, in every Blender asked")


if __name__ == "__main__":
    sys.exit(main())
