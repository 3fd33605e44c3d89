#!/usr/bin/python3
"""The main job at reduced size: `run.sh --small --no-build --out DIR` with the built brdf.

Checks that the job succeeds with its progress display, that every promised file exists, that the
images (PNG, EXR) are readable, non-blank and NaN-free, that index.html links only files that
exist, and that the saved Fig. 2 data shows what the paper states: R_d = 0 at specular
(theta_s = theta_i, phi_s = 180), symmetric about phi_s = 180, small near the normal at small
theta_i, and larger in the outer theta_s ring than in the inner ring for every map.

Environment (set by ctest): BRDF_EXE, LIBBRDF_ROOT, LIBBRDF_BUILD. The report stays in
$LIBBRDF_BUILD/main_job_test/report for inspection.
"""
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys

import numpy as np
import OpenImageIO as oiio

ROOT = os.environ["LIBBRDF_ROOT"]
BRDF = os.environ["BRDF_EXE"]
OUT = os.path.join(os.environ.get("LIBBRDF_BUILD", "/tmp"), "main_job_test", "report")
sys.path.insert(0, os.path.join(ROOT, "tools", "report"))
sys.path.insert(0, os.path.join(ROOT, "tests"))
import brdfcli  # noqa: E402
import checks  # noqa: E402
import make_index  # noqa: E402
from checks import check  # noqa: E402

checks.print_passes = False  # the messages below name the problem
SUMMARY_RENDERERS = ("povray", "blender", "mitsuba")


def run_job():
    shutil.rmtree(OUT, ignore_errors=True)
    env = dict(os.environ, BRDF_EXE=BRDF)
    job = subprocess.run([os.path.join(ROOT, "run.sh"), "--small", "--no-build", "--out", OUT],
                         env=env, capture_output=True, text=True, timeout=1700)
    sys.stderr.write(job.stderr)
    if job.returncode != 0:
        # The last line names every failed stage (and each failure printed its own line above).
        sys.exit(f"FAIL: run.sh --small exited {job.returncode}: {job.stderr.strip().splitlines()[-1:]}")
    head = job.stderr.splitlines()[:2]
    check(len(head) == 2 and re.match(r"expected duration: .*\d+(-\d+)? min", head[1]),
          f"run.sh states its expected duration on its second line: {head}")
    for k in range(1, 14):
        check(f"[{k}/13]" in job.stderr, f"progress display lacks stage [{k}/13]")
    check(len(re.findall(r"ok in [0-9.]+ s|ok in [0-9]+m[0-9]{2}s", job.stderr)) == 11,
          "progress display should report 'ok in <time>' for the 11 stages that ran")


def check_promised_files():
    # A fixed core list (independent of make_index) plus everything the report page promises.
    core = ["index.html", "timings.csv", "fig2.png", "fig2_rd.npz", "fig2_summary.csv", "surfaces.csv",
            "models_overview.png", "models_hemisphere.png", "bench.csv", "bench.png", "bakes/bakes.csv",
            "renders/povray_comparison.png", "renders/povray_difference.png",
            "renders/blender_comparison.png", "renders/blender_difference.png"]
    promised = sorted(set(core) | set(make_index.promised_files()))
    for rel in promised:
        path = os.path.join(OUT, rel)
        check(os.path.isfile(path) and os.path.getsize(path) > 0, f"missing or empty: {rel}")
    return promised


def check_image(rel):
    buf = oiio.ImageBuf(os.path.join(OUT, rel))
    pixels = buf.get_pixels(oiio.FLOAT)
    if not check(pixels is not None and buf.spec().width > 0 and buf.spec().height > 0,
                 f"{rel}: unreadable ({buf.geterror()})"):
        return
    pixels = np.asarray(pixels, dtype=np.float64)
    check(np.all(np.isfinite(pixels)), f"{rel}: {np.count_nonzero(~np.isfinite(pixels))} non-finite pixel values")
    finite = pixels[np.isfinite(pixels)]
    if rel.endswith(".exr"):
        check(finite.min() >= 0.0 and finite.max() > 0.0, f"{rel}: values should be >= 0 and not all 0 "
              f"(min {finite.min():.3g}, max {finite.max():.3g})")
    else:
        colour = pixels[..., :3]
        check(colour.max() - colour.min() > 0.2 and colour.std() > 0.02,
              f"{rel}: looks blank (range {colour.min():.3f}..{colour.max():.3f}, std {colour.std():.4f})")
        check(buf.spec().width >= 200 and buf.spec().height >= 100,
              f"{rel}: suspiciously small ({buf.spec().width}x{buf.spec().height})")


