#!/usr/bin/python3
"""Writes the main job's report page, index.html, into the report directory.

It opens with a one-screen summary: every default material rendered by POV-Ray, Blender Cycles and
Mitsuba 3 on one exposure, each render's error against `brdf eval` (renders/summary.csv,
tools/render_summary.py), the fastest path of `brdf bench` that meets 1e-3 and the default bakes'
error; then the per-pixel difference of every render on one log scale and what each material mode
costs in the renderer (cost/renderer_cost.json and Mitsuba's cost from the summary's run). Then every figure with
a one-line caption, the tables (CSV files of the other stages) as HTML tables (long ones folded),
where the bakes' error comes from, and at the end the time of each stage (timings.csv, written by
run.sh). A missing file is shown as missing, with the status of the stage that should have made it.
`promised_files()` lists what a complete report holds (the main-job test checks that list).
"""
import argparse
import csv
import datetime
import html
import json
import math
import os
import platform
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import brdfcli  # noqa: E402

# (stage name in run.sh's logs, path in the report, one-line caption)
FIG2 = [("fig2", "fig2.png",
         "The paper's Fig. 2 reproduced: R_d = |2F/Q − S|/(2F/Q) (eq. 23) over the hemisphere for five indices "
         "(rows) at θi = 15, 30, 45, 60° (columns); 0 at the specular point ★, growing towards grazing.")]
MODEL_FIGURES = [
    ("models", "models_overview.png",
     "mbk in the plane of incidence at θi = 30° for every surface: the lobe widens from polished to very rough "
     "while the specular spike R_spec fades."),
    ("models", "models_hemisphere.png",
     "All six models over the scattered hemisphere at θi = 30° (rows: surfaces; log colour per row)."),
]
RENDERS = [
    ("povray", "renders/povray_comparison.png",
     "POV-Ray (NAME_Exact): mbk, bk, bk-modified and the mapped microfacet model (rows) on gold spheres from "
     "polished to rough (columns), one sun of irradiance 3, one exposure for every sphere (the Blender figure "
     "below uses the same exposure, surfaces, sun and layout; tools/comparison_common.py)."),
    ("povray", "renders/povray_difference.png",
     "POV-Ray: |L − L_mbk| / L_mbk per pixel (luminance) of each model, median annotated (where mbk is above 1% "
     "of its peak) — the metric of the Blender difference below."),
    ("blender", "renders/blender_comparison.png",
     "Blender (Cycles, LUT mode): the same models, surfaces, sun and exposure as the POV-Ray figure above; a grey "
     "sky (0.1) adds the specular spike's mirror reflection, which POV-Ray's NAME_Exact does not draw."),
    ("blender", "renders/blender_difference.png",
     "Blender: |L − L_mbk| / L_mbk per pixel (luminance) of each model, median annotated (as for POV-Ray)."),
    ("fitscene", "renders/fit_scene.png",
     "FIT mode in a scene (issue 10): four default materials (au-s0.01, au-s0.15, au-s0.5, bk7-s0.05) on spheres "
     "over a grey ground, a uniform sky and two suns with shadows; Blender Cycles (the add-on's fitted Beckmann "
     "lobes) beside POV-Ray (NAME_Fit: fitted Blinn and Phong lobes). POV-Ray's lobes see the sky only through the mirror "
     "reflection. Each fit's measured error: table fit_scene_errors."),
]
ALBEDO = [("albedo", "albedo.png",
           "White furnace: directional albedo a(θi) = ∫ f cos θs dω + R_spec of every model (specular spike "
           "included; K modes plane — solid — and tis — dashed) for each surface at the design wavelength "
           "(brdf albedo, adaptive Gauss-Kronrod). Above 1 = energy created.")]
BENCH = [("bench", "bench.png", "Speed against error of every fast path (brdf bench --quick): time per "
          "evaluation against the relative error to the reference series.")]
