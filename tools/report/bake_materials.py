#!/usr/bin/python3
"""Bakes the main job's default material set (tools/report/materials.json) with `brdf bake`.

One OpenEXR table per surface: the mbk model (the paper's reference) at the bake wavelengths
(R, G, B channels) in the Rusinkiewicz layout. Writes into --out:
  <name>.exr   the tables
  bakes.csv    per table: surface, model, file, size, bake time and the error the bake measured
               against direct evaluation (read back from the file's header)
  bake_errors.csv, bake_errors.png, <name>.kernel.exr
               where that error comes from, and the same surfaces in the kernel layout (bake_errors.py)
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bake_errors  # noqa: E402
import brdfcli  # noqa: E402

MODEL = "mbk"
LAYOUT = "rusinkiewicz"
SMALL_RESOLUTION = "24,24,12"   # nodes per axis for --small (the CLI's default otherwise)


def header_attributes(path):
    """The EXR header's string/number attributes (OpenImageIO), e.g. the measured error."""
    import OpenImageIO as oiio
    image = oiio.ImageInput.open(path)
    if image is None:
        raise RuntimeError(f"cannot read {path}: {oiio.geterror()}")
    spec = image.spec()
    image.close()
    return {a.name: a.value for a in spec.extra_attribs}, spec


def find_attribute(attributes, *words):
    for key, value in attributes.items():
        if all(w in key.lower() for w in words):
            return value
    return ""


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--brdf", required=True, help="path of the brdf executable")
    parser.add_argument("--out", required=True, help="output directory")
    parser.add_argument("--small", action="store_true", help=f"small tables ({SMALL_RESOLUTION} nodes)")
    parser.add_argument("--materials", default=brdfcli.MATERIALS_FILE, help="material set (JSON)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    config = brdfcli.load_materials(args.materials)
    wavelengths = ",".join(f"{w:g}" for w in config["bake_wavelengths_um"])

    rows = []
    for s in config["surfaces"]:
        path = os.path.join(args.out, f"{s['name']}.exr")
        command = [args.brdf, "bake", "--model", MODEL, "--material", s["material"],
                   "--sigma-s", f"{s['sigma_s_um']:.6g}", "--lc", f"{s['lc_um']:g}", "--wavelength", wavelengths,
                   "--layout", LAYOUT, "--output", path]
        if args.small:
            command += ["--resolution", SMALL_RESOLUTION]
        brdfcli.progress(f"baking {s['name']}: {' '.join(command[1:])}")
        start = time.monotonic()
        run = subprocess.run(command, capture_output=True, text=True)
        seconds = time.monotonic() - start
        sys.stderr.write(run.stdout + run.stderr)
        if run.returncode != 0:
            last = (run.stderr.strip().splitlines() or ["(no message)"])[-1]
            sys.exit(f"bake_materials: brdf bake failed for {s['name']} ({run.returncode}): {last}")
        if not os.path.isfile(path) or os.path.getsize(path) == 0:
            sys.exit(f"bake_materials: brdf bake wrote no table at {path}")
        attributes, spec = header_attributes(path)
        # `brdf bake` prints "... max relative X, rms relative Y ..." (its measurement at off-grid points).
        measured = re.search(r"max relative ([0-9.eE+-]+), rms relative ([0-9.eE+-]+)", run.stdout)
        horizon = re.search(r"up to the horizon: max relative ([0-9.eE+-]+)", run.stdout)
        rows.append({
            "surface": s["name"], "model": MODEL, "material": s["material"], "sigma_s_um": f"{s['sigma_s_um']:.4g}",
            "lc_um": s["lc_um"], "wavelengths_um": wavelengths, "layout": LAYOUT,
            "file": os.path.basename(path), "image": f"{spec.width}x{spec.height}x{spec.nchannels}",
            "bytes": os.path.getsize(path), "seconds": f"{seconds:.2f}",
            "max_relative_error": measured.group(1) if measured else find_attribute(attributes, "max"),
            "rms_relative_error": measured.group(2) if measured else find_attribute(attributes, "rms"),
            "max_relative_error_to_horizon": horizon.group(1) if horizon else "",
        })
    with open(os.path.join(args.out, "bakes.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    bake_errors.analyse(args.brdf, config, args.out, 50000 if args.small else 400000)


if __name__ == "__main__":
    main()
