#!/usr/bin/python3
"""Blender comparison of the paper's models, polished to rough, side by side.

    render_blender_comparison.py --brdf BRDF_EXE --out DIR [--small] [--blender BLENDER]
                                 [--material Au] [--lc 2.0]

Renders (Blender headless, Cycles CPU) one sphere per model and roughness with the libbrdf add-on
(blender_addon/libbrdf_materials, installed into a temporary user folder), each model baked into a
table (LUT mode: the BRDF lit by one sun, emitted, plus the specular spike as a mirror lobe that
reflects a uniform grey sky): rows MBK, original BK, modified BK and the mapped microfacet model;
columns sigma_s/lambda from 0.002 to 0.5 (lambda = 0.55 um, the green channel).
Writes
  DIR/blender_comparison.png   the renders, one exposure (the POV-Ray comparison's when DIR holds
                               povray_comparison.json), x/(1+x) tone curve, sRGB (comparison_common.py)
  DIR/blender_difference.png   |L - L_mbk| / L_mbk per pixel (luminance), log colour scale
  DIR/blender_comparison.json  per cell: median and 90th-percentile relative difference to MBK
  DIR/blender_comparison.exr   the raw render (multilayer EXR)
Needs Debian's python3 (numpy, matplotlib, OpenImageIO).
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(ROOT, "blender_addon"))
from package import addon_zip  # noqa: E402
from libbrdf_materials.core import KERNEL_MODELS  # noqa: E402

sys.path.insert(0, os.path.join(ROOT, "tools"))
import comparison_common as cc  # noqa: E402  (surfaces, sun, exposure and metric shared with POV-Ray)

ROWS = cc.ROWS
LAMBDA_UM = cc.LAMBDA_UM
SPACING = 2.2          # scene units between sphere centres (radius 1)
# A uniform grey sky, seen through the specular spike's mirror lobe (LUT mode lights the BRDF
# itself by the sun alone), and a sun of angle 0 (no glint sampling noise).
WORLD = (0.1, 0.1, 0.1)
SUN = {"direction": list(cc.BLENDER_SUN_DIRECTION), "strength": cc.SUN_IRRADIANCE, "color": [1.0, 1.0, 1.0],
       "angle_deg": 0.0}


def build_job(args, work, columns, cell):
    objects = []
    for r, (model, _) in enumerate(ROWS):
        for c, ratio in enumerate(columns):
            material = {"model": model, "material": args.material, "sigma_s": ratio * LAMBDA_UM, "lc": args.lc,
                        "mode": "LUT"}
            if model not in KERNEL_MODELS:  # the factored form's P~ table keeps its exporter default (54^3)
                material["resolution"] = list(args.resolution)
            x = (c - (len(columns) - 1) / 2) * SPACING
            z = ((len(ROWS) - 1) / 2 - r) * SPACING
            # Not seen in the other spheres' mirror lobes: each cell shows one model alone.
            objects.append({"shape": "sphere", "location": [x, 0.0, z], "material": material,
                            "visible_glossy": False})
    output = os.path.join(work, "comparison.exr")
    render = {"output": output, "resolution": [len(columns) * cell, len(ROWS) * cell], "samples": args.samples,
              "engine": "CYCLES", "camera": {"direction": [0.0, -1.0, 0.0], "ortho_scale": max(len(columns), len(ROWS)) * SPACING},
              "filter_width": 1.5, "sun": SUN, "world": list(WORLD), "passes": [], "objects": objects}
    return {"addon": {"zip": addon_zip(work)}, "results": os.path.join(work, "results.json"), "renders": [render]}


def read_combined(path):
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    pixels = buf.get_pixels(oiio.FLOAT).reshape(spec.height, spec.width, spec.nchannels)
    index = [spec.channelnames.index(f"ViewLayer.Combined.{c}") for c in "RGB"]
    return pixels[:, :, index]


def cells(image, rows, columns, cell):
    return [[image[r * cell:(r + 1) * cell, c * cell:(c + 1) * cell] for c in range(columns)] for r in range(rows)]


def sphere_mask(cell):
    y, x = np.mgrid[0:cell, 0:cell] + 0.5
    radius = cell / SPACING  # sphere radius 1 in a SPACING-wide cell
    return (x - cell / 2) ** 2 + (y - cell / 2) ** 2 < (0.97 * radius) ** 2


def figures(image, columns, cell, out, args):
    grid = cells(image, len(ROWS), len(columns), cell)
    shared = cc.shared_exposure(out)
    exposure = shared if shared else cc.exposure_of(image)
    title = (f"{args.material}, l_c = {args.lc:g} um, sun {SUN['strength']:g} W/m^2, grey sky {WORLD[0]:g}; "
             f"RGB = 0.65/0.55/0.45 um; exposure x{exposure:.3g}"
             f"{' (the POV-Ray comparison' + chr(39) + 's)' if shared else ''}, x/(1+x)")
    cc.comparison_figure(grid, columns, exposure, "libbrdf in Blender (Cycles, LUT mode)\n" + title,
                         os.path.join(out, "blender_comparison.png"))
    summary = {"exposure": exposure, "columns_sigma_over_lambda": list(columns),
               "cells": cc.difference_figure(grid, columns, sphere_mask(cell),
                                             "Difference to MBK per pixel (first row: MBK itself)",
                                             os.path.join(out, "blender_difference.png"))}
    with open(os.path.join(out, "blender_comparison.json"), "w", encoding="utf-8") as f:
        json.dump(summary, f, indent=1)
    return summary


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--brdf", required=True, help="the brdf executable")
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument("--small", action="store_true", help="3 roughness columns, small cells, coarser tables")
    parser.add_argument("--blender", default=shutil.which("blender") or "blender")
    parser.add_argument("--material", default=cc.MATERIAL, help=f"built-in material (default {cc.MATERIAL})")
    parser.add_argument("--lc", type=float, default=cc.LC_UM, help=f"correlation length l_c in um (default {cc.LC_UM:g})")
    args = parser.parse_args()
    columns = cc.columns(args.small)
    cell = 96 if args.small else 160
    args.resolution = (96, 48, 32) if args.small else (128, 64, 48)
    args.samples = 4 if args.small else 16  # antialiasing (1.5-pixel filter); LUT shading is noise-free
    brdf = os.path.abspath(args.brdf)
    if not (os.path.isfile(brdf) and os.access(brdf, os.X_OK)):
        print(f"render_blender_comparison: error: brdf: {brdf} is not an executable file", file=sys.stderr)
        return 2
    os.makedirs(args.out, exist_ok=True)
    work = tempfile.mkdtemp(prefix="libbrdf_blender_comparison_")
    try:
        job = build_job(args, work, columns, cell)
        job_path = os.path.join(work, "job.json")
        with open(job_path, "w", encoding="utf-8") as f:
            json.dump(job, f, indent=1)
        env = dict(os.environ, LIBBRDF_BRDF_EXE=brdf, BLENDER_USER_SCRIPTS=os.path.join(work, "scripts"),
                   BLENDER_USER_CONFIG=os.path.join(work, "config"), TMPDIR=work, XDG_CACHE_HOME=os.path.join(work, "cache"))
        done = subprocess.run([args.blender, "-b", "--factory-startup", "--python-exit-code", "1", "--python",
                               os.path.join(ROOT, "tools", "blender_render_job.py"), "--", job_path],
                              env=env, capture_output=True, text=True)
        output = job["renders"][0]["output"]
        if done.returncode != 0 or not os.path.isfile(output):
            print((done.stdout + done.stderr)[-3000:], file=sys.stderr)
            print(f"render_blender_comparison: error: blender failed (exit {done.returncode})", file=sys.stderr)
            return 1
        image = read_combined(output)
        if not np.all(np.isfinite(image)):
            print("render_blender_comparison: error: the render has non-finite pixels", file=sys.stderr)
            return 1
        shutil.copyfile(output, os.path.join(args.out, "blender_comparison.exr"))
        summary = figures(image, columns, cell, args.out, args)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    for cell_summary in summary["cells"]:
        if cell_summary["model"] != "mbk":
            print(f"{cell_summary['model']:>12} sigma_s/lambda {cell_summary['sigma_over_lambda']:<6g} "
                  f"median |L - L_mbk|/L_mbk {cell_summary['median_relative']:.3f}  p90 {cell_summary['p90_relative']:.3f}")
    print(os.path.join(args.out, "blender_comparison.png"))
    print(os.path.join(args.out, "blender_difference.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
