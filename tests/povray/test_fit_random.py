#!/usr/bin/python3
"""NAME_Fit (POV-Ray's fitted Blinn and Phong lobes) at seeded random suns, cameras and surfaces,
rendered by the real POV-Ray against `brdf eval` (issue 33, deliverable 2).

Scenes: tests/blender/test_blender_random.py's random_scene (the sun and the camera uniform on the
sphere less than 140 deg apart; mbk, bk or bk-modified; sigma_s 0.005-2 um log-uniform, l_c 0.5-10 um;
a named metal, BK7 or random n + i kappa), the same seed as the Blender tests; the view zoomed on the
specular point to the lobe's width (its diffraction width or its rms-slope width, the larger). `brdf export povray` writes Material.inc for that sun and camera;
povray/scenes/object_check.pov renders the unit sphere under Brdf_Sun with Material_Fit (Pass 2)
and the normal pass twice (coarse and fine, decoded to world normals), no antialiasing. Compared:
every channel of every pixel inside the sphere (mask eroded by 2) with theta_i, theta_s <= 70 deg and
every channel above 1% of the maximum, relative error against f_r cos(theta_i) E.

Asserted (tests/fit_bands.py), with the include's stated error for the scene's band of sun-camera
angle (NAME_Fit_Sun_Angle_Deg, NAME_Fit_Error_Median_By_Angle / _P95_By_Angle): below
ASSERTED_BELOW_DEG the issue's targets (median <= 5%, p95 <= 20%); above it the targets where the
stated band meets them, elsewhere rendered median <= 1.5 x stated median + 2%.
Environment (set by ctest): BRDF_EXE, LIBBRDF_ROOT, LIBBRDF_BUILD. Usage: [--scenes N] [--seed S]
"""
import argparse
import math
import os
import re
import sys
from pathlib import Path

import numpy as np

ROOT = Path(os.environ["LIBBRDF_ROOT"])
BRDF = os.environ["BRDF_EXE"]
OUT = Path(os.environ.get("LIBBRDF_BUILD", "/tmp")) / "povray_test" / "fit_random"
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "tests" / "blender"))
import checks  # noqa: E402
import fit_bands  # noqa: E402
import povray_common as pc  # noqa: E402
from checks import check  # noqa: E402
from test_blender_random import MAX_ANGLE_DEG, random_scene  # noqa: E402

SCENE = ROOT / "povray" / "scenes" / "object_check.pov"
WAVELENGTHS = [0.65, 0.55, 0.45]
SIZE = 160
# Below this sun-camera angle the targets are asserted for every surface (docs/fit.md); above it
# the include's stated band decides.
ASSERTED_BELOW_DEG = 90.0