def check_fig2():
    data = np.load(os.path.join(OUT, "fig2_rd.npz"))
    theta_s, phi_s, theta_i, rd = data["theta_s"], data["phi_s"], data["theta_i"], data["rd"]
    check(list(theta_i) == [15.0, 30.0, 45.0, 60.0], f"fig2: theta_i {theta_i}")
    check(list(zip(data["n"], data["k"])) == [(4, 10), (1.5, 1), (1.4, 0), (1.7, 5), (0.25, 3)],
          f"fig2: indices {list(zip(data['n'], data['k']))}")
    check(rd.shape == (5, 4, theta_s.size, phi_s.size), f"fig2: rd shape {rd.shape}")
    check(np.all(np.isfinite(rd)) and rd.min() >= 0.0, "fig2: R_d must be finite and >= 0")
    check(theta_s.min() == 0.0 and theta_s.max() >= 85.0, f"fig2: theta_s should span the hemisphere "
          f"({theta_s.min()}..{theta_s.max()})")
    j180 = np.flatnonzero(phi_s == 180.0)
    check(j180.size == 1 and phi_s.min() == 0.0 and phi_s.max() == 360.0, "fig2: phi_s grid 0..360 with 180")
    inner, outer = theta_s <= 20.0, theta_s >= 70.0
    for a in range(rd.shape[0]):
        for b, ti in enumerate(theta_i):
            m = rd[a, b]
            label = f"fig2 n={data['n'][a]:g}+{data['k'][a]:g}i theta_i={ti:g}"
            i = np.flatnonzero(theta_s == ti)
            if check(i.size == 1, f"{label}: theta_s grid lacks theta_i"):
                check(abs(m[i[0], j180[0]]) < 1e-9, f"{label}: R_d at specular = {m[i[0], j180[0]]:.3g}, want 0")
                # The zero is a minimum: its neighbours in theta_s are larger.
                check(m[i[0] - 1, j180[0]] > m[i[0], j180[0]] and m[i[0] + 1, j180[0]] > m[i[0], j180[0]],
                      f"{label}: specular is not a local minimum along the in-plane line")
            check(np.allclose(m, m[:, ::-1], rtol=1e-9, atol=1e-12), f"{label}: not symmetric about phi_s = 180")
            mi, mo = m[inner].mean(), m[outer].mean()
            check(mo > mi, f"{label}: mean R_d in the outer ring ({mo:.3g}) should exceed the inner ring ({mi:.3g})")
            if ti == 15.0:
                check(mi < 0.05, f"{label}: R_d near the normal should be small at small theta_i (mean {mi:.3g})")
    # The summary table agrees with the arrays.
    rows = read_rows("fig2_summary.csv")
    check(len(rows) == 20, f"fig2_summary.csv: {len(rows)} rows, want 20")
    for r in rows:
        check(float(r["mean_outer_ring"]) > float(r["mean_inner_ring"]), f"fig2_summary.csv: {r}")


def read_rows(rel, header_dicts=True):
    """Rows of a CSV in the report ([] when missing: check_promised_files reports that)."""
    path = os.path.join(OUT, rel)
    if not os.path.isfile(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f)) if header_dicts else list(csv.reader(f))


