#!/usr/bin/python3
"""The package as pip installs it (issue 33): the `python` install component of the build, which
is exactly what pyproject.toml puts into the wheel (install.components = ["python"]), installed
into a temporary prefix and imported from a directory outside the source and build trees, with
nothing on PYTHONPATH but that prefix: the files of libbrdf/ (the compiled _core, __init__.py,
mitsuba.py), `import libbrdf` giving `brdf eval`'s value bit for bit, and the package's names
(every public name of _core re-exported, the types reporting the package as their module).
Environment: BRDF_EXE, LIBBRDF_BUILD (the build directory). `pip wheel .` itself compiles the
library from scratch (minutes), so it is checked by hand (docs/mitsuba.md), not here.
"""
import glob
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from checks import check, finish  # noqa: E402

BRDF = os.environ["BRDF_EXE"]
BUILD = os.environ["LIBBRDF_BUILD"]
ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SURFACE = ["--material", "Au", "--sigma-s", "0.05", "--lc", "2", "--wavelength", "0.55"]

with tempfile.TemporaryDirectory() as prefix, tempfile.TemporaryDirectory() as elsewhere:
    install = subprocess.run(["cmake", "--install", BUILD, "--component", "python", "--prefix", prefix],
                             capture_output=True, text=True)
    check(install.returncode == 0, f"cmake --install --component python: {install.stderr.strip()[-300:]}")
    # The package sits in the interpreter's layout under the prefix (lib/pythonX.Y/site-packages;
    # at the root of a wheel): its parent goes on PYTHONPATH.
    found = glob.glob(os.path.join(prefix, "**", "libbrdf", "__init__.py"), recursive=True)
    check(len(found) == 1, f"one libbrdf package under the prefix: {found}")
    site = os.path.dirname(os.path.dirname(found[0])) if found else prefix
    files = sorted(os.path.relpath(p, site) for p in glob.glob(os.path.join(site, "**", "*"), recursive=True)
                   if os.path.isfile(p))
    expected_python = sorted(os.path.join("libbrdf", os.path.basename(p)) for p in glob.glob(os.path.join(ROOT, "python", "libbrdf", "*.py")))
    core = [f for f in files if f.startswith(os.path.join("libbrdf", "_core.")) and f.endswith(".so")]
    check(len(core) == 1 and sorted(set(files) - set(core)) == expected_python,
          f"the component holds libbrdf/_core*.so and python/libbrdf/*.py, nothing else: {files}")
    script = (
        "import libbrdf, libbrdf._core as core\n"
        "print(repr(libbrdf.Model('mbk', material='Au', sigma_s=0.05, lc=2.0, wavelength=0.55)(30, 40, 180)))\n"
        "print(libbrdf.__file__)\n"
        "print(sorted(n for n in dir(core) if not n.startswith('_')) == sorted(libbrdf.__all__)"
        " and all(hasattr(libbrdf, n) for n in libbrdf.__all__))\n"
        "print(libbrdf.Model.__module__, libbrdf.InvalidArgument.__module__)\n")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = site
    run = subprocess.run([sys.executable, "-c", script], cwd=elsewhere, env=env, capture_output=True, text=True)
    check(run.returncode == 0, f"import libbrdf from the installed prefix: {run.stderr.strip()[-300:]}")
    lines = run.stdout.splitlines() if run.returncode == 0 else ["", "", "", ""]
    cli = subprocess.run([BRDF, "eval", "--model", "mbk", *SURFACE, "--at", "30,40,180"], capture_output=True, text=True, check=True)
    cli_value = float(cli.stdout.splitlines()[1].split(",")[3])
    check(lines[0] != "" and float(lines[0]) == cli_value, f"installed libbrdf.Model = brdf eval bit for bit: {lines[0]} vs {cli_value!r}")
    check(lines[1].startswith(site), f"imported from the prefix, not a source or build tree: {lines[1]}")
    check(lines[2] == "True", "every public name of libbrdf._core is re-exported by libbrdf")
    check(lines[3] == "libbrdf libbrdf", f"the types report the package as their module: {lines[3]}")

finish("ok: the python install component (the wheel's content) imports and computes outside the trees")
