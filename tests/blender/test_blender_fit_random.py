"""FIT mode at seeded random suns, cameras and surfaces, in a real Blender, pixel by pixel against
`brdf eval` (issue 33, deliverable 2).

The scenes are test_blender_random.py's (random_scene: the sun and the camera uniform on the sphere
less than 140 deg apart; mbk, bk or bk-modified; sigma_s 0.005-2 um, l_c 0.5-10 um; a named metal,
BK7 or random n + i kappa; a turned UV sphere seen orthographically, zoomed on polished lobes), with
point sampling (1 sample per pixel at its centre). Compared: every channel of every pixel in the
object (mask eroded by 2) with theta_i, theta_s <= 70 deg and every channel above 1% of the render's
maximum; relative error |render - f_r cos(theta_i) E| / (f_r cos(theta_i) E).

What is asserted, per render (tests/fit_bands.py), with the band of sun-camera angle the scene falls
in (exporters/fit.h kSunAngleBands: 0-30, 30-60, 60-90, 90-120, 120-140 deg) and the error the
description states for that band (fit.error.by_sun_angle; EEVEE: fit.eevee.error.by_sun_angle):
below ASSERTED_BELOW_DEG the issue's targets (median <= 5%, p95 <= 20%) whatever the fit states;
above it the targets where the stated band meets them, elsewhere rendered median <= 1.5 x stated
median + 2% (the error the add-on's panel shows must be the one rendered). EEVEE: the stated median
only (ASSERTED_BELOW_DEG).
Measured (docs/fit.md): Cycles, 8 scenes of the default seed, medians 0.2-2.9% (p95 <= 15%) below
110 deg; the two scenes at ~128 deg 14% and 23% (stated for 120-140 deg: 14% and 35%).

Usage: test_blender_fit_random.py [--engines CYCLES[,BLENDER_EEVEE]] [--scenes N] [--seed S] [--keep DIR]
  (env BRDF_EXE, LIBBRDF_ROOT; Debian's Blender 3.4; EEVEE without an OpenGL context: skipped, exit 77)
"""

import argparse
import math
import os
import sys

import numpy as np

import blender_test_env  # noqa: F401  (sys.path)
from blender_test_env import BRDF, ROOT
import checks  # noqa: E402
import fit_bands  # noqa: E402
import render_check  # noqa: E402
from checks import check  # noqa: E402
from package import addon_zip  # noqa: E402
from test_blender_random import MAX_ANGLE_DEG, random_scene  # noqa: E402

# Below this sun-camera angle the targets are asserted for every surface (docs/fit.md: Cycles'
# stated p95 per band <= 13% there on the surveyed surfaces); above it the stated band decides.
# EEVEE: only its stated median is checked (its stated p95 is the exact GGX's; EEVEE's LTC lighting
# renders longer tails: bk-modified Cu at 86 deg, stated 4.2% / 9.6%, rendered 4.5% / 138%).
ASSERTED_BELOW_DEG = {"CYCLES": 90.0, "BLENDER_EEVEE": 0.0}
BLENDER = os.environ.get("BLENDER", "blender")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--engines", default="CYCLES")
    parser.add_argument("--scenes", type=int, default=8)
    parser.add_argument("--seed", type=int, default=int(os.environ.get("LIBBRDF_TEST_SEED", "20261204")))
    parser.add_argument("--resolution", type=int, default=128)
    parser.add_argument("--keep")
    args = parser.parse_args()
    return render_check.in_folder(args.keep, "libbrdf_fit_random_", lambda tmp: run(args, tmp))


