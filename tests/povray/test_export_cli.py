#!/usr/bin/python3
"""The `brdf export povray` contract (issue #4).

Bad input exits 2 with one line naming the parameter and writes nothing. A good export writes
DIR/NAME.inc only (no temporary left), and the include behaves as POV-Ray includes should: it can
be included twice (guard), restores the scene's #version, takes NAME_Irradiance (float or rgb)
declared before it as the emission scale of NAME_Exact, and NAME_Fit renders under a light.

Environment (set by ctest): BRDF_EXE, LIBBRDF_ROOT, LIBBRDF_BUILD.
"""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(os.environ["LIBBRDF_ROOT"])
BRDF = os.environ["BRDF_EXE"]
OUT = Path(os.environ.get("LIBBRDF_BUILD", "/tmp")) / "povray_test" / "export_cli"
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "tests"))
import checks  # noqa: E402
import povray_common as pc  # noqa: E402
from checks import check  # noqa: E402

checks.print_passes = False  # the messages below name the problem

GOOD = ["--model", "mbk", "--material", "Au", "--sigma-s", "0.03", "--lc", "2", "--light-dir", "-1,1,-1",
        "--view-dir", "0,0,-1", "--name", "Gold", "--resolution", "64"]


def with_option(args, option, value):
    """GOOD with `option` set to `value` (None: removed)."""
    out = list(args)
    if option in out:
        i = out.index(option)
        del out[i:i + 2]
    if value is not None:
        out += [option, value]
    return out


def check_bad_input():
    cases = [
        ("light-dir", with_option(GOOD, "--light-dir", "0,0,0")),
        ("light-dir", with_option(GOOD, "--light-dir", "0,1")),
        ("light-dir", with_option(GOOD, "--light-dir", "0,1,nan")),
        ("light-dir", with_option(GOOD, "--light-dir", "0,0,1")),  # opposite to the view
        ("view-dir", with_option(GOOD, "--view-dir", "x,0,1")),
        ("name", with_option(GOOD, "--name", "1Gold")),
        ("name", with_option(GOOD, "--name", "Gold-Leaf")),
        ("resolution", with_option(GOOD, "--resolution", "300")),
        ("resolution", with_option(GOOD, "--resolution", "4")),
        ("model", with_option(GOOD, "--model", "fresnel")),
        ("model", with_option(GOOD, "--model", "nonsense")),
        ("wavelength", with_option(GOOD, "--wavelength", "0.5,0.6")),
        ("sigma_s", with_option(GOOD, "--sigma-s", "-1")),
    ]
    for parameter, args in cases:
        directory = OUT / "bad"
        shutil.rmtree(directory, ignore_errors=True)
        run = subprocess.run([BRDF, "export", "povray", *args, "-o", str(directory)], capture_output=True, text=True)
        lines = run.stderr.strip().splitlines()
        label = " ".join(args[-2:]) if parameter not in ("light-dir", "view-dir") else f"{parameter} {args}"
        check(run.returncode == 2, f"{label}: exit {run.returncode}, want 2 ({run.stderr.strip()})")
        check(len(lines) == 1 and parameter.replace("_", "-") in lines[0].replace("_", "-"),
              f"{label}: want one line naming {parameter}, got {lines}")
        check(not directory.exists() or not any(directory.iterdir()), f"{label}: files written despite the error")
    missing = subprocess.run([BRDF, "export", "povray", *with_option(GOOD, "--light-dir", None), "-o", str(OUT)],
                             capture_output=True, text=True)
    check(missing.returncode == 2 and "light-dir" in missing.stderr, f"missing --light-dir: {missing.stderr.strip()}")


def check_include_in_povray():
    directory = OUT / "good"
    shutil.rmtree(directory, ignore_errors=True)
    run = subprocess.run([BRDF, "export", "povray", *GOOD, "-o", str(directory)], capture_output=True, text=True)
    if not check(run.returncode == 0, f"good export failed: {run.stderr.strip()}"):
        return
    check(sorted(p.name for p in directory.iterdir()) == ["Gold.inc"],
          f"export should leave only Gold.inc, found {sorted(p.name for p in directory.iterdir())}")
    check("wrote" in run.stdout and "max error" in run.stdout, f"export summary missing: {run.stdout!r}")

    def scene(irradiance_declaration, texture, light=""):
        path = directory / f"scene_{len(list(directory.glob('scene_*')))}.pov"
        path.write_text(f"""#version 3.7;
global_settings {{ assumed_gamma 1.0 ambient_light 0 }}
{irradiance_declaration}
#include "libbrdf.inc"
#include "Gold.inc"
#include "Gold.inc"  // a second inclusion must be a no-op
#if (version != 3.7) #error "Gold.inc did not restore #version" #end
Brdf_Ortho_Camera(Gold_View_Direction, <0, 0, 0>, 2.3, 2.3)
{light}
sphere {{ 0, 1 texture {{ {texture} }} }}
""")
        return path

    size = 96
    renders = {}
    for key, declaration, texture, light in [
            ("unit", "", "Gold_Exact", ""),
            ("rgb", "#declare Gold_Irradiance = rgb <1, 2, 0.5>;", "Gold_Exact", ""),
            ("fit", "", "Gold_Fit", "Brdf_Sun(Gold_Light_Direction, rgb 1)")]:
        try:
            renders[key] = pc.run_povray(scene(declaration, texture, light), directory / f"{key}.exr", size, size,
                                         [directory])
        except RuntimeError as error:
            check(False, f"{key}: {error}")
    if len(renders) != 3:
        return
    unit, rgb = renders["unit"][..., :3], renders["rgb"][..., :3]
    lit = unit > 1e-3 * unit.max()
    for c, scale in enumerate([1.0, 2.0, 0.5]):
        ratio = rgb[..., c][lit[..., c]] / unit[..., c][lit[..., c]]
        # Two half-float roundings (OpenEXR output), each <= 2^-11 relative.
        check(ratio.size >= 20 and np.abs(ratio - scale).max() < 2.5e-3 * scale,
              f"Gold_Irradiance rgb: channel {c} scaled by {ratio.min():.4g}..{ratio.max():.4g} over {ratio.size} "
              f"pixels, want {scale}")
    fit = renders["fit"][..., :3]
    check(np.all(np.isfinite(fit)) and fit.max() > 0, "Gold_Fit renders black or non-finite")
    print(f"  include: guard, #version, rgb irradiance ok; fit max radiance {fit.max():.3g}, exact {unit.max():.3g}")


def main():
    check_bad_input()
    check_include_in_povray()
    checks.finish("ok: brdf export povray contract")


if __name__ == "__main__":
    main()
