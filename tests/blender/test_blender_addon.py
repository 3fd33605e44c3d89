"""Installs the add-on into a headless Blender and runs blender_addon_checks.py there
(registration, presets, operator errors, FIT/LUT/OSL set-up, drivers, unregister).
Usage: test_blender_addon.py   (env BRDF_EXE, LIBBRDF_ROOT)
"""

import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from test_blender_render import BLENDER, BRDF, addon_zip  # noqa: E402


def main():
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, LIBBRDF_BRDF_EXE=os.path.abspath(BRDF) if os.path.sep in BRDF else shutil.which(BRDF),
                   BLENDER_USER_SCRIPTS=os.path.join(tmp, "user_scripts"),
                   BLENDER_USER_CONFIG=os.path.join(tmp, "user_config"), TMPDIR=tmp)
        done = subprocess.run([BLENDER, "-b", "--factory-startup", "--python-exit-code", "1", "--python",
                               os.path.join(HERE, "blender_addon_checks.py"), "--", addon_zip(tmp)],
                              env=env, capture_output=True, text=True)
        lines = [line for line in done.stdout.splitlines() if line.startswith(("ok ", "FAIL", "{"))]
        print("\n".join(lines))
        if done.returncode != 0 or not lines or not lines[-1].startswith('{"failures": 0'):
            print(done.stderr[-3000:])
            print(f"FAIL blender exited with {done.returncode}")
            return 1
    print("add-on checks in Blender passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