BAKE_ERRORS = [("bake", "bakes/bake_errors.png",
                "Where the default bakes' error is: the largest relative error of each table against the model, "
                "by half-vector angle θh (left, θi, θs ≤ 85°) and towards the horizon (right); solid: the "
                "default Rusinkiewicz layout, dashed: the same surface in the kernel layout.")]
# brdf bench's surfaces (cli/bench_command.cpp, kSurfaces: Au at 0.55 um): sigma_s in um.
BENCH_SURFACE_SIGMA_UM = {"polished": 0.01, "intermediate": 0.1, "rough": 0.5}
MEETS = 1e-3  # the summary's error target for a fast path
COST_SURFACE_SIGMA_UM = 0.1  # tools/bench/renderer_cost.py's surface (Au, l_c 2 um)
TABLES = {"surfaces": ("models", "surfaces.csv"), "bakes": ("bake", "bakes/bakes.csv"),
          "fig2": ("fig2", "fig2_summary.csv"), "bench": ("bench", "bench.csv"),
          "albedo": ("albedo", "albedo_summary.csv"),
          "fit_scene_errors": ("fitscene", "renders/fit_scene_errors.csv"),
          "fit_errors_by_angle": ("fitscene", "renders/fit_errors_by_angle.csv"),
          "summary": ("summary", "renders/summary.csv"), "bake_errors": ("bake", "bakes/bake_errors.csv")}
SUMMARY_DIFFERENCE = [("summary", "renders/summary_difference.png",
                       "Per material (columns) and renderer (rows): |L / L_eval − 1| per lit pixel (the largest channel; "
                       "the pixels of the summary's error), one log colour scale for all; grey: not compared (a channel below 1% "
                       "of the sphere's maximum, off the sphere or in its 2-pixel silhouette band). POV-Ray writes half "
                       "floats (relative rounding up to 2^-11 = 4.9e-4); Blender's LUT mode interpolates a table; Mitsuba's "
                       "plugin evaluates the model in float32 at each sample's hit point.")]
# Where Mitsuba's cost per sample comes from: the summary stage's run of tools/render_mitsuba_comparison.py.
MITSUBA_RUN = "renders/summary/work/mitsuba/mitsuba_comparison.json"


def surface_figures(config):
    return [("models", f"models_{s['name']}.png",
             f"{s['name']} ({s['material']}, σs/λ = {s['sigma_over_lambda']:g}, l_c = {s['lc_um']:g} µm): "
             "in-plane BRDF of every model (log axis, regimes of g shaded) and polar lobes at θi = 30° and 60°.")
            for s in config["surfaces"]]


def promised_files(materials=brdfcli.MATERIALS_FILE):
    """Every file a complete report holds, relative to the report directory."""
    config = brdfcli.load_materials(materials)
    files = ["index.html", "timings.csv", "fig2_rd.npz"]
    files += [p for _, p, _ in FIG2 + MODEL_FIGURES + surface_figures(config) + ALBEDO + RENDERS + BENCH + BAKE_ERRORS
              + SUMMARY_DIFFERENCE]
    files += ["cost/renderer_cost.json", "cost/renderer_cost.md"]
    files += [p for _, p in TABLES.values()]
    files += [f"bakes/{s['name']}.exr" for s in config["surfaces"]]
    return files


CSS = """
body { font-family: system-ui, sans-serif; max-width: 1500px; margin: 1.5em auto; padding: 0 1em; color: #222; }
h1 { margin-bottom: 0.2em; } h2 { border-bottom: 1px solid #ccc; padding-bottom: 0.2em; margin-top: 2em; }
.meta { color: #555; }
figure { margin: 1.2em 0; } figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { color: #333; font-size: 0.95em; margin-top: 0.3em; }
table { border-collapse: collapse; font-size: 0.85em; margin: 0.6em 0; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.5em; text-align: right; }
th { background: #f0f0f0; } td.l, th.l { text-align: left; }
.missing { color: #b00; border: 1px dashed #b00; padding: 0.6em; margin: 1em 0; }
.ok { color: #070; } .failed { color: #b00; font-weight: bold; } .skipped { color: #777; }
details { margin: 0.6em 0; } summary { cursor: pointer; }
.meta { font-size: 0.9em; margin: 0.2em 0; }
table.summary { font-size: 0.82em; } table.summary td { text-align: center; padding: 0.15em 0.3em; }
table.summary th { font-weight: normal; } table.summary th.l { font-weight: bold; }
table.summary img { width: 108px; height: 108px; display: block; margin: auto; image-rendering: auto; }
.wide { overflow-x: auto; }
.caption { font-size: 0.85em; color: #333; max-width: 1250px; }
"""


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


