#!/usr/bin/python3
"""Energy: the directional albedo (white furnace) of every BRDF model for the default material set.

For each surface (tools/report/materials.json) at the design wavelength, `brdf albedo` gives
a(theta_i) = integral of f cos theta_s over the hemisphere + R_spec (the specular spike included;
libbrdf/include/libbrdf/albedo.h). Models whose amplitude is K (mbk, mbk-fg, microfacet with
rho_s = K) in both K modes (plane, eq. 13; tis). Writes
  albedo.csv          surface, model, k_mode, theta_i, albedo, lobe, specular, error_estimate
  albedo_summary.csv  per surface, model and K mode: albedo at 0, 60, 80 deg, the largest and where,
                      and the theta_i range where it exceeds 1
  albedo.png          a(theta_i) per surface (one panel each), the line a = 1 marked
"""
import argparse
import csv
import io
import multiprocessing
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import brdfcli  # noqa: E402

# (model, k_mode or None when the model has no K)
CURVES = [("mbk", "plane"), ("mbk", "tis"), ("mbk-fg", "plane"), ("mbk-fg", "tis"), ("microfacet", "plane"),
          ("microfacet", "tis"), ("mbk-polished", None), ("bk", None), ("bk-modified", None)]
STYLE = {"mbk": "black", "mbk-fg": "tab:brown", "microfacet": "tab:red", "mbk-polished": "tab:blue",
         "bk": "tab:green", "bk-modified": "tab:purple"}
THETA_I = [0, 10, 20, 30, 40, 50, 60, 70, 75, 80, 82.5, 85, 87.5, 89]
THETA_I_SMALL = [0, 30, 60, 80, 85, 89]


def albedo_rows(job):
    brdf, surface, model, k_mode, angles = job
    command = [brdf, "albedo", "--model", model, "--material", surface["material"],
               "--sigma-s", f"{surface['sigma_s_um']:.17g}", "--lc", f"{surface['lc_um']:.17g}",
               "--wavelength", f"{surface['wavelength']:.17g}", "--theta-i", ",".join(f"{a:g}" for a in angles)]
    if k_mode:
        command += ["--k-mode", k_mode]
    run = subprocess.run(command, capture_output=True, text=True)
    if run.returncode != 0:
        raise brdfcli.BrdfError(f"{' '.join(command)} failed ({run.returncode}): {run.stderr.strip()}")
    rows = list(csv.DictReader(io.StringIO(run.stdout)))
    return [{"surface": surface["name"], "model": model, "k_mode": k_mode or "-", **row} for row in rows]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--brdf", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--small", action="store_true", help="fewer incidence angles")
    parser.add_argument("--materials", default=brdfcli.MATERIALS_FILE)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    config = brdfcli.load_materials(args.materials)
    surfaces = config["surfaces"]
    angles = THETA_I_SMALL if args.small else THETA_I
    for s in surfaces:
        s["wavelength"] = config["design_wavelength_um"]
    jobs = [(args.brdf, s, model, k_mode, angles) for s in surfaces for model, k_mode in CURVES]
    with multiprocessing.Pool(max(1, min(2, os.cpu_count() or 1))) as pool:
        results = []
        for done, rows in enumerate(pool.imap(albedo_rows, jobs), 1):
            results += rows
            if done % len(CURVES) == 0:
                brdfcli.progress(f"albedo: {done // len(CURVES)}/{len(surfaces)} surfaces")

    fields = ["surface", "model", "k_mode", "theta_i", "albedo", "lobe", "specular", "error_estimate"]
    with open(os.path.join(args.out, "albedo.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields)
        writer.writeheader()
        writer.writerows(results)

    summary = []
    for s in surfaces:
        for model, k_mode in CURVES:
            rows = [r for r in results if r["surface"] == s["name"] and r["model"] == model and
                    r["k_mode"] == (k_mode or "-")]
            by_angle = {float(r["theta_i"]): float(r["albedo"]) for r in rows}
            top = max(by_angle, key=by_angle.get)
            above = [a for a, v in by_angle.items() if v > 1.0]
            summary.append({"surface": s["name"], "model": model, "k_mode": k_mode or "-",
                            "albedo_0": f"{by_angle.get(0.0, float('nan')):.4f}",
                            "albedo_60": f"{by_angle.get(60.0, float('nan')):.4f}",
                            "albedo_80": f"{by_angle.get(80.0, float('nan')):.4f}",
                            "max_albedo": f"{by_angle[top]:.4f}", "at_theta_i": f"{top:g}",
                            "above_1": f"{min(above):g}-{max(above):g} deg" if above else "never"})
    with open(os.path.join(args.out, "albedo_summary.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(summary[0]))
        writer.writeheader()
        writer.writerows(summary)

    columns = 4
    rows_n = (len(surfaces) + columns - 1) // columns
    fig, axes = plt.subplots(rows_n, columns, figsize=(4.2 * columns, 3.4 * rows_n), squeeze=False)
    for ax, s in zip(axes.ravel(), surfaces):
        for model, k_mode in CURVES:
            rows = [r for r in results if r["surface"] == s["name"] and r["model"] == model and
                    r["k_mode"] == (k_mode or "-")]
            label = model + (f" ({k_mode})" if k_mode else "")
            ax.plot([float(r["theta_i"]) for r in rows], [float(r["albedo"]) for r in rows], color=STYLE[model],
                    ls="--" if k_mode == "tis" else "-", lw=1.4, marker=".", label=label)
        ax.axhline(1.0, color="gray", lw=0.8, ls=":")
        ax.set_ylim(0, 1.6)
        ax.set_xlim(0, 90)
        ax.set_title(f"{s['name']} (σs/λ = {s['sigma_over_lambda']:g}, l_c = {s['lc_um']:g} µm)", fontsize=9)
        ax.set_xlabel("θi [deg]")
        ax.set_ylabel("directional albedo")
    for ax in axes.ravel()[len(surfaces):]:
        ax.axis("off")
    handles, labels = axes.ravel()[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower right", fontsize=8, ncol=2)
    fig.suptitle(f"White furnace: directional albedo (spike included) at λ = {config['design_wavelength_um']:g} µm; "
                 "above 1 = energy created (axis clipped at 1.6)", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "albedo.png"), dpi=110)
    print(f"albedo: {len(results)} values for {len(surfaces)} surfaces -> {args.out}/albedo.csv, albedo_summary.csv, "
          "albedo.png")


if __name__ == "__main__":
    main()