def run(args, tmp):
    engines = args.engines.split(",")
    renders, scenes = [], []
    for index in range(args.scenes):
        rng = np.random.default_rng(args.seed + index)
        sun, camera, material, ortho_scale, target, rotation = random_scene(rng)
        for number, engine in enumerate(engines):
            name = f"scene{index:02d}_{engine.lower()}"
            renders.append({
                "name": name, "output": os.path.join(tmp, name + ".exr"),
                "resolution": [args.resolution, args.resolution], "samples": 1, "engine": engine,
                "camera": {"direction": camera.tolist(), "ortho_scale": ortho_scale, "target": target},
                # EEVEE's sun needs a small disc (tests/blender/test_blender_fit.py); Cycles' is exact.
                "sun": {"direction": sun.tolist(), "strength": 1.0, "color": [1.0, 1.0, 1.0],
                        "angle_deg": 0.526 if engine != "CYCLES" else 0.0, "shadow": False},
                "world": [0.0, 0.0, 0.0], "passes": ["normal"], "keep_objects": number > 0,
                "objects": [{"shape": "sphere", "rotation_deg": rotation, "material": dict(material, mode="FIT")}]})
            scenes.append((index, engine, material))
    results = render_check.run_blender_job(tmp, renders, BLENDER, BRDF, ROOT, addon_zip,
                                           " (rerun with --engines CYCLES)" if "BLENDER_EEVEE" in engines else "")
    print(f"     Blender {results[0]['blender']}, seed {args.seed}, {args.scenes} scenes, engines {args.engines}")
    table = []
    for render, result, (index, engine, material) in zip(renders, results, scenes):
        passes = render_check.read_passes(render["output"])
        check(bool(np.all(np.isfinite(passes["Combined"]))), f"{render['name']}: every pixel finite")
        normals = passes["Normal"][:, :, :3]
        mask = render_check.erode(np.linalg.norm(normals, axis=2) > 0.5, 2)
        description, model, channels = render_check.description_surface(result["materials"][0]["description"])
        light, view = np.array(result["sun_direction"]), np.array(result["camera_direction"])
        angle = math.degrees(math.acos(float(np.clip(light @ view / np.linalg.norm(light) / np.linalg.norm(view), -1, 1))))
        predicted, (ti, ts, _) = render_check.predicted_radiance(BRDF, model, channels, normals[mask], light, view,
                                                                 1.0, [1.0, 1.0, 1.0])
        rendered = passes["Combined"][:, :, :3][mask]
        # The floor: 1% of the maximum over theta_i, theta_s <= 80 deg, as the fit's stated measure takes it.
        peak = predicted[(ti <= fit_bands.PEAK_ANGLE_DEG) & (ts <= fit_bands.PEAK_ANGLE_DEG)].max()
        selected = (ti <= MAX_ANGLE_DEG) & (ts <= MAX_ANGLE_DEG) & (predicted.min(axis=1) > 0.01 * peak)
        surface = material["material"] or f"n {material['n']:g} + {material['k']:g}i"
        what = (f"{render['name']} (FIT, {engine}, Blender {result['blender']}): {model} {surface} sigma_s "
                f"{material['sigma_s']:g} l_c {material['lc']:g}, sun-camera {angle:.1f} deg")
        if not check(selected.sum() >= 30, f"{what}: {selected.sum()} pixels to compare (>= 30)"):
            continue
        rel = (np.abs(rendered - predicted)[selected] / predicted[selected]).ravel()
        median, p95 = float(np.median(rel)), float(np.percentile(rel, 95))
        print(f"     {what}: {selected.sum()} pixels, median {median:.2%}, p95 {p95:.2%}")
        fit = description["fit"] if engine == "CYCLES" else description["fit"]["eevee"]
        stated = fit_bands.check_render(what + f", {selected.sum()} pixels", median, p95, angle,
                                        fit["error"].get("by_sun_angle", []), ASSERTED_BELOW_DEG[engine],
                                        targets_where_stated=engine == "CYCLES")
        if stated is not None:
            table.append((render["name"], engine, angle, int(selected.sum()), median, p95,
                          f"{stated['from_deg']:g}-{stated['to_deg']:g} deg", stated["median"], stated["p95"]))
    print("     render | engine | sun-camera deg | pixels | median | p95 | band | stated median | stated p95")
    for row in table:
        print(f"     {row[0]} | {row[1]} | {row[2]:.1f} | {row[3]} | {row[4]:.2%} | {row[5]:.2%} | {row[6]} | "
              f"{row[7]:.2%} | {row[8]:.2%}")
    checks.finish("FIT at random suns: the targets where asserted, the stated error elsewhere")


if __name__ == "__main__":
    sys.exit(main())
