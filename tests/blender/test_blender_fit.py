"""FIT mode (issue 10, item 2) rendered by the real Blender, Cycles and EEVEE, per pixel against
`brdf eval`, in the issue's one-sun scene: an orthographic sphere of radius 1.2, one sun (about 43
deg from the camera), black world, no shadows needed (a convex object).

For each surface (n = 1.5 + 1i at l_c = 2 um, sigma_s = 0.02 and 0.2 um, and sigma_s = 1.0 um at
l_c = 5 um; Au polished, intermediate and rough; BK7) the add-on builds the FIT material (its fitted
Beckmann lobes for Cycles, GGX lobes for EEVEE) and the chosen engine renders it (Cycles: 1 sample,
a sun of angle 0 makes the direct light exact at each pixel centre; EEVEE: sun angle 0.526 deg).
Compared: each channel of every pixel inside the sphere (mask eroded by 2 pixels) with theta_i,
theta_s <= 70 deg and every channel above 1% of the render's maximum, against the exact radiance f_r
cos(theta_i) E C. Asserted per surface: >= 200 pixels, every pixel finite; median relative error <=
5%, 95th percentile <= 20% (the issue's targets) for Cycles everywhere and for EEVEE on the narrow
lobes (polished n = 1.5 + 1i and Au, BK7, intermediate Au).

EEVEE's broad lobes are measured and printed, not asserted: Blender 3.4's EEVEE lights a GGX Glossy
BSDF by a sun through its LTC tables, which depart from GGX between roughness ~0.4 and ~0.85 (a
white Glossy on this sphere under this sun against the analytic GGX, median / 5th percentile of
EEVEE / GGX where GGX exceeds 1% of its maximum: roughness 0.3 1.01 / 0.97, 0.4 0.98 / 0.83, 0.45
0.91 / 0.45, 0.5 0.78 / 0.00, 0.6 0.81 / 0.06, 0.75 0.98 / 0.49, 0.85 1.02 / 0.80, 1.0 1.04 / 0.97;
a sun of 5 or 20 deg keeps the dip: 0.5 0.78 / 0.01, 0.79 / 0.09; Cycles 1.000 / 1.000; a Diffuse
BSDF 0.999 / 0.999), and broad MBK lobes need roughness 0.45-0.65 (alpha 0.2-0.4).

Fitting to what EEVEE renders instead of GGX does not reach the targets either
(tools/calibrate/eevee_ggx_span.py: white GGX lobes rendered by EEVEE at roughness 0.025..1 in steps
of 0.025 and a Diffuse, under this sun and 4 others 17-63 deg from the camera; signed least squares
of lobes x Bernstein(N.V) colours, as the fit's, on 4 suns, measured on the 5th as here; median /
p95 on this sun, then the worst median and p95 over the 5 suns held out): n = 1.5 + 1i sigma_s 0.2
um 2.7% / 12%, worst 4.3% / 62%; sigma_s 1.0 um, l_c 5 um 6.5% / 18%, worst 14.5% / 94%; Au sigma_s
0.5 um, l_c 3 um 4.4% / 14%, worst 6.6% / 36%. Fitted on all 5 suns at once, the rough n = 1.5 + 1i
lobe still has medians 5.3-11.6% (p95 18-32%): no mixture of EEVEE's lobes with colours in N.V
follows MBK under every sun, while the analytic GGX lobes at the same pixels do (held out, this sun:
0.5% / 1.4%, 3.0% / 11%, 1.5% / 3.5%). With only the lobes EEVEE renders within ~10% of GGX
(roughness <= 0.375 or >= 0.875, Diffuse): 4.4% / 19%, 12.8% / 34%, 9.8% / 26% on this sun.

So EEVEE's fit keeps its GGX lobes out of roughness (0.375, 0.875) (exporters/blender.h), and what it
states is what EEVEE renders: asserted for the broad surfaces, rendered median <= 1.5 x the stated
median + 2% (measured, rendered / stated: 14.7% / 17.2%, 13.4% / 14.4%, 25.9% / 21.7%; with lobes in
the band the rendered medians were 5.7%, 36%, 20%, and the rough surface's stated one 10.7%).

Usage: test_blender_fit.py [--keep DIR] [--engines CYCLES,BLENDER_EEVEE]  (ctest: one engine per test)
  (env BRDF_EXE, LIBBRDF_ROOT; EEVEE without an OpenGL context is reported and skipped)
"""