class Page:
    def __init__(self, out, stages):
        self.out = out
        self.stages = stages   # stage name -> status text
        self.parts = []

    def add(self, text):
        self.parts.append(text)

    def missing(self, stage, path):
        status = self.stages.get(stage, "not run")
        self.add(f'<div class="missing">missing: <code>{html.escape(path)}</code> '
                 f'(stage <b>{html.escape(stage)}</b>: {html.escape(status)})</div>')

    def figure(self, stage, path, caption):
        if os.path.isfile(os.path.join(self.out, path)):
            self.add(f'<figure><a href="{html.escape(path)}"><img src="{html.escape(path)}" alt="{html.escape(path)}">'
                     f'</a><figcaption>{html.escape(caption)}</figcaption></figure>')
        else:
            self.missing(stage, path)

    def table(self, stage, path, caption, collapsed=False, long_rows=40):
        full = os.path.join(self.out, path)
        if not os.path.isfile(full):
            self.missing(stage, path)
            return
        rows = read_csv(full)
        if not rows:
            self.missing(stage, path + " (empty)")
            return
        cells = ["<div class='wide'><table><tr>" + "".join(f'<th class="l">{html.escape(h)}</th>' for h in rows[0]) + "</tr>"]
        for r in rows[1:]:
            cells.append("<tr>" + "".join(
                f'<td class="{"l" if not _is_number(c) else ""}">{html.escape(c)}</td>' for c in r) + "</tr>")
        cells.append("</table></div>")
        body = "".join(cells)
        link = f' (<a href="{html.escape(path)}">{html.escape(os.path.basename(path))}</a>)'
        if collapsed or len(rows) > long_rows:  # long tables folded: the page stays readable
            self.add(f"<details><summary>{html.escape(caption)}{link} — {len(rows) - 1} rows, click to show"
                     f"</summary>{body}</details>")
        else:
            self.add(f"<p>{html.escape(caption)}{link}</p>{body}")