def stated_bands(header, name="Material"):
    """The include's error per band of sun-camera angle: [{from_deg, to_deg, median, p95}]."""
    def array(suffix):
        found = re.search(rf"#declare {name}_{suffix} = array\[\d+\] \{{([^}}]*)\}};", header)
        return [float(v) for v in found.group(1).split(",")] if found else []
    edges, medians, p95s = array("Fit_Sun_Angle_Deg"), array("Fit_Error_Median_By_Angle"), array("Fit_Error_P95_By_Angle")
    if not (len(edges) == len(medians) + 1 == len(p95s) + 1):
        return []
    return [{"from_deg": edges[i], "to_deg": edges[i + 1], "median": medians[i], "p95": p95s[i]} for i in range(len(medians))]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--scenes", type=int, default=8)
    parser.add_argument("--seed", type=int, default=int(os.environ.get("LIBBRDF_TEST_SEED", "20261204")))
    args = parser.parse_args()
    rows = []
    for index in range(args.scenes):
        rng = np.random.default_rng(args.seed + index)
        sun, camera, material, ortho_scale, target, _ = random_scene(rng)
        angle = math.degrees(math.acos(float(np.clip(sun @ camera, -1.0, 1.0))))
        params = {key: material[key] for key in ("sigma_s", "lc")}
        params.update(material=material["material"]) if material["material"] else params.update(n=material["n"], k=material["k"])
        model = material["model"]
        surface = material["material"] or f"n {material['n']:g} + {material['k']:g}i"
        what = (f"scene{index:02d} (POV-Ray NAME_Fit): {model} {surface} sigma_s {material['sigma_s']:g} l_c "
                f"{material['lc']:g}, sun-camera {angle:.1f} deg")
        directory = OUT / f"scene{index:02d}"
        directory.mkdir(parents=True, exist_ok=True)
        pc.export_include(BRDF, model, params, sun, camera, "Material", directory)
        bands = stated_bands((directory / "Material.inc").read_text())
        # The view covers the lobe: random_scene's zoom follows its diffraction width (l_c), which a
        # rough lobe exceeds; its width from the surface's rms slope sqrt(2) sigma_s / l_c (8 half
        # widths across, as random_scene's). Framed like this, the render's pixels are the ones the
        # stated error counts (the sphere's pixels above 1% of the maximum), not only its peak.
        width = min(2.3, max(ortho_scale, 8.0 * math.sqrt(2.0) * material["sigma_s"] / material["lc"]))
        centre = target if width < 2.3 else [0.0, 0.0, 0.0]
        view = dict(View_Width=width, Target_X=centre[0], Target_Y=centre[1], Target_Z=centre[2])
        render = {}
        for key, declares in [("fit", dict(Pass=2)), ("coarse", dict(Pass=1, Frequency=1)),
                              ("fine", dict(Pass=1, Frequency=pc.NORMAL_FREQUENCY))]:
            render[key] = pc.run_povray(SCENE, directory / f"{key}.exr", SIZE, SIZE, [directory], dict(view, **declares))
        check(np.all(np.isfinite(render["fit"])), f"{what}: render finite (no NaN/Inf)")
        inner = pc.erode(render["fine"][..., 3] > 0.999, 2)
        normals = pc.decode_normals(render["coarse"], render["fine"])[inner]
        exact, lit = pc.predicted_radiance(BRDF, model, params, WAVELENGTHS, normals, sun, camera, 1.0)
        ti, ts, _ = pc.scatter_angles(normals, sun, camera)
        # The floor: 1% of the maximum over theta_i, theta_s <= 80 deg, as the fit's stated measure takes it
        # (exporters/src/fit.cpp: its scenes stop there; bk's radiance grows without bound at grazing light).
        peak = exact[lit & (ti <= fit_bands.PEAK_ANGLE_DEG) & (ts <= fit_bands.PEAK_ANGLE_DEG)].max()
        selected = lit & (ti <= MAX_ANGLE_DEG) & (ts <= MAX_ANGLE_DEG) & (exact.min(axis=1) > 0.01 * peak)
        if not check(selected.sum() >= 30, f"{what}: {selected.sum()} pixels to compare (>= 30)"):
            continue
        rendered = render["fit"][inner][:, :3]
        rel = (np.abs(rendered - exact)[selected] / exact[selected]).ravel()
        median, p95 = float(np.median(rel)), float(np.percentile(rel, 95))
        print(f"  {what}: {selected.sum()} pixels, median {median:.2%}, p95 {p95:.2%}")
        stated = fit_bands.check_render(what + f", {selected.sum()} pixels", median, p95, angle, bands, ASSERTED_BELOW_DEG)
        if stated is not None:
            rows.append((f"scene{index:02d}", f"{model} {surface} s {material['sigma_s']:g}", angle, int(selected.sum()),
                         median, p95, f"{stated['from_deg']:g}-{stated['to_deg']:g}", stated["median"], stated["p95"]))
    print("  scene | surface | sun-camera deg | pixels | median | p95 | band | stated median | stated p95")
    for r in rows:
        print(f"  {r[0]} | {r[1]} | {r[2]:.1f} | {r[3]} | {r[4]:.2%} | {r[5]:.2%} | {r[6]} | {r[7]:.2%} | {r[8]:.2%}")
    checks.finish(f"ok: POV-Ray NAME_Fit at random suns; renders in {OUT}")


if __name__ == "__main__":
    main()
