#!/usr/bin/python3
"""`cmake --install` puts a usable libbrdf into a prefix.

Installs the build ($LIBBRDF_BUILD) into a fresh temporary prefix, then:
- the files the README promises are there (brdf, headers, CMake package, Python module, POV-Ray
  include, Blender add-on zip);
- tests/install/consumer/, configured and built with Debian's /usr/bin/cmake and only
  CMAKE_PREFIX_PATH=PREFIX, links libbrdf::libbrdf (a static library: its private dependencies
  come through the package's find_dependency) and checks F at normal incidence against
  ((n-1)^2+k^2)/((n+1)^2+k^2), the batch path against the scalar Fresnel function, and
  libbrdf::exporters' POV-Ray slope value against 1/2 + asin(N.d)/pi;
- PREFIX/bin/brdf eval gives F(0) = ((n-1)^2+k^2)/((n+1)^2+k^2) for two indices;
- the installed Python package (PREFIX/lib/python3.X/site-packages/libbrdf) imports from there and agrees.

Usage: test_install.py [--cmake CMAKE]   (env LIBBRDF_BUILD, LIBBRDF_ROOT; CMAKE: the one that
configured the build, for `--install`)
"""
import argparse
import glob
import os
import subprocess
import sys
import tempfile

ROOT = os.environ["LIBBRDF_ROOT"]
BUILD = os.environ["LIBBRDF_BUILD"]
sys.path.insert(0, os.path.join(ROOT, "tests"))
import checks  # noqa: E402
from checks import check  # noqa: E402


def run(command, **kwargs):
    print("$", " ".join(command), flush=True)
    result = subprocess.run(command, capture_output=True, text=True, **kwargs)
    if result.returncode != 0:
        print(result.stdout[-3000:], result.stderr[-3000:], sep="\n", flush=True)
    return result


def normal_incidence_fresnel(n, k):
    return ((n - 1) ** 2 + k ** 2) / ((n + 1) ** 2 + k ** 2)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--cmake", default="cmake")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="libbrdf_install_") as tmp:
        prefix = os.path.join(tmp, "prefix")
        installed = run([args.cmake, "--install", BUILD, "--prefix", prefix])
        if not check(installed.returncode == 0, "cmake --install into a fresh prefix"):
            checks.finish()
        for path in ("bin/brdf", "include/libbrdf/fresnel.h", "include/libbrdf/version.h",
                     "include/exporters/povray.h", "lib/libbrdf.a", "lib/cmake/libbrdf/libbrdfConfig.cmake",
                     "lib/cmake/libbrdf/libbrdfConfigVersion.cmake", "lib/cmake/libbrdf/libbrdfTargets.cmake",
                     "share/libbrdf/povray/libbrdf.inc", "share/libbrdf/blender/libbrdf_materials.zip",
                     "share/libbrdf/tools/plot_bench.py"):
            check(os.path.isfile(os.path.join(prefix, path)), f"installed {path}")
        modules = glob.glob(os.path.join(prefix, "lib", "python3.*", "site-packages", "libbrdf", "_core*.so"))
        check(len(modules) == 1, f"the Python package libbrdf (its _core) under lib/python3.X/site-packages: {modules}")

        # A consumer project, as a user would build one: Debian's cmake, nothing but the prefix.
        consumer_build = os.path.join(tmp, "consumer-build")
        configured = run(["/usr/bin/cmake", "-S", os.path.join(ROOT, "tests", "install", "consumer"),
                          "-B", consumer_build, f"-DCMAKE_PREFIX_PATH={prefix}", "-DCMAKE_BUILD_TYPE=Release"])
        if check(configured.returncode == 0, "consumer configures with find_package(libbrdf) (/usr/bin/cmake)"):
            built = run(["/usr/bin/cmake", "--build", consumer_build])
            if check(built.returncode == 0, "consumer links libbrdf::libbrdf and libbrdf::exporters"):
                ran = run([os.path.join(consumer_build, "consumer")])
                print(ran.stdout, end="")
                check(ran.returncode == 0 and ran.stdout.count("ok  ") == 4,
                      "consumer's checks hold (F(0) formula, batch against scalar, exporters' slope value)")
        # The version file refuses a version the package is not (0.x: same minor version only).
        too_new = run(["/usr/bin/cmake", "-S", os.path.join(ROOT, "tests", "install", "consumer"),
                       "-B", os.path.join(tmp, "consumer-too-new"), f"-DCMAKE_PREFIX_PATH={prefix}",
                       "-DLIBBRDF_WANTED_VERSION=99.0"])
        check(too_new.returncode != 0 and "compatible with requested version" in too_new.stderr,
              "find_package(libbrdf 99.0) is refused by the version file")

        # The installed program, away from the build tree.
        brdf = os.path.join(prefix, "bin", "brdf")
        for n, k in ((1.5, 0.0), (0.5, 2.0)):
            out = run([brdf, "eval", "--model", "fresnel", "--n", str(n), "--k", str(k), "--at", "0,0,180"], cwd=tmp)
            lines = out.stdout.split()
            value = float(lines[-1].split(",")[-1]) if out.returncode == 0 and len(lines) == 2 else float("nan")
            want = normal_incidence_fresnel(n, k)
            check(abs(value - want) <= 1e-14, f"PREFIX/bin/brdf eval fresnel n={n} k={k} at 0,0,180: {value} (expected {want})")

        # The installed Python module, found through the prefix's site-packages alone.
        if modules:
            site = os.path.dirname(os.path.dirname(modules[0]))
            code = ("import libbrdf, sys; print(libbrdf.__file__); "
                    "print(repr(float(libbrdf.Model('fresnel', n=0.5, k=2.0)(0.0, 0.0, 180.0))))")
            py = run(["/usr/bin/python3", "-c", code], env=dict(os.environ, PYTHONPATH=site), cwd=tmp)
            lines = py.stdout.split()
            ok = py.returncode == 0 and len(lines) == 2 and lines[0].startswith(site)
            check(ok and abs(float(lines[1]) - normal_incidence_fresnel(0.5, 2.0)) <= 1e-14,
                  f"installed Python module imports from the prefix and gives F(0): {py.stdout.strip()}")
    checks.finish("ok: the installed prefix builds a consumer, runs brdf and imports libbrdf")


if __name__ == "__main__":
    main()