def check_tables():
    rows = read_rows("surfaces.csv")
    if not rows:
        return
    config = brdfcli.load_materials()
    check([r["name"] for r in rows] == [s["name"] for s in config["surfaces"]], "surfaces.csv: surfaces differ")
    # g at specular scales as sigma_s^2 (eq. 12) among the surfaces with the same l_c, lambda.
    g0, s0 = float(rows[0]["g_spec_30"]), float(rows[0]["sigma_s_um"])
    for r in rows:
        ratio = float(r["g_spec_30"]) / g0 / (float(r["sigma_s_um"]) / s0) ** 2
        check(abs(ratio - 1) < 2e-3, f"surfaces.csv {r['name']}: g does not scale as sigma_s^2 ({ratio:.4f})")
        check(r["regime_30"] == brdfcli.regime(float(r["g_spec_30"])), f"surfaces.csv {r['name']}: regime")
    regimes = {r["regime_30"] for r in rows}
    check({"polished", "very rough"} <= regimes, f"the material set should span polished to very rough: {regimes}")

    for rel in ["bench.csv", "bakes/bakes.csv"]:
        table = read_rows(rel, header_dicts=False)
        check(len(table) >= 2, f"{rel}: no data rows")
        for row in table[1:]:
            for cell in row:
                try:
                    v = float(cell)
                except ValueError:
                    continue
                check(math.isfinite(v), f"{rel}: non-finite value in {row}")
    bakes = read_rows("bakes/bakes.csv")
    check(len(bakes) == len(config["surfaces"]), f"bakes.csv: {len(bakes)} bakes, want {len(config['surfaces'])}")

    # The summary (tools/render_summary.py): three renderers, every default material, against brdf eval.
    summary = read_rows("renders/summary.csv")
    check(sorted((r["surface"], r["renderer"]) for r in summary) ==
          sorted((s["name"], r) for s in config["surfaces"] for r in SUMMARY_RENDERERS),
          f"renders/summary.csv: want every default material x {SUMMARY_RENDERERS}, got {len(summary)} rows")
    check(len({r["exposure"] for r in summary}) == 1, "renders/summary.csv: one exposure for every render")
    for r in summary:
        if r["renderer"] == "mitsuba" and not r["image"]:  # no Mitsuba venv here: the row says why
            check(r["note"].startswith("unavailable: "), f"renders/summary.csv: Mitsuba row without image: {r}")
            print(f"note: Mitsuba {r['note']}")
            continue
        # Mitsuba evaluates the model itself (float32) at each sample's exact hit point: far tighter.
        median_limit, p95_limit = (1e-4, 1e-4) if r["renderer"] == "mitsuba" else (0.005, 0.02)
        check(int(r["lit_pixels"]) >= 20 and float(r["median_relative_error"]) <= median_limit and
              float(r["p95_relative_error"]) <= p95_limit,
              f"renders/summary.csv {r['surface']} {r['renderer']}: {r['lit_pixels']} lit pixels, median "
              f"{r['median_relative_error']} (<= {median_limit:g}), p95 {r['p95_relative_error']} (<= {p95_limit:g}) "
              "against brdf eval")
    check_cost()
    bake_errors = read_rows("bakes/bake_errors.csv")
    check(len(bake_errors) == 2 * len(config["surfaces"]), f"bakes/bake_errors.csv: {len(bake_errors)} rows")
    for r in bake_errors:
        if r["layout"] == "kernel":
            check(float(r["bake_max_relative"]) <= 1e-4, f"bake_errors.csv: kernel layout of {r['surface']}: "
                  f"max {r['bake_max_relative']} (<= 1e-4)")

    timings = read_rows("timings.csv", header_dicts=False)[1:]
    check(len(timings) == 13, f"timings.csv: {len(timings)} stages, want 13")
    for number, title, status, seconds, log in timings:
        check(status == "ok" or status.startswith("skipped"), f"timings.csv: stage {number} {title}: {status}")
        check(float(seconds) >= 0, f"timings.csv: stage {number} time {seconds}")


def check_cost():
    """renderer_cost.json (the cost stage): every mode timed, positive and finite, ratios against
    the reference of the same run (the reference's own ratio is 1)."""
    path = os.path.join(OUT, "cost", "renderer_cost.json")
    if not os.path.isfile(path):
        return  # check_promised_files reports it
    with open(path, encoding="utf-8") as f:
        cost = json.load(f)
    modes = {r["mode"] for r in cost["cycles"]}
    check({"Principled BSDF", "LUT", "FIT"} <= modes, f"renderer_cost.json: Cycles modes {modes}")
    check({r["mode"] for r in cost["povray"]} == {"plain finish", "NAME_Exact"}, "renderer_cost.json: POV-Ray modes")
    for key, time_key, reference in (("cycles", "seconds_per_sample", "Principled BSDF"), ("povray", "seconds_per_pixel", "plain finish")):
        for r in cost[key]:
            check(math.isfinite(r[time_key]) and r[time_key] > 0 and math.isfinite(r["ratio"]) and r["ratio"] > 0,
                  f"renderer_cost.json {key}: {r}")
            if r["mode"] == reference:
                check(r["ratio"] == 1.0, f"renderer_cost.json {key}: the reference's ratio {r['ratio']}")


