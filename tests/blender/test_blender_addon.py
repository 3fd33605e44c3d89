"""Installs the add-on into a headless Blender and runs blender_addon_checks.py there
(registration, presets, operator errors, FIT/LUT/OSL set-up, drivers, unregister).
Usage: test_blender_addon.py [--blender debian|4.5|5.0]   (env BRDF_EXE, LIBBRDF_ROOT)
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.dirname(HERE))
from blender_test_env import BLENDER_VERSIONS, BRDF, ROOT, blender_program  # noqa: E402
from render_check import blender_command  # noqa: E402
sys.path.insert(0, os.path.join(ROOT, "blender_addon"))
import checks  # noqa: E402
from package import addon_zip  # noqa: E402


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--blender", default="debian", choices=BLENDER_VERSIONS)
    program = blender_program(parser.parse_args().blender)
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, LIBBRDF_BRDF_EXE=os.path.abspath(BRDF) if os.path.sep in BRDF else shutil.which(BRDF),
                   BLENDER_USER_SCRIPTS=os.path.join(tmp, "user_scripts"),
                   BLENDER_USER_CONFIG=os.path.join(tmp, "user_config"), TMPDIR=tmp,
                   XDG_CACHE_HOME=os.path.join(tmp, "cache"))
        done = subprocess.run(blender_command(program, os.path.join(HERE, "blender_addon_checks.py"), addon_zip(tmp)),
                              env=env, capture_output=True, text=True)
        # blender_addon_checks.py uses tests/checks.py: its last summary line counts the checks.
        lines = [line for line in done.stdout.splitlines()
                 if line.startswith(("ok ", "FAIL")) or re.fullmatch(r"\d+ passed, \d+ failed", line)]
        print("\n".join(lines))
        ok = done.returncode == 0 and bool(lines) and re.fullmatch(r"\d+ passed, 0 failed", lines[-1]) is not None
        if not ok:
            print(done.stderr[-3000:])
        checks.check(ok, f"add-on checks in Blender (blender exited with {done.returncode})")
    checks.finish("add-on checks in Blender passed")


if __name__ == "__main__":
    main()
