#!/usr/bin/python3
"""What each libbrdf material mode costs in the renderer (issue 33, item 5), measured in one run:

    tools/bench/renderer_cost.py --brdf build/cli/brdf --out DIR [--blender 4.5] [--small]

Scene: the one-sun scene of the renderer tests (a sphere of radius 1.2 seen along +z by an
orthographic camera, one sun towards (-0.3, 0.45, 0.84), black world), gold (mbk, sigma_s 0.1 um,
l_c 2 um; R, G, B = 0.65, 0.55, 0.45 um).
Cycles: seconds per sample = (t(N samples) - t(1 sample)) / (N - 1) of bpy.ops.render.render, which
cancels scene sync, kernel and OSL compilation and the file write; for LUT, FIT, OSL (Blenders with
OSL) and a metallic Principled BSDF whose roughness is the FIT's strongest Beckmann lobe's
(Blender roughness = sqrt(alpha)): "the same roughness". Each at 1 thread and at all threads.
POV-Ray: seconds per pixel = (t(large) - t(small)) / (pixels(large) - pixels(small)) of whole
povray runs (cancels parsing the include), NAME_Exact against a plain metallic finish under the
same sun (povray/scenes/object_check.pov, Pass 0 and 3), at 1 thread (+WT1) and all threads.
Every time is the fastest of 2 (--small) or 3 repeats. Writes DIR/renderer_cost.json and DIR/renderer_cost.md (the table; ratios against the reference of
the same run and thread count).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "tests" / "blender"))
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "blender_addon"))
import povray_common as pc  # noqa: E402
import render_check  # noqa: E402
from blender_test_env import blender_program  # noqa: E402
from package import addon_zip  # noqa: E402

SURFACE = {"model": "mbk", "material": "Au", "sigma_s": 0.1, "lc": 2.0}
SUN = [-0.3, 0.45, 0.84]
CAMERA = [0.0, 0.0, 1.0]


def strongest_lobe_roughness(brdf, tmp):
    """Blender roughness (sqrt alpha) of the FIT's Cycles lobe with the largest colour weight."""
    out = os.path.join(tmp, "fit_probe", "fit.json")
    subprocess.run([brdf, "export", "blender", "--model", SURFACE["model"], "--material", SURFACE["material"],
                    "--sigma-s", str(SURFACE["sigma_s"]), "--lc", str(SURFACE["lc"]), "--mode", "fit",
                    "--output", out], check=True, capture_output=True, text=True)
    with open(out, encoding="utf-8") as f:
        lobes = json.load(f)["fit"]["lobes"]
    weight = [sum(sum(c) for c in lobe["colour"]) for lobe in lobes]
    alpha = lobes[weight.index(max(weight))]["alpha"]
    return alpha ** 0.5


def blender_costs(brdf, version, samples, size, repeats, tmp):
    program = blender_program(version)
    roughness = strongest_lobe_roughness(brdf, tmp)
    has_osl = version != "debian"
    kinds = [("Principled BSDF", {"principled": {"roughness": roughness, "color": [1.0, 0.78, 0.34]}}),
             ("LUT", {"material": dict(SURFACE, mode="LUT")}), ("FIT", {"material": dict(SURFACE, mode="FIT")})]
    if has_osl:
        kinds.append(("OSL", {"material": dict(SURFACE, mode="OSL")}))
    threads = [1, os.cpu_count() or 1]
    renders, keys = [], []
    for label, obj in kinds:
        for thread_count in threads:
            for n, repeat in [(n, k) for k in range(repeats) for n in (1, samples)]:
                name = f"{label.split()[0].lower()}_t{thread_count}_s{n}_r{repeat}"
                renders.append({"name": name, "output": os.path.join(tmp, name + ".exr"), "resolution": [size, size],
                                "samples": n, "engine": "CYCLES", "threads": thread_count,
                                "camera": {"direction": CAMERA, "ortho_scale": 2.8},
                                "sun": {"direction": SUN, "strength": 1.0, "color": [1.0, 1.0, 1.0]},
                                "world": [0.0, 0.0, 0.0], "passes": [], "keep_objects": False,
                                "objects": [dict({"shape": "sphere", "scale": [1.2] * 3}, **obj)]})
                keys.append((label, thread_count, n))
    results = render_check.run_blender_job(tmp, renders, program, brdf, str(ROOT), addon_zip)
    seconds = {}
    for key, r in zip(keys, results):  # the fastest of the repeats: the least disturbed by other work
        seconds[key] = min(seconds.get(key, float("inf")), r["render_seconds"])
    rows = []
    for label, _ in kinds:
        for thread_count in threads:
            per_sample = (seconds[label, thread_count, samples] - seconds[label, thread_count, 1]) / (samples - 1)
            require_positive(per_sample, f"Cycles {label} at {thread_count} thread(s): t({samples}) - t(1)")
            rows.append({"renderer": f"Cycles (Blender {results[0]['blender']})", "mode": label,
                         "threads": thread_count, "seconds_per_sample": per_sample})
    for row in rows:
        reference = next(r for r in rows if r["mode"] == "Principled BSDF" and r["threads"] == row["threads"])
        row["ratio"] = row["seconds_per_sample"] / reference["seconds_per_sample"]
    return rows, {"principled_roughness": roughness, "samples": samples, "resolution": size}


