#!/usr/bin/python3
"""The report's first screen: every default material (tools/report/materials.json) rendered by
POV-Ray, Blender Cycles and Mitsuba 3 in the same scene, on one exposure, each checked against `brdf eval`.

    render_summary.py --brdf BRDF_EXE --out DIR [--small] [--blender BLENDER]

Scene (the same in the three renderers): a unit sphere with the mbk model (the paper's reference),
one sun of irradiance E = 1 at 40 deg from an orthographic camera (2.3 units across, as
povray/scenes/object_check.pov), black background. POV-Ray draws NAME_Exact of `brdf export
povray` (emission, half-float EXR); Blender draws the add-on's LUT mode (Cycles, one sample at each
pixel centre, emission pass, float EXR); Mitsuba draws the libbrdf.mitsuba plugin (llvm_ad_rgb,
direct light, one sample per pixel, float EXR with each sample's hit position) through
tools/render_mitsuba_comparison.py in the pinned venv of `scripts/python_env.sh mitsuba` (exit 3:
the Mitsuba row says unavailable, with the reason); the specular spike (a delta) is in none.
Error, the same for all: per pixel and channel |L - L_eval| / L_eval, with L_eval = f_r cos(theta_i) E
from `brdf eval` at the pixel's normal (POV-Ray: the analytic sphere; Blender: its Normal pass;
Mitsuba: its position output), over the lit pixels: inside the sphere (mask eroded by 2 pixels),
every channel above 1% of the sphere's maximum. Reported: median and 95th percentile.
Exposure: one for all 3 x 7 images, 1 / (the 99th percentile of the lit pixels' luminance over all
of them); tone curve x/(1+x), sRGB.
Writes DIR/summary/NAME_RENDERER.png (one per cell), DIR/summary_difference.png (|L / L_eval - 1|
per lit pixel of every cell, largest channel, one log colour scale), DIR/summary.csv and keeps the
inputs in DIR/summary/work/ (Mitsuba's cost per sample against its roughconductor:
DIR/summary/work/mitsuba/mitsuba_comparison.json).
"""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "tests" / "blender"))
sys.path.insert(0, str(ROOT / "blender_addon"))
import povray_common as pc  # noqa: E402
from povray_common import brdfcli  # noqa: E402
import render_check  # noqa: E402  (Blender job runner and per-pixel prediction, shared with the tests)
import mitsuba_common  # noqa: E402  (predicted_sun_radiance: brdf eval at Mitsuba's hit positions)
from package import addon_zip  # noqa: E402

MODEL = "mbk"
# POV-Ray world (left-handed, y up): camera on -z. Blender (right-handed, z up): (x, y, z) -> (x, z, y).
POV_LIGHT, POV_VIEW = (0.55, 0.45, -1.0), (0.0, 0.0, -1.0)
BLENDER_LIGHT, BLENDER_VIEW = (0.55, -1.0, 0.45), (0.0, -1.0, 0.0)
# Mitsuba (right-handed, camera on +z, up +y): Blender's (x, y, z) -> (x, z, -y).
MITSUBA_LIGHT, MITSUBA_VIEW = (0.55, 0.45, 1.0), (0.0, 0.0, 1.0)
HALF_WIDTH = 1.15  # object_check.pov's Brdf_Ortho_Camera(..., 2.3, 2.3); Blender ortho_scale 2.3
LIT_FRACTION = 0.01
DIFFERENCE_RANGE = (1e-8, 1e-1)  # the difference figure's log colour scale
EXPOSURE_PERCENTILE = 99.0


def relative_errors(rendered, expected, mask):
    """(pixels, median, p95) of |rendered - expected| / expected per pixel and channel over the lit
    pixels (inside `mask`, every channel above LIT_FRACTION of the maximum)."""
    r, e = rendered[mask][:, :3], expected[mask]
    lit = e.min(axis=1) > LIT_FRACTION * e.max()
    rel = (np.abs(r[lit] - e[lit]) / e[lit]).ravel()
    if rel.size == 0:
        return 0, float("nan"), float("nan")
    return int(lit.sum()), float(np.median(rel)), float(np.percentile(rel, 95))