import argparse
import json
import os
import shutil
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.environ.get("LIBBRDF_ROOT", os.path.normpath(os.path.join(HERE, "..", "..")))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "blender_addon"))
sys.path.insert(0, os.path.join(ROOT, "tools", "report"))
import brdfcli  # noqa: E402
import checks  # noqa: E402
import render_check  # noqa: E402
from checks import check  # noqa: E402
from package import addon_zip  # noqa: E402

BRDF = os.environ.get("BRDF_EXE", "brdf")
BLENDER = os.environ.get("BLENDER", "blender")
MEDIAN_LIMIT, P95_LIMIT = 0.05, 0.20
WAVELENGTHS = (0.65, 0.55, 0.45)

# (name, add_material arguments). n = 1.5 + 1i: the table; Au and BK7 polished to rough.
SURFACES = [
    ("n1.5+1i_s0.02", dict(model="mbk", n=1.5, k=1.0, sigma_s=0.02, lc=2.0)),
    ("n1.5+1i_s0.2", dict(model="mbk", n=1.5, k=1.0, sigma_s=0.2, lc=2.0)),
    ("n1.5+1i_s1.0_lc5", dict(model="mbk", n=1.5, k=1.0, sigma_s=1.0, lc=5.0)),
    ("Au_s0.02", dict(model="mbk", material="Au", sigma_s=0.02, lc=2.0)),
    ("Au_s0.5_lc3", dict(model="mbk", material="Au", sigma_s=0.5, lc=3.0)),
    ("BK7_s0.1", dict(model="mbk", material="BK7", sigma_s=0.1, lc=2.0)),
    # Chosen here: intermediate gold (the report's au-s0.15, sigma_s/lambda = 0.15 at 0.55 um).
    ("Au_s0.08", dict(model="mbk", material="Au", sigma_s=0.08, lc=2.0)),
]
# EEVEE meets the targets on the narrow lobes only (its GGX departs from GGX at roughness
# ~0.4-0.85, and no mixture of its lobes follows the broad ones: see above); elsewhere its error
# is printed as MEASURED.
EEVEE_ASSERTED = {"n1.5+1i_s0.02", "Au_s0.02", "BK7_s0.1", "Au_s0.08"}
CAMERA = {"direction": [0.0, -1.0, 0.3], "ortho_scale": 2.6}
SUN = {"direction": [0.7, -0.7, 0.3], "strength": 2.0, "color": [1.0, 0.95, 0.9], "shadow": False}
# The polished halo covers a few degrees around the half vector: finer pixels for it.
RESOLUTION = {"s0.02": [224, 224], "s0.08": [128, 128]}
DEFAULT_RESOLUTION = [96, 96]


def renders(out, engines):
    jobs = []
    for name, surface in SURFACES:
        material = dict(surface, mode="FIT", wavelengths=list(WAVELENGTHS), name=f"fit {name}")
        for index, engine in enumerate(engines):
            sun = dict(SUN, angle_deg=0.526) if engine != "CYCLES" else dict(SUN, angle_deg=0.0)
            jobs.append({"name": f"{name}_{engine.lower()}", "surface": name, "engine": engine,
                         "output": os.path.join(out, f"{name}_{engine.lower()}.exr"),
                         "resolution": next((r for key, r in RESOLUTION.items() if key in name), DEFAULT_RESOLUTION),
                         "samples": 1, "camera": CAMERA, "sun": sun, "world": [0.0, 0.0, 0.0],
                         "passes": ["normal"], "keep_objects": index > 0,  # same material, other engine
                         "objects": [{"shape": "sphere", "scale": [1.2, 1.2, 1.2], "material": material}]})
    return jobs


