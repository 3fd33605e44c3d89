#!/usr/bin/python3
"""tools/render_povray_comparison.py --small end to end (issue #4).

Checks that it writes the promised PNGs and EXRs (readable, finite, non-negative, not blank), that
the difference of mbk against itself is exactly 0, and that the spheres of the comparison EXR
(radiance per unit irradiance after the tool divides its exposure back out) match `brdf eval` at the
analytic sphere normals within 2% (pixels above 1e-3 of the sphere's peak, silhouette excluded):
mbk on every surface and every model on the roughest one (each `brdf eval` call costs a process, and
test_exact_render.py covers the models in depth).

Environment (set by ctest): BRDF_EXE, LIBBRDF_ROOT, LIBBRDF_BUILD.
"""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

ROOT = Path(os.environ["LIBBRDF_ROOT"])
BRDF = os.environ["BRDF_EXE"]
OUT = Path(os.environ.get("LIBBRDF_BUILD", "/tmp")) / "povray_test" / "comparison"
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "tests"))
import checks  # noqa: E402
import povray_common as pc  # noqa: E402
import render_povray_comparison as tool  # noqa: E402
from checks import check  # noqa: E402

checks.print_passes = False  # the messages below name the problem


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    run = subprocess.run(["/usr/bin/python3", str(ROOT / "tools" / "render_povray_comparison.py"), "--brdf", BRDF,
                          "--out", str(OUT), "--small"], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"FAIL: render_povray_comparison.py exited {run.returncode}: {run.stderr.strip()[-2000:]}")
    for name in ["povray_comparison.png", "povray_difference.png"]:
        pixels = oiio.ImageBuf(str(OUT / name)).get_pixels(oiio.FLOAT)
        if check(pixels is not None and pixels.size > 0, f"{name}: unreadable"):
            check(pixels.shape[1] >= 200 and pixels.shape[0] >= 100, f"{name}: {pixels.shape} too small")
            check(pixels[..., :3].std() > 0.02, f"{name}: looks blank")
    radiance = pc.read_exr(OUT / "povray_comparison.exr")
    difference = pc.read_exr(OUT / "povray_difference.exr")
    for name, image in [("comparison", radiance), ("difference", difference)]:
        check(np.all(np.isfinite(image)) and image.min() >= 0 and image.max() > 0, f"povray_{name}.exr: "
              f"values should be finite, >= 0 and not all 0 ({image.min():.3g}..{image.max():.3g})")

    surfaces = tool.surfaces(None, small=True)
    rows, columns = len(tool.MODELS), len(surfaces)  # rows: models, columns: surfaces (as in Blender)
    cell = radiance.shape[1] // columns
    check(radiance.shape[0] == rows * cell, f"comparison EXR {radiance.shape} is not {rows}x{columns} cells")
    check(np.all(difference[:cell, :] == 0), "the mbk row of the difference should be exactly 0")
    # Analytic normals of a unit sphere centred in a cell tool.SPACING world units wide (comparison.pov).
    j, i = np.mgrid[0:cell, 0:cell]
    x = (i + 0.5) / cell * tool.SPACING - tool.SPACING / 2
    y = tool.SPACING / 2 - (j + 0.5) / cell * tool.SPACING
    inside = pc.erode(x * x + y * y < 1.0, 2)
    normals = np.stack([x, y, -np.sqrt(np.clip(1 - x * x - y * y, 0, None))], -1)[inside]
    for c, surface in enumerate(surfaces):
        for m, model in enumerate(tool.MODELS):
            if model != "mbk" and c != len(surfaces) - 1:  # every model on the roughest surface
                continue
            block = radiance[m * cell:(m + 1) * cell, c * cell:(c + 1) * cell, :3][inside]
            predicted, lit = pc.predicted_radiance(BRDF, model, surface["params"], [0.65, 0.55, 0.45], normals,
                                                   tool.LIGHT, tool.VIEW)
            use = lit[:, None] & (predicted > 1e-3 * predicted.max(axis=0))
            rel = np.abs(block - predicted)[use] / predicted[use]
            label = f"{surface['label']} {model}"
            if check(use.sum() >= 20, f"{label}: only {use.sum()} pixel-channels above the floor"):
                print(f"  {label:26s} {int(use.sum()):5d} pixel-channels, max rel error {rel.max():.3%}")
                check(rel.max() <= 0.02, f"{label}: max relative error {rel.max():.3%} > 2%")
    checks.finish(f"ok: POV-Ray comparison renders in {OUT}", f" in {OUT}")


if __name__ == "__main__":
    main()