def render_povray(brdf, surfaces, size, work):
    images = {}
    for s in surfaces:
        directory = work / "povray" / s["name"]
        directory.mkdir(parents=True, exist_ok=True)
        params = dict(material=s["material"], sigma_s=s["sigma_s_um"], lc=s["lc_um"])
        pc.export_include(brdf, MODEL, params, POV_LIGHT, POV_VIEW, "Material", directory)
        image = pc.run_povray(pc.POVRAY_DIR / "scenes" / "object_check.pov", directory / "exact.exr", size, size,
                              [directory], dict(Shape=0, Pass=0, Irradiance=1))
        mask = pc.erode(image[..., 3] > 0.999, 2)
        normals = pc.analytic_sphere_normals(size, HALF_WIDTH)
        expected = np.zeros(image.shape[:2] + (3,))
        expected[mask], _ = pc.predicted_radiance(brdf, MODEL, params, brdfcli.load_materials()["bake_wavelengths_um"],
                                                  normals[mask], POV_LIGHT, POV_VIEW, 1.0)
        images[s["name"]] = (image[..., :3], expected, mask)
        brdfcli.progress(f"POV-Ray {s['name']}: {relative_errors(image, expected, mask)}")
    return images


def render_blender(brdf, blender, surfaces, size, work):
    renders = []
    for s in surfaces:
        material = {"model": MODEL, "material": s["material"], "sigma_s": s["sigma_s_um"], "lc": s["lc_um"],
                    "mode": "LUT"}
        renders.append({"name": s["name"], "output": str(work / "blender" / f"{s['name']}.exr"),
                        "resolution": [size, size], "samples": 1, "engine": "CYCLES",
                        "camera": {"direction": list(BLENDER_VIEW), "ortho_scale": 2 * HALF_WIDTH},
                        "sun": {"direction": list(BLENDER_LIGHT), "strength": 1.0, "color": [1.0, 1.0, 1.0],
                                "angle_deg": 0.0},
                        "world": [0.0, 0.0, 0.0], "passes": ["normal", "emit"],
                        "objects": [{"shape": "sphere", "material": material}]})
    (work / "blender").mkdir(parents=True, exist_ok=True)
    brdfcli.progress(f"Blender: {len(renders)} renders of {size}x{size}")
    results = render_check.run_blender_job(str(work / "blender"), renders, blender, brdf, str(ROOT), addon_zip)
    images = {}
    for s, render, result in zip(surfaces, renders, results):
        passes = render_check.read_passes(render["output"])
        normals = passes["Normal"][..., :3]
        mask = render_check.erode(np.linalg.norm(normals, axis=2) > 0.5, 2)
        _, model, channels = render_check.description_surface(result["materials"][0]["description"])
        expected = np.zeros(normals.shape[:2] + (3,))
        expected[mask], _ = render_check.predicted_radiance(brdf, model, channels, normals[mask],
                                                            np.array(result["sun_direction"]),
                                                            np.array(result["camera_direction"]),
                                                            result["sun_strength"], result["sun_color"])
        images[s["name"]] = (passes["Combined"][..., :3], expected, mask)
        brdfcli.progress(f"Blender {s['name']}: {relative_errors(passes['Combined'], expected, mask)}")
    return images


def mitsuba_python_path(brdf):
    """The built libbrdf package beside the brdf program's build (build/cli/brdf -> build/python)."""
    beside = Path(brdf).resolve().parent.parent / "python"
    return beside if (beside / "libbrdf").is_dir() else ROOT / "build" / "python"