def reference(surface, normals, light, view, strength, colour):
    """Exact radiance f_r cos(theta_i) E C per pixel and channel from `brdf eval`, and the angles."""
    ti, ts, ps = render_check.pixel_angles(normals, light, view)
    lit = (ti < 89.9) & (ts < 89.9)
    out = np.zeros((normals.shape[0], 3))
    params = {key: surface[key] for key in ("material", "n", "k", "sigma_s", "lc") if key in surface}
    for c, wavelength in enumerate(WAVELENGTHS):
        f = brdfcli.evaluate(BRDF, surface["model"], ti[lit], ts[lit], ps[lit], wavelength=wavelength, **params)
        out[lit, c] = f * np.cos(np.radians(ti[lit])) * strength * colour[c]
    return out, ti, ts


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--keep", help="keep renders and materials in this folder")
    parser.add_argument("--engines", default="CYCLES,BLENDER_EEVEE")
    args = parser.parse_args()
    tmp = args.keep or tempfile.mkdtemp(prefix="libbrdf_blender_fit_")
    os.makedirs(tmp, exist_ok=True)
    try:
        return run(tmp, args.engines.split(","))
    finally:
        if not args.keep:
            shutil.rmtree(tmp, ignore_errors=True)


def run(tmp, engines):
    jobs = renders(tmp, engines)
    results = render_check.run_blender_job(tmp, jobs, BLENDER, BRDF, ROOT, addon_zip,
                                           " (rerun with --engines CYCLES)" if "BLENDER_EEVEE" in engines else "")
    surfaces = dict(SURFACES)
    table = []
    for render, result in zip(jobs, results):
        passes = render_check.read_passes(render["output"])
        combined = passes["Combined"][:, :, :3]
        check(bool(np.all(np.isfinite(combined))), f"{render['name']}: every pixel finite")
        normals = passes["Normal"][:, :, :3]
        mask = render_check.erode(np.linalg.norm(normals, axis=2) > 0.5, 2)
        light, view = np.array(result["sun_direction"]), np.array(result["camera_direction"])
        exact, ti, ts = reference(surfaces[render["surface"]], normals[mask], light, view,
                                  result["sun_strength"], result["sun_color"])
        rendered = combined[mask]
        selected = (ti <= 70) & (ts <= 70) & (exact.min(axis=1) > 0.01 * exact.max())
        rel = (np.abs(rendered - exact)[selected] / exact[selected]).ravel()
        if not check(selected.sum() >= 200, f"{render['name']}: {selected.sum()} pixels selected, want >= 200"):
            continue
        median, p95 = float(np.median(rel)), float(np.percentile(rel, 95))
        with open(result["materials"][0]["description"], encoding="utf-8") as f:
            fit = json.load(f)["fit"]
        stored = fit["eevee"]["error"] if render["engine"] != "CYCLES" else fit["error"]
        table.append((render["surface"], render["engine"], int(selected.sum()), median, p95, stored["median"], stored["p95"]))
        if render["engine"] != "CYCLES" and render["surface"] not in EEVEE_ASSERTED:
            # Known gap (the targets are reported, not asserted): EEVEE's sun-lit GGX departs from GGX
            # at roughness ~0.4-0.85 (module docstring), where the broad lobes would be. Its lobes stay
            # out of that band, so the error the JSON and the panel state is the one EEVEE renders:
            # asserted to within 1.5x + 2% (the median; with lobes in the band it was 10.7% stated,
            # 36% rendered for the rough n = 1.5 + 1i surface).
            print(f"     MEASURED (EEVEE, targets not asserted) {render['name']}: median {median:.2%}, p95 {p95:.2%}")
            check(median <= 1.5 * stored["median"] + 0.02,
                  f"{render['name']}: EEVEE renders the error its fit states: median {median:.2%} <= 1.5 x "
                  f"{stored['median']:.2%} + 2%")
            continue
        check(median <= MEDIAN_LIMIT and p95 <= P95_LIMIT,
              f"{render['name']}: FIT vs brdf eval over {selected.sum()} pixels x 3 channels: median {median:.2%} "
              f"(<= {MEDIAN_LIMIT:.0%}), p95 {p95:.2%} (<= {P95_LIMIT:.0%}); the fit's own measure: median "
              f"{stored['median']:.2%}, p95 {stored['p95']:.2%}")
    print("     surface | engine | pixels | median | p95 | fit's stored median | p95")
    for row in table:
        print(f"     {row[0]} | {row[1]} | {row[2]} | {row[3]:.2%} | {row[4]:.2%} | {row[5]:.2%} | {row[6]:.2%}")
    checks.finish("Blender FIT renders within the issue's targets")


if __name__ == "__main__":
    sys.exit(main())
