#!/usr/bin/python3
"""Runs every command of README.md's ```sh blocks verbatim, as a new user would after the set-up.

The two set-up commands (`./run.sh`, `./tests/run_all.sh`) are skipped: they are the main job and
this test suite itself. Everything else runs, in README order, in one bash session (so `export` and
`cd` carry over) with `set -e`, in a fresh temporary directory that holds only `build` (a link to
the build under test, which the quickstart installs from), with HOME a fresh temporary directory
(so `cmake --install build --prefix ~/.local` and Blender's preferences land there) and a PATH
without any ~/.local/bin. The test fails if any command exits non-zero (naming it), and checks that
the quickstart's two renders exist and show gold: lit, and redder than blue. It also runs the
```python blocks with Debian's /usr/bin/python3 in the same environment (the module from the fresh
~/.local, matplotlib on Agg).

Usage: test_readme_commands.py [README]   (env LIBBRDF_ROOT, LIBBRDF_BUILD)
"""
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

ROOT = os.environ["LIBBRDF_ROOT"]
BUILD = os.environ["LIBBRDF_BUILD"]
sys.path.insert(0, os.path.join(ROOT, "tests"))
import checks  # noqa: E402
from checks import check  # noqa: E402

SETUP_COMMANDS = ("./run.sh", "./tests/run_all.sh")  # the main job and the test suite: not run here
MARK = "@@readme-command@@"


def readme_commands(text):
    """The shell commands in README order: every line of the ```sh blocks (a line ending in a
    backslash continues; comments skipped), and the `$ ` lines of the plain ``` blocks (a command
    with its output, which tests/cli/test_eval_contract.py compares)."""
    commands = []
    for info, block in re.findall(r"^```(\w*)\n(.*?)^```", text, flags=re.M | re.S):
        if info == "":
            commands += [line[2:] for line in block.splitlines() if line.startswith("$ ")]
        elif info == "sh":
            pending = ""
            for line in block.splitlines():
                if line.endswith("\\"):
                    pending += line[:-1] + " "
                    continue
                line, pending = pending + line, ""
                if line.strip() and not line.lstrip().startswith("#"):
                    commands.append(line)
    return commands


def python_blocks(text):
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.M | re.S)


def is_setup(command):
    return command.split("#")[0].strip() in SETUP_COMMANDS


def rendered_gold(path):
    if not check(os.path.isfile(path), f"{os.path.basename(path)} rendered"):
        return
    pixels = np.asarray(oiio.ImageBuf(path).get_pixels(oiio.FLOAT))[..., :3]
    red, blue = pixels[..., 0].mean(), pixels[..., 2].mean()
    check(pixels.max() > 0.3 and red > 1.05 * blue,
          f"{os.path.basename(path)} is lit and gold-tinted (max {pixels.max():.3f}, mean R {red:.3f}, B {blue:.3f})")


def main():
    readme = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "README.md")
    with open(readme, encoding="utf-8") as f:
        text = f.read()
    commands = readme_commands(text)
    skipped = [c for c in commands if is_setup(c)]
    commands = [c for c in commands if not is_setup(c)]
    check(len(skipped) == 2, f"the two set-up commands found and skipped: {skipped}")
    check(any(c.startswith("cmake --install build --prefix ~/.local") for c in commands),
          "the README installs into ~/.local")
    with tempfile.TemporaryDirectory(prefix="libbrdf_readme_") as tmp:
        home, work = os.path.join(tmp, "home"), os.path.join(tmp, "work")
        os.makedirs(home)
        os.makedirs(work)
        os.symlink(BUILD, os.path.join(work, "build"))
        script = ["set -e -o pipefail"]
        for number, command in enumerate(commands):
            script += [f"echo '{MARK} {number}' >&2", command]
        path = [p for p in os.environ["PATH"].split(os.pathsep) if not p.rstrip("/").endswith(".local/bin")]
        env = {key: value for key, value in os.environ.items()
               if not key.startswith(("LIBBRDF", "BRDF_", "PYTHON", "BLENDER_USER"))}
        env.update(HOME=home, PATH=os.pathsep.join(path))
        for key in ("XDG_CONFIG_HOME", "XDG_CACHE_HOME", "XDG_DATA_HOME"):
            env.pop(key, None)
        result = subprocess.run(["bash", "-c", "\n".join(script)], cwd=work, env=env, capture_output=True, text=True)
        marks = [int(line.split()[-1]) for line in result.stderr.splitlines() if line.startswith(MARK)]
        last = marks[-1] if marks else -1
        print(result.stdout[-4000:])
        if result.returncode != 0:
            print(result.stderr[-6000:], file=sys.stderr)
        check(result.returncode == 0 and last == len(commands) - 1,
              f"all {len(commands)} README commands exit 0" if result.returncode == 0 else
              f"README command {last + 1} of {len(commands)} exits {result.returncode}: {commands[last] if last >= 0 else '?'}")
        # The Python blocks, by Debian's python3 with the module from the temporary ~/.local only.
        for number, code in enumerate(python_blocks(text)):
            ran = subprocess.run(["/usr/bin/python3", "-c", code], cwd=work, env=dict(env, MPLBACKEND="Agg"),
                                 capture_output=True, text=True)
            check(ran.returncode == 0, f"README python block {number + 1} runs (exit {ran.returncode}: {ran.stderr[-500:]})")
        gold = os.path.join(work, "gold")
        rendered_gold(os.path.join(gold, "gold_povray.png"))
        rendered_gold(os.path.join(gold, "gold_blender.png"))
        check(os.path.isfile(os.path.join(home, ".local", "bin", "brdf")), "brdf installed into the temporary ~/.local/bin")
    checks.finish(f"ok: every README command runs verbatim ({len(commands)} commands, 2 set-up commands skipped)")


if __name__ == "__main__":
    main()