def _is_number(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


def stage_statuses(out):
    path = os.path.join(out, "timings.csv")
    if not os.path.isfile(path):
        return {}, []
    rows = read_csv(path)[1:]
    statuses = {}
    for r in rows:
        name = os.path.basename(r[4])[3:-4] if r[4] else ""
        statuses[name] = r[2]
    return statuses, rows


def timing_table(rows):
    total = sum(float(r[3]) for r in rows)
    lines = ['<table><tr><th>#</th><th class="l">stage</th><th class="l">status</th><th>time [s]</th>'
             '<th class="l">log</th></tr>']
    for number, title, status, seconds, log in rows:
        cls = "ok" if status == "ok" else ("skipped" if status.startswith("skipped") else "failed")
        log_cell = f'<a href="{html.escape(log)}">{html.escape(os.path.basename(log))}</a>' if log else ""
        lines.append(f'<tr><td>{number}</td><td class="l">{html.escape(title)}</td>'
                     f'<td class="l {cls}">{html.escape(status)}</td><td>{float(seconds):.1f}</td>'
                     f'<td class="l">{log_cell}</td></tr>')
    lines.append(f'<tr><th></th><th class="l">total</th><th></th><th>{total:.1f}</th><th></th></tr></table>')
    return "".join(lines), total


def read_dicts(path):
    if not os.path.isfile(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def fastest_paths(out):
    """Per bench surface: the fastest mbk row of bench.csv (any kind but the bake) whose max relative
    error is at most MEETS, as (label, evaluations per second, max error)."""
    best = {}
    for r in read_dicts(os.path.join(out, "bench.csv")):
        if r["model"] != "mbk" or r["kind"] == "bake" or float(r["max_rel_error"]) > MEETS:
            continue
        speed = float(r["evals_per_s"])
        if r["surface"] not in best or speed > best[r["surface"]][1]:
            best[r["surface"]] = (path_label(r), speed, float(r["max_rel_error"]))
    return best


def path_label(row):
    """A short name of a bench row: a table's layout and shape (3-channel lookups marked), else the variant."""
    if row["kind"] in ("lut", "lut3"):
        form = ", closed-form P" if "closed-form" in row["variant"] else ", P~ table" if "P~" in row["variant"] else ""
        return f"{row['layout']} {row['shape']}{form}" + (", RGB" if row["kind"] == "lut3" else "")
    return row["variant"]


def nearest_bench_surface(sigma_s_um):
    return min(BENCH_SURFACE_SIGMA_UM, key=lambda k: abs(math.log(sigma_s_um / BENCH_SURFACE_SIGMA_UM[k])))


def percent(value):
    value = float(value)
    if value >= 1.0:
        return f"{100 * value:.0f}%"
    return f"{100 * value:.2g}%" if value >= 0.01 else f"{100 * value:.1g}%" if value >= 1e-4 else f"{value:.1e}"


def summary_section(page, out, config):
    """The first screen: per default material the POV-Ray and Blender renders (one exposure), their
    error against brdf eval, the fastest path that meets MEETS and the bake's error."""
    rows = read_dicts(os.path.join(out, "renders", "summary.csv"))
    if not rows:
        page.missing("summary", "renders/summary.csv")
        return
    by = {(r["surface"], r["renderer"]): r for r in rows}
    bakes = {r["surface"]: r for r in read_dicts(os.path.join(out, "bakes", "bake_errors.csv")) if r["layout"] == "rusinkiewicz"}
    kernel = {r["surface"]: r for r in read_dicts(os.path.join(out, "bakes", "bake_errors.csv")) if r["layout"] == "kernel"}
    fastest = fastest_paths(out)
    surfaces = config["surfaces"]
    head = "".join(f"<th><b>{html.escape(s['name'])}</b><br>{html.escape(s['material'])}, σs/λ {s['sigma_over_lambda']:g}</th>"
                   for s in surfaces)
    lines = [f"<table class='summary'><tr><th></th>{head}</tr>"]
    mitsuba_note = next((r.get("note", "") for r in rows if r["renderer"] == "mitsuba"), "not run")
    mitsuba_title = ("Mitsuba 3<br><small>libbrdf.mitsuba plugin</small>" if not mitsuba_note.startswith(("unavailable", "not run"))
                     else f"Mitsuba 3<br><small>{html.escape(mitsuba_note)}</small>")
    renderers = [("povray", "POV-Ray 3.7<br><small>NAME_Exact</small>", "POV-Ray error"),
                 ("blender", "Blender Cycles<br><small>add-on, LUT mode</small>", "Blender error"),
                 ("mitsuba", mitsuba_title, "Mitsuba error")]
    for renderer, title, _ in renderers:
        cells = []
        for s in surfaces:
            r = by.get((s["name"], renderer))
            cells.append(f"<td><img src='renders/{html.escape(r['image'])}' alt='{renderer} {s['name']}'></td>" if r and r["image"]
                         else "<td class='skipped'>unavailable</td>" if r else "<td class='failed'>missing</td>")
        lines.append(f"<tr><th class='l'>{title}</th>{''.join(cells)}</tr>")
    for renderer, _, title in renderers:
        cells = [f"<td>{percent(by[(s['name'], renderer)]['median_relative_error'])} / "
                 f"{percent(by[(s['name'], renderer)]['p95_relative_error'])}</td>"
                 if by.get((s["name"], renderer), {}).get("median_relative_error") else "<td></td>" for s in surfaces]
        lines.append(f"<tr><th class='l'>{title}<br><small>median / p95 vs brdf eval</small></th>{''.join(cells)}</tr>")
    cells = []
    for s in surfaces:
        bench = nearest_bench_surface(s["sigma_s_um"])
        label, speed, error = fastest.get(bench, ("none", 0.0, 0.0))
        cells.append(f"<td>{html.escape(label)}<br>{speed / 1e6:.3g} M lookups/s, "
                     f"max {error:.1g}<br><small>(bench: {bench})</small></td>")
    lines.append(f"<tr><th class='l'>fastest mbk path<br><small>max error ≤ {MEETS:g}</small></th>{''.join(cells)}</tr>")
    cells = [f"<td>{percent(bakes[s['name']]['bake_max_relative'])} / {percent(bakes[s['name']]['bake_max_relative_to_horizon'])}"
             f"<br><small>kernel {float(kernel[s['name']]['bake_max_relative']):.1g}</small></td>"
             if s["name"] in bakes and s["name"] in kernel else "<td></td>" for s in surfaces]
    shape = next(iter(bakes.values()))["shape"] if bakes else ""
    lines.append(f"<tr><th class='l'>bake max error<br><small>rusinkiewicz {html.escape(shape)}, θ ≤ 85° / to horizon "
                 "(<a href='#bake-errors'>why</a>)</small></th>" + "".join(cells) + "</tr></table>")
    page.add("".join(lines))
    exposure = rows[0]["exposure"]
    page.add("<p class='caption'>Each default material (mbk, the paper's reference model) on a unit sphere, lit "
             "by one sun of irradiance 1 at 40° from an orthographic camera, black background, the same scene in the "
             "three renderers (Mitsuba: llvm_ad_rgb, direct light, one sample per pixel at a random point of the pixel), "
             f"shown on <b>one exposure</b> (×{float(exposure):.3g}, the 99th percentile of all lit pixels "
             "→ 1/2, tone curve x/(1+x), sRGB): polished spheres show a small bright highlight, rough ones a wide dim "
             "lobe. Error: per pixel and channel |L − L<sub>eval</sub>| / L<sub>eval</sub> with L<sub>eval</sub> = "
             "f<sub>r</sub> cos θi from <code>brdf eval</code> at the pixel's normal, over the lit pixels (every "
             "channel above 1% of the sphere's maximum; silhouette excluded); the same metric for every renderer "
             "(<a href='renders/summary.csv'>summary.csv</a>). Fastest path: the fastest mbk row of "
             "<code>brdf bench</code> with max error ≤ 1e-3 on its surface nearest in σs "
             "(<a href='#bench'>speed vs error</a>).</p>")


def cost_section(page, out):
    """What each material mode costs in the renderer: Cycles and POV-Ray from tools/bench/renderer_cost.py
    (the cost stage), Mitsuba from the summary's run; every ratio against the reference of the same run."""
    page.add("<h2 id='cost'>What each material mode costs in the renderer</h2>")
    path = os.path.join(out, "cost", "renderer_cost.json")
    if not os.path.isfile(path):
        page.missing("cost", "cost/renderer_cost.json")
        return
    with open(path, encoding="utf-8") as f:
        cost = json.load(f)
    meta = cost["meta"]
    lines = ["<table><tr><th class='l'>renderer</th><th class='l'>material mode</th><th class='l'>reference (same run)</th>"
             "<th>threads</th><th>time per sample</th><th>× reference</th></tr>"]

    def row(renderer, mode, reference, threads, time_text, ratio):
        lines.append(f"<tr><td class='l'>{html.escape(renderer)}</td><td class='l'>{html.escape(mode)}</td>"
                     f"<td class='l'>{html.escape(reference)}</td><td>{threads}</td><td>{time_text}</td><td><b>{ratio:.2f}</b></td></tr>")

    principled = f"Principled BSDF, metallic, roughness {meta['principled_roughness']:.3f}"
    for r in cost["cycles"]:
        row(r["renderer"], r["mode"], principled, r["threads"], f"{1e3 * r['seconds_per_sample']:.3g} ms / sample "
            f"({meta['resolution']}² px)", r["ratio"])
    for r in cost["povray"]:
        row(r["renderer"], r["mode"], "plain metallic finish", r["threads"], f"{1e6 * r['seconds_per_pixel']:.3g} µs / pixel",
            r["ratio"])
    mitsuba_path = os.path.join(out, MITSUBA_RUN)
    mitsuba_text = "Mitsuba: not measured in this run (the summary stage's Mitsuba row says why)."
    if os.path.isfile(mitsuba_path):
        with open(mitsuba_path, encoding="utf-8") as f:
            mitsuba = json.load(f)
        measured = [s for s in mitsuba["surfaces_left_to_right"] if s.get("cost")]
        if measured:
            # The material nearest the Cycles/POV-Ray one (Au, sigma_s 0.1 um), and the range over all.
            nearest = min(measured, key=lambda s: abs(math.log(s["surface"]["sigma_s"] / COST_SURFACE_SIGMA_UM)))
            c = nearest["cost"]
            ratios = [s["cost"]["ratio"] for s in measured]
            row(mitsuba["renderer"].split(",")[0], f"libbrdf plugin, {nearest['name']}",
                f"roughconductor, Beckmann α {c['roughconductor']['alpha']:.3f}", "all",
                f"{c['libbrdf_ns_per_sample'] / 1e3:.3g} µs / sample", c["ratio"])
            mitsuba_text = (f"Mitsuba: time per sample of a 64² path-traced sun + sky render (depth 3, "
                            f"{c['samples'] // 4096} samples per pixel), one timed render each after a warm-up, the plugin "
                            f"against Mitsuba's roughconductor with the plugin's proxy α and the material's index at "
                            f"0.55 µm; over the {len(measured)} default materials the ratio spans "
                            f"{min(ratios):.2f}–{max(ratios):.2f} ({html.escape(MITSUBA_RUN)}).")
    lines.append("</table>")
    page.add("".join(lines))
    load = (f" (load average {meta['load_average_1min']:.1f} on {os.cpu_count()} cores at the end: on a busy machine "
            "the ratios carry its noise)" if "load_average_1min" in meta else "")
    page.add(f"<p class='caption'>Cycles (tools/bench/renderer_cost.py): seconds per sample = (t({meta['samples']}) − t(1)) / "
             f"{meta['samples'] - 1} of whole renders (cancels sync, compilation and the write), gold mbk σs 0.1 µm on a "
             "sphere under one sun; the Principled BSDF has the roughness of the FIT's strongest lobe. POV-Ray: seconds "
             "per pixel from two image sizes, NAME_Exact against a plain metallic finish. Each the fastest of "
             f"{meta['repeats']} repeats{load}; ratios against the reference of the same run and thread count "
             f"(<a href='cost/renderer_cost.md'>renderer_cost.md</a>). {mitsuba_text}</p>")


def bake_error_section(page, out):
    """Where the default bakes' error comes from, in numbers measured by bake_errors.py."""
    rows = read_dicts(os.path.join(out, "bakes", "bake_errors.csv"))
    page.add("<h3 id='bake-errors'>Where the bakes' percent-level error comes from</h3>")
    if not rows:
        page.missing("bake", "bakes/bake_errors.csv")
        return
    rus = [r for r in rows if r["layout"] == "rusinkiewicz"]
    ker = [r for r in rows if r["layout"] == "kernel"]
    worst = max(rus, key=lambda r: float(r["bake_max_relative"]))
    horizon = max(rus, key=lambda r: float(r["bake_max_relative_to_horizon"]))
    flank = max(float(r["max_theta_h_2_10"]) for r in rus)
    peak = max(max(float(r["max_theta_h_0_0.5"]), float(r["max_theta_h_0.5_2"])) for r in rus)
    mid = max(float(r["max_theta_0_60"]) for r in rus)
    page.add(
        "<p>The tables above (<code>brdf bake</code>'s default Rusinkiewicz layout, "
        f"{html.escape(rus[0]['shape'])} nodes in θh, θd, φd) interpolate the BRDF linearly between nodes. Measured "
        f"(bake_errors.csv, {html.escape(worst['surface'])} worst): max {percent(worst['bake_max_relative'])} for θi, θs ≤ 85°, "
        f"found at θh = {worst['worst_theta_h']}°, θd = {worst['worst_theta_d']}° (θi {worst['worst_theta_i']}°, θs "
        f"{worst['worst_theta_s']}°, φs {worst['worst_phi_s']}°). By band, over all surfaces: near the specular peak "
        f"(θh &lt; 2°, where the θh axis is densest) at most {percent(peak)}; on the lobe's flank (θh 2–10°, where a "
        f"polished lobe falls by decades between two nodes, and linear interpolation of a steeply falling value "
        f"overshoots in relative terms) up to {percent(flank)}; with both angles ≤ 60° up to {percent(mid)}. Towards "
        f"the horizon (θi or θs &gt; 85°) the values change fastest of all (shadowing, K and cos θ near 0): up to "
        f"{percent(horizon['bake_max_relative_to_horizon'])} ({html.escape(horizon['surface'])}). The kernel layout "
        f"(<code>--layout kernel</code>: the factored form K F P × Σ(g, c) with the angular factor P in closed form and "
        f"only the smooth Σ tabulated) reaches max {max(float(r['bake_max_relative']) for r in ker):.2g} (θ ≤ 85°) and "
        f"{max(float(r['bake_max_relative_to_horizon']) for r in ker):.2g} to the horizon on the same surfaces: use it "
        "(or a finer grid, <code>--target-error</code>) where percent-level errors matter.</p>")
    for item in BAKE_ERRORS:
        page.figure(*item)
    page.table(*TABLES["bake_errors"], "Per surface and layout: the bake's measured error, the sampled largest "
               "error and where it is, the largest per θh band and per horizon band.", collapsed=True)


def brdf_version(brdf):
    try:
        return subprocess.run([brdf, "--version"], capture_output=True, text=True, timeout=30).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", required=True, help="report directory")
    parser.add_argument("--brdf", default="brdf", help="brdf executable (for its version)")
    parser.add_argument("--small", action="store_true", help="the job ran at reduced size")
    parser.add_argument("--materials", default=brdfcli.MATERIALS_FILE)
    args = parser.parse_args()
    config = brdfcli.load_materials(args.materials)
    statuses, timing_rows = stage_statuses(args.out)
    page = Page(args.out, statuses)
    timing_html, total = timing_table(timing_rows) if timing_rows else ("<p>no timings.csv</p>", 0.0)

    mode = "reduced size (--small)" if args.small else "full size"
    now = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
    page.add(f"<h1>libbrdf main job report</h1><p class='meta'>{now}; {html.escape(mode)}; "
             f"brdf {html.escape(brdf_version(args.brdf))}; {html.escape(platform.node())}, {os.cpu_count()} cores; "
             f"job time {total:.0f} s (<a href='#stages'>stages</a>). Models: Butler, Nauyoks &amp; Marciniak, Opt. "
             f"Express 23, 29100 (2015). Angles in degrees (φs = 180° is in-plane forward scatter), lengths in µm, "
             f"BRDFs in 1/sr.</p>")
    summary_section(page, args.out, config)
    for item in SUMMARY_DIFFERENCE:
        page.figure(*item)
    page.add("<p>Contents: <a href='#cost'>renderer cost</a> · <a href='#materials'>materials and bakes</a> · <a href='#bake-errors'>why the bakes' "
             "error</a> · <a href='#fig2'>Fig. 2</a> · <a href='#models'>models</a> · <a href='#energy'>energy</a> · "
             "<a href='#bench'>speed vs error</a> · <a href='#renders'>model comparisons</a> · "
             "<a href='#stages'>stages and timings</a></p>")
    cost_section(page, args.out)

    page.add("<h2 id='materials'>Materials and bakes</h2>")
    page.table(*TABLES["surfaces"],
               f"The default material set at λ = {config['design_wavelength_um']:g} µm: g at specular, the paper's "
               f"regime (g < {brdfcli.G_POLISHED:g} polished, g > {brdfcli.G_VERY_ROUGH:g} very rough), K and the "
               "specular spike R_spec at θi = 30° and 60°.")
    page.table(*TABLES["bakes"], "The baked tables (mbk, Rusinkiewicz layout, R/G/B = "
               + ", ".join(f"{w:g}" for w in config["bake_wavelengths_um"])
               + " µm) with the error the bake measured against direct evaluation.")
    bake_error_section(page, args.out)

    page.add("<h2 id='fig2'>Fig. 2: R_d between 2F/Q and S</h2>")
    for item in FIG2:
        page.figure(*item)
    page.table(*TABLES["fig2"], "Per map: R_d at specular, mean R_d over the inner (θs ≤ 20°) and outer "
               "(θs ≥ 70°) rings, and the maximum.", collapsed=True)

    page.add("<h2 id='models'>The models per surface</h2>")
    for item in MODEL_FIGURES + surface_figures(config):
        page.figure(*item)

    page.add("<h2 id='energy'>Energy: directional albedo</h2>")
    for item in ALBEDO:
        page.figure(*item)
    page.table(*TABLES["albedo"], "Per surface, model and K mode: the albedo at θi = 0, 60, 80°, its largest "
               "value and where, and the θi range where it exceeds 1 (README, “Energy”).")

    page.add("<h2 id='bench'>Speed against error</h2>")
    for item in BENCH:
        page.figure(*item)
    page.table(*TABLES["bench"], "brdf bench --quick: every fast path's speed and its error against the "
               "reference.")

    page.add("<h2 id='renders'>Model comparisons and FIT renders</h2>")
    for item in RENDERS:
        page.figure(*item)
    page.table(*TABLES["fit_scene_errors"], "FIT mode: every fit's measured per-pixel error against the exact "
               "radiance f_r cos θi (median, 95th percentile; orthographic spheres lit by one sun at 10–100° from "
               "the camera, θi, θs ≤ 70°, pixels above 1% of the maximum), with its number of lobes: Cycles "
               "(Beckmann), EEVEE (signed GGX through Shader to RGB; EEVEE's own GGX deviates from it, see the "
               "README) and POV-Ray (Blinn and Phong). The exact one-sun renders are the comparison figures above.")
    page.table(*TABLES["fit_errors_by_angle"], "FIT mode by the angle between sun and camera: the error each fit "
               "states (and the add-on panel and the include header show) per band, measured on two suns inside "
               "the band; 'meets_5_20': median <= 5% and p95 <= 20%. Lobes over the half vector that may vary "
               "with N.V alone cannot follow MBK beyond ~90 deg (docs/fit.md); EEVEE's GGX is not GGX at "
               "roughness 0.375-0.875.", collapsed=True)
    page.table(*TABLES["summary"], "The summary's numbers: per material and renderer the lit pixels, the median "
               "and 95th-percentile relative error against brdf eval, the peak radiance and the common exposure.",
               collapsed=True)

    page.add("<h2 id='stages'>Stages and timings</h2>")
    page.add(f"<p>Each stage of <code>run.sh</code>, its status and wall time (logs beside this page).</p>{timing_html}")

    text = ("<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>libbrdf main job report</title>"
            f"<style>{CSS}</style></head><body>" + "\n".join(page.parts) + "</body></html>\n")
    tmp = os.path.join(args.out, "index.html.tmp")
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, os.path.join(args.out, "index.html"))
    missing = [p for p in promised_files(args.materials) if not os.path.isfile(os.path.join(args.out, p))
               and p != "index.html"]
    if missing:
        print(f"index.html written; {len(missing)} promised file(s) missing: {', '.join(missing)}", file=sys.stderr)


if __name__ == "__main__":
    main()