def render_mitsuba(brdf, surfaces, size, work, small):
    """{name: (radiance, expected, mask)} and the renderer's label, or (None, why it is unavailable)."""
    made = subprocess.run([str(ROOT / "scripts" / "python_env.sh"), "mitsuba"], capture_output=True, text=True)
    if made.returncode == 3:
        return None, "unavailable: " + (made.stderr.strip().splitlines() or ["no venv"])[-1]
    if made.returncode != 0:
        raise RuntimeError(f"scripts/python_env.sh mitsuba failed (exit {made.returncode}): {made.stderr[-500:]}")
    python = Path(made.stdout.strip().splitlines()[-1]) / "bin" / "python"
    directory = work / "mitsuba"
    command = [str(python), str(ROOT / "tools" / "render_mitsuba_comparison.py"), "--brdf", brdf, "--out", str(directory),
               "--model", MODEL, "--resolution", str(size), "--half-width", str(HALF_WIDTH),
               "--to-sun", *map(str, MITSUBA_LIGHT), "--towards-camera", *map(str, MITSUBA_VIEW),
               "--cost-spp", "4" if small else "16"]
    brdfcli.progress(f"Mitsuba: {len(surfaces)} renders of {size}x{size} and the cost per sample")
    env = dict(os.environ, PYTHONPATH=str(mitsuba_python_path(brdf)))
    subprocess.run(command, env=env, check=True)
    label = json.loads((directory / "mitsuba_comparison.json").read_text())["renderer"]
    to_sun, towards_camera = mitsuba_common.unit(MITSUBA_LIGHT), mitsuba_common.unit(MITSUBA_VIEW)
    images = {}
    for s in surfaces:
        buf = oiio.ImageBuf(str(directory / "mitsuba" / f"{s['name']}.exr"))
        spec = buf.spec()
        pixels = buf.get_pixels(oiio.FLOAT).reshape(spec.height, spec.width, spec.nchannels)
        channel = {name: i for i, name in enumerate(spec.channelnames)}
        radiance = pixels[..., [channel[c] for c in ("R", "G", "B")]].astype(np.float64)
        positions = pixels[..., [channel[f"position.{c}"] for c in "XYZ"]].astype(np.float64)
        mask = pc.erode(np.abs(np.linalg.norm(positions, axis=2) - 1.0) < 1e-3, 2)
        expected = np.zeros(radiance.shape)
        surface = {"material": s["material"], "sigma_s": s["sigma_s_um"], "lc": s["lc_um"]}
        expected[mask], _ = mitsuba_common.predicted_sun_radiance(brdf, MODEL, surface, positions[mask], to_sun,
                                                                  towards_camera)
        images[s["name"]] = (radiance, expected, mask)
        brdfcli.progress(f"Mitsuba {s['name']}: {relative_errors(radiance, expected, mask)}")
    return images, label