def povray_costs(brdf, sizes, repeats, tmp):
    directory = Path(tmp) / "povray"
    directory.mkdir(parents=True, exist_ok=True)
    light, view = pc.blender_to_povray(SUN), pc.blender_to_povray(CAMERA)
    pc.export_include(brdf, SURFACE["model"], {"material": SURFACE["material"], "sigma_s": SURFACE["sigma_s"],
                                                 "lc": SURFACE["lc"]}, light, view, "Material", directory)
    scene = ROOT / "povray" / "scenes" / "object_check.pov"
    rows = []
    for label, render_pass in (("plain finish", 3), ("NAME_Exact", 0)):
        for threads in (1, os.cpu_count() or 1):
            times = []
            for size in sizes:
                command = [pc.find_povray(), f"+I{scene}", f"+O{directory / 'cost.exr'}", f"+W{size}", f"+H{size}",
                           "+FE", "+UA", "-D", "-A", "-P", "-V", "+WL0", f"+WT{threads}",
                           f"+L{ROOT / 'povray'}", f"+L{directory}", f"Declare=Pass={render_pass}"]
                best = float("inf")
                for _ in range(repeats):
                    start = time.perf_counter()
                    subprocess.run(command, cwd=directory, check=True, capture_output=True)
                    best = min(best, time.perf_counter() - start)
                times.append(best)
            per_pixel = (times[1] - times[0]) / (sizes[1] ** 2 - sizes[0] ** 2)
            require_positive(per_pixel, f"POV-Ray {label} at {threads} thread(s): t({sizes[1]}²) - t({sizes[0]}²)")
            rows.append({"renderer": "POV-Ray 3.7", "mode": label, "threads": threads, "seconds_per_pixel": per_pixel})
    for row in rows:
        reference = next(r for r in rows if r["mode"] == "plain finish" and r["threads"] == row["threads"])
        row["ratio"] = row["seconds_per_pixel"] / reference["seconds_per_pixel"]
    return rows


def require_positive(seconds, what):
    """A difference of two timings at or below 0 means the machine's noise exceeded the work measured:
    stop with that instead of writing a meaningless (negative) cost into the table."""
    if not seconds > 0:
        raise SystemExit(f"renderer_cost.py: {what} = {seconds:.3g} s, not positive: the timing noise exceeds "
                         "the measured work (a busy machine?); run again or without --small")


def markdown(blender_rows, povray_rows, meta):
    lines = [f"Cycles: seconds per sample at {meta['resolution']}x{meta['resolution']} "
             f"((t({meta['samples']}) - t(1)) / {meta['samples'] - 1}); reference: Principled BSDF, metallic, "
             f"roughness {meta['principled_roughness']:.3f}", "",
             "| renderer | mode | threads | s per sample | x reference |", "|---|---|---|---|---|"]
    lines += [f"| {r['renderer']} | {r['mode']} | {r['threads']} | {r['seconds_per_sample']:.4f} | {r['ratio']:.2f} |"
              for r in blender_rows]
    lines += ["", "POV-Ray: seconds per pixel (difference of two image sizes); reference: a plain metallic finish", "",
              "| renderer | mode | threads | us per pixel | x reference |", "|---|---|---|---|---|"]
    lines += [f"| {r['renderer']} | {r['mode']} | {r['threads']} | {1e6 * r['seconds_per_pixel']:.2f} | {r['ratio']:.2f} |"
              for r in povray_rows]
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--brdf", default=str(ROOT / "build" / "cli" / "brdf"))
    parser.add_argument("--out", required=True)
    parser.add_argument("--blender", default="4.5", choices=["debian", "4.5", "5.0"])
    parser.add_argument("--small", action="store_true", help="fewer samples and pixels (the test's size)")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    # POV-Ray costs ~0.1-0.2 us per pixel: the two sizes differ by >= 1.6 M pixels (~0.3 s) so that
    # process noise (128 against 320 px once gave a negative difference) stays small beside it.
    samples, size, pov_sizes, repeats = (17, 128, (256, 1280), 2) if args.small else (33, 256, (256, 2048), 3)
    with tempfile.TemporaryDirectory(prefix="libbrdf_cost_") as tmp:
        blender_rows, meta = blender_costs(args.brdf, args.blender, samples, size, repeats, tmp)
        povray_rows = povray_costs(args.brdf, pov_sizes, repeats, tmp)
    meta["repeats"] = repeats
    meta["load_average_1min"] = os.getloadavg()[0]  # a shared machine's ratios are only as steady as its load
    with open(out / "renderer_cost.json", "w", encoding="utf-8") as f:
        json.dump({"cycles": blender_rows, "povray": povray_rows, "meta": meta}, f, indent=1)
    text = markdown(blender_rows, povray_rows, meta)
    (out / "renderer_cost.md").write_text(text, encoding="utf-8")
    print(text)


if __name__ == "__main__":
    main()
