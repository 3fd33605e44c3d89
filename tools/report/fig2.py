#!/usr/bin/python3
"""Reproduces Fig. 2 of Butler, Nauyoks & Marciniak (2015): the relative difference
R_d = |2F/Q - S| / (2F/Q) (eq. 23) over the scattered hemisphere for five complex indices at
theta_i = 15, 30, 45, 60 deg, as a 5 x 4 grid of polar maps (phi_s as the polar angle with
phi_s = 180 deg, in-plane forward scatter, on the right as in the paper; theta_s as the radius).

Every value is the `rd` quantity of `brdf eval --model rd --n N --k K`, taken through tools/report/brdfcli.py
(the libbrdf Python module, bit-identical to brdf eval).

Writes into --out:
  fig2.png          the 5 x 4 maps
  fig2_rd.npz       theta_s, phi_s (1D, degrees), theta_i (4), n, k (5), rd [5, 4, theta_s, phi_s]
  fig2_summary.csv  per map: R_d at specular, mean over the inner (theta_s <= 20) and outer
                    (theta_s >= 70) rings, maximum and where it is
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import brdfcli  # noqa: E402

# The paper's five indices n + i kappa and four incident angles (section 3.1).
INDICES = [(4.0, 10.0), (1.5, 1.0), (1.4, 0.0), (1.7, 5.0), (0.25, 3.0)]
THETA_I = [15.0, 30.0, 45.0, 60.0]
INNER_RING_MAX = 20.0   # theta_s <= this: the "inner ring" of the summary
OUTER_RING_MIN = 70.0   # theta_s >= this: the "outer ring"


def index_label(n, k):
    if k == 0:
        return f"ñ = {n:g}"
    return f"ñ = {n:g} + {k:g}i" if k != 1 else f"ñ = {n:g} + i"


def compute(brdf, small):
    # Node grids that contain every theta_i exactly and phi_s = 180, so the specular point is a node.
    step_t, step_p = (3.0, 6.0) if small else (1.0, 2.0)
    theta_s = np.arange(0.0, 90.0, step_t)
    phi_s = np.arange(0.0, 360.0 + step_p / 2, step_p)
    TS, PS = np.meshgrid(theta_s, phi_s, indexing="ij")
    rd = np.empty((len(INDICES), len(THETA_I), len(theta_s), len(phi_s)))
    for a, (n, k) in enumerate(INDICES):
        brdfcli.progress(f"R_d for {index_label(n, k)}")
        # One batch per index: all four incident angles at once.
        TI = np.array(THETA_I)[:, None, None] * np.ones_like(TS)
        rd[a] = brdfcli.evaluate(brdf, "rd", TI, TS, PS, n=n, k=k)
    return theta_s, phi_s, rd


def summary_rows(theta_s, phi_s, rd):
    rows = []
    j180 = int(np.argmin(abs(phi_s - 180.0)))
    for a, (n, k) in enumerate(INDICES):
        for b, ti in enumerate(THETA_I):
            m = rd[a, b]
            i_spec = int(np.argmin(abs(theta_s - ti)))
            imax = np.unravel_index(int(np.argmax(m)), m.shape)
            rows.append({
                "n": n, "kappa": k, "theta_i_deg": ti,
                "rd_at_specular": m[i_spec, j180],
                "mean_inner_ring": m[theta_s <= INNER_RING_MAX].mean(),
                "mean_outer_ring": m[theta_s >= OUTER_RING_MIN].mean(),
                "max": m[imax], "theta_s_at_max": theta_s[imax[0]], "phi_s_at_max": phi_s[imax[1]],
            })
    return rows


def plot(theta_s, phi_s, rd, path):
    vmax = max(1.0, np.ceil(rd.max() * 10) / 10)
    fig, axes = plt.subplots(len(INDICES), len(THETA_I), figsize=(14, 15), subplot_kw={"projection": "polar"},
                             gridspec_kw={"hspace": 0.3, "wspace": 0.45})
    P, T = np.meshgrid(np.radians(phi_s), theta_s)
    letters = "abcdefghijklmnopqrst"
    for a, (n, k) in enumerate(INDICES):
        for b, ti in enumerate(THETA_I):
            ax = axes[a, b]
            ax.grid(False)  # pcolormesh would remove it; added back below
            ax.set_theta_zero_location("W")   # phi_s = 0 (back-scatter) left, 180 (forward) right
            mesh = ax.pcolormesh(P, T, rd[a, b], shading="gouraud", cmap="viridis", vmin=0.0, vmax=vmax,
                                 rasterized=True)
            ax.contour(P, T, rd[a, b], levels=[0.05, 0.2], colors="white", linewidths=0.7,
                       linestyles=["dashed", "solid"], alpha=0.85)
            ax.plot([np.pi, np.pi], [0, 90], ":", color="black", lw=1.4)  # in-plane forward line
            ax.plot([np.pi], [ti], marker="*", color="red", markersize=9, markeredgecolor="white",
                    markeredgewidth=0.6, linestyle="none")  # specular point, R_d = 0
            ax.set_ylim(0, 90)
            ax.set_yticks([30, 60, 90])
            ax.set_yticklabels(["30°", "60°", "90°"], fontsize=6, color="white")
            ax.set_rlabel_position(315)
            ax.set_xticks(np.radians([0, 90, 180, 270]))
            ax.set_xticklabels(["0°", "90°", "180°", "270°"], fontsize=7)
            ax.tick_params(axis="x", pad=0)
            ax.grid(color="white", alpha=0.35, lw=0.5)
            ax.set_title(f"({letters[a * len(THETA_I) + b]}) {index_label(n, k)}, θi = {ti:g}°", fontsize=9, pad=9)
    cbar = fig.colorbar(mesh, ax=axes, shrink=0.5, pad=0.03, aspect=30)
    cbar.set_label("$R_d$ = |2F/Q − S| / (2F/Q)  (eq. 23)")
    fig.suptitle("Fig. 2 reproduced: relative difference $R_d$ between 2F/Q and S over the scattered hemisphere\n"
                 "polar angle φs (180° = in-plane forward, dotted line; 0° = back-scatter), radius θs; "
                 "★ specular point ($R_d$ = 0); white contours: dashed $R_d$ = 0.05, solid $R_d$ = 0.2", fontsize=11, y=0.945)
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--brdf", required=True, help="path of the brdf executable")
    parser.add_argument("--out", required=True, help="output directory")
    parser.add_argument("--small", action="store_true", help="coarser grid (3 x 6 deg instead of 1 x 2 deg)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    theta_s, phi_s, rd = compute(args.brdf, args.small)
    np.savez(os.path.join(args.out, "fig2_rd.npz"), theta_s=theta_s, phi_s=phi_s, theta_i=np.array(THETA_I),
             n=np.array([n for n, _ in INDICES]), k=np.array([k for _, k in INDICES]), rd=rd)
    rows = summary_rows(theta_s, phi_s, rd)
    with open(os.path.join(args.out, "fig2_summary.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        for r in rows:
            writer.writerow({key: (f"{v:.6g}" if isinstance(v, float) else v) for key, v in r.items()})
    brdfcli.progress("plotting fig2.png")
    plot(theta_s, phi_s, rd, os.path.join(args.out, "fig2.png"))


if __name__ == "__main__":
    try:
        main()
    except brdfcli.BrdfError as e:
        sys.exit(f"fig2: {e}")