def difference_figure(renders, surfaces, titles, path):
    """|L / L_eval - 1| per lit pixel (largest channel) of every cell on one log colour scale."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm
    norm = LogNorm(DIFFERENCE_RANGE[0], DIFFERENCE_RANGE[1], clip=True)
    cmap = plt.get_cmap("magma").copy()
    cmap.set_bad((0.82, 0.82, 0.82))
    figure, axes = plt.subplots(len(titles), len(surfaces), figsize=(1.55 * len(surfaces) + 1.4, 1.6 * len(titles) + 0.3),
                                squeeze=False, constrained_layout=True)
    image = None
    for row, (renderer, title) in enumerate(titles.items()):
        for column, s in enumerate(surfaces):
            ax = axes[row, column]
            ax.set_xticks([])
            ax.set_yticks([])
            if row == 0:
                ax.set_title(s["name"], fontsize=9)
            if column == 0:
                ax.set_ylabel(title, fontsize=9)
            if renders.get(renderer) is None:
                ax.text(0.5, 0.5, "unavailable", ha="center", va="center", fontsize=8, transform=ax.transAxes)
                continue
            rendered, expected, mask = renders[renderer][s["name"]]
            lit = mask & (expected.min(axis=2) > LIT_FRACTION * expected[mask].max())
            relative = np.full(mask.shape, np.nan)
            relative[lit] = np.max(np.abs(rendered[lit][:, :3] / expected[lit] - 1.0), axis=1)
            # 0 (bit-exact) shown at the scale's floor; the floor is far below every median measured.
            image = ax.imshow(np.ma.masked_invalid(np.maximum(relative, DIFFERENCE_RANGE[0])), cmap=cmap, norm=norm,
                              interpolation="nearest")
    if image is not None:
        bar = figure.colorbar(image, ax=axes, shrink=0.9, pad=0.01)
        bar.set_label("|L / L_eval − 1|", fontsize=9)
    temporary = path.with_name(f".{path.name}.tmp{os.getpid()}.png")
    figure.savefig(temporary, dpi=110)
    plt.close(figure)
    os.replace(temporary, path)


def luminance(rgb):
    return rgb @ np.array([0.2126, 0.7152, 0.0722])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--brdf", required=True, help="the brdf executable")
    parser.add_argument("--out", required=True, type=Path, help="output directory (the report's renders/)")
    parser.add_argument("--small", action="store_true", help="smaller renders")
    parser.add_argument("--blender", default=shutil.which("blender") or "blender")
    args = parser.parse_args()
    start = time.time()
    brdf = os.path.abspath(args.brdf)
    surfaces = brdfcli.load_materials()["surfaces"]
    size = 96 if args.small else 160
    cells = args.out / "summary"
    work = cells / "work"
    work.mkdir(parents=True, exist_ok=True)
    renders = {"povray": render_povray(brdf, surfaces, size, work),
               "blender": render_blender(brdf, args.blender, surfaces, size, work)}
    renders["mitsuba"], mitsuba_label = render_mitsuba(brdf, surfaces, size, work, args.small)
    if renders["mitsuba"] is None:
        brdfcli.progress(f"Mitsuba {mitsuba_label}")

    lit = []
    for images in renders.values():
        if images is None:
            continue
        for rendered, expected, mask in images.values():
            e = expected[mask]
            lit.append(luminance(rendered[mask][e.min(axis=1) > LIT_FRACTION * e.max()]))
    exposure = 1.0 / np.percentile(np.concatenate(lit), EXPOSURE_PERCENTILE)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = []
    for renderer, images in renders.items():
        for s in surfaces:
            if images is None:  # the renderer could not run here: its row says why
                rows.append({"surface": s["name"], "renderer": renderer, "lit_pixels": 0, "median_relative_error": "",
                             "p95_relative_error": "", "peak_radiance_per_sr": "", "exposure": f"{exposure:.4g}",
                             "image": "", "note": mitsuba_label})
                continue
            rendered, expected, mask = images[s["name"]]
            x = np.clip(rendered, 0.0, None) * exposure
            path = cells / f"{s['name']}_{renderer}.png"
            plt.imsave(path, pc.to_srgb(x / (1.0 + x)))
            pixels, median, p95 = relative_errors(rendered, expected, mask)
            rows.append({"surface": s["name"], "renderer": renderer, "lit_pixels": pixels,
                         "median_relative_error": f"{median:.3g}", "p95_relative_error": f"{p95:.3g}",
                         "peak_radiance_per_sr": f"{luminance(rendered).max():.4g}", "exposure": f"{exposure:.4g}",
                         "image": f"summary/{path.name}", "note": mitsuba_label if renderer == "mitsuba" else ""})
    difference_figure(renders, surfaces, {"povray": "POV-Ray", "blender": "Blender Cycles", "mitsuba": "Mitsuba 3"},
                      args.out / "summary_difference.png")
    temporary = args.out / f".summary.csv.tmp{os.getpid()}"
    with open(temporary, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    os.replace(temporary, args.out / "summary.csv")
    for row in rows:
        if not row["image"]:
            print(f"{row['surface']:10s} {row['renderer']:8s} {row['note']}")
            continue
        print(f"{row['surface']:10s} {row['renderer']:8s} {row['lit_pixels']:6d} lit pixels: median "
              f"{float(row['median_relative_error']):.2e}, p95 {float(row['p95_relative_error']):.2e}")
    print(f"exposure x{exposure:.4g}; wrote {args.out / 'summary.csv'} ({time.time() - start:.1f} s)")


if __name__ == "__main__":
    main()