def check_index(promised):
    page = open(os.path.join(OUT, "index.html"), encoding="utf-8").read()
    check("missing:" not in page, "index.html shows missing items")
    links = re.findall(r'''(?:src|href)=["']([^"'#:]+)["']''', page)
    for link in links:
        check(os.path.isfile(os.path.join(OUT, link)), f"index.html links {link}, which does not exist")
    for rel in promised:
        if rel.endswith(".png"):
            check(f'src="{rel}"' in page, f"index.html does not show {rel}")
    check(page.count("<figcaption>") >= len([p for p in promised if p.endswith(".png")]),
          "index.html: every figure needs a caption")
    check(page.count("<table>") >= 5, "index.html: expected the timings, surfaces, bakes, Fig. 2 and bench tables")
    # The first screen is the summary; the stage timings come last; long tables are folded.
    first_section = page.find("<h2")
    check(0 < page.find("class='summary'") < first_section, "index.html: the summary table comes before any section")
    check(page.find("<h2 id='stages'>") == page.rfind("<h2"), "index.html: stages and timings are the last section")
    # The summary's cells: every material in both renderers on the first screen; on one exposure the
    # polished highlights are small, the rough lobes wide and bright.
    config = brdfcli.load_materials()
    mitsuba_ran = any(r["renderer"] == "mitsuba" and r["image"] for r in read_rows("renders/summary.csv"))
    for s in config["surfaces"]:
        for renderer in SUMMARY_RENDERERS if mitsuba_ran else SUMMARY_RENDERERS[:2]:
            rel = f"renders/summary/{s['name']}_{renderer}.png"
            check(f"src='{rel}'" in page and os.path.isfile(os.path.join(OUT, rel)), f"index.html: summary cell {rel}")
            if s["sigma_over_lambda"] >= 0.5 and os.path.isfile(os.path.join(OUT, rel)):
                colour = oiio.ImageBuf(os.path.join(OUT, rel)).get_pixels(oiio.FLOAT)[..., :3]
                check(colour.max() > 0.2 and colour.std() > 0.02, f"{rel}: a rough sphere should be visible "
                      f"(max {colour.max():.3f}, std {colour.std():.4f})")
    # Just after the summary: the difference figure, then the renderer cost table (before the materials).
    difference, cost = page.find('src="renders/summary_difference.png"'), page.find("<h2 id='cost'>")
    check(page.find("class='summary'") < difference < cost < page.find("<h2 id='materials'>"),
          "index.html: the summary, its difference figure, the renderer cost table, then the materials")
    cost_table = page[cost:page.find("</table>", cost)]
    for mode in ["LUT", "FIT", "NAME_Exact"] + (["libbrdf plugin"] if mitsuba_ran else []):
        check(f">{mode}" in cost_table, f"index.html: the renderer cost table lacks {mode}")
    for name in ["bench.csv", "albedo_summary.csv"]:
        at = page.find(f'href="{name}"')
        check(at > 0 and page.rfind("<details>", 0, at) > page.rfind("</details>", 0, at),
              f"index.html: the long table {name} is folded in <details>")


def main():
    run_job()
    promised = check_promised_files()
    images = sorted({p for p in promised if p.endswith((".png", ".exr"))})
    for rel in images:
        if os.path.isfile(os.path.join(OUT, rel)):
            check_image(rel)
    if os.path.isfile(os.path.join(OUT, "fig2_rd.npz")):
        check_fig2()
    check_tables()
    if os.path.isfile(os.path.join(OUT, "index.html")):
        check_index(promised)
    checks.finish(f"ok: main job at reduced size; {len(promised)} files, {len(images)} images checked in {OUT}",
                  f" in {OUT}")


if __name__ == "__main__":
    main()
