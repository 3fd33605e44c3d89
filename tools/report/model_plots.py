#!/usr/bin/python3
"""In-plane and polar plots of the BRDF models for each surface of the default material set.

For each surface (tools/report/materials.json) at the design wavelength:
  models_<name>.png    rows theta_i = 30, 60 deg; left: in-plane BRDF of every model against a signed
                       theta_s (negative: back-scatter side, phi_s = 0; positive: forward, phi_s = 180),
                       log value axis, the paper's regimes of g(theta_i, theta_s) shaded; right: the
                       same as a polar lobe diagram (radius = log10 of the value)
and for all surfaces:
  models_overview.png    mbk in-plane at theta_i = 30 deg, every surface on one log axis
  models_hemisphere.png  every model over the scattered hemisphere at theta_i = 30 deg (log colour)
  surfaces.csv           per surface: sigma_s, l_c, g at specular, regime, K, R_spec at 30 and 60 deg
  models_inplane.npz     the in-plane curves (signed theta_s, values per surface, model, theta_i)

Every value comes from libbrdf through tools/report/brdfcli.py (the Python module, bit-identical to `brdf eval`).
"""
import argparse
import csv
import multiprocessing
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import brdfcli  # noqa: E402
from brdfcli import G_POLISHED, G_VERY_ROUGH  # noqa: E402

MODELS = ["mbk", "mbk-polished", "mbk-rough", "bk", "bk-modified", "microfacet"]
STYLE = {
    "mbk": dict(color="black", lw=2.4, ls="-"),
    "mbk-polished": dict(color="tab:blue", lw=1.5, ls="--"),
    "mbk-rough": dict(color="tab:orange", lw=1.5, ls="--"),
    "bk": dict(color="tab:green", lw=1.5, ls=":"),
    "bk-modified": dict(color="tab:purple", lw=1.5, ls="-."),
    "microfacet": dict(color="tab:red", lw=1.2, ls="-"),
}
THETA_I = [30.0, 60.0]
HEMI_THETA_I = 30.0
DECADES = 8          # the value axes span this many decades below the top
HEADROOM = 30.0      # models may rise at most this factor above mbk's peak before being clipped


def surface_title(s):
    return (f"{s['material']}, σs = {s['sigma_s_um']:.4g} µm (σs/λ = {s['sigma_over_lambda']:g}), "
            f"l_c = {s['lc_um']:g} µm, λ = {s['wavelength']:g} µm")


def inplane_grid(small):
    step = 0.5 if small else 0.25
    x = np.arange(-89.5, 89.5 + step / 2, step)   # contains every theta_i of THETA_I exactly
    return x, np.abs(x), np.where(x >= 0, 180.0, 0.0)


def hemisphere_grid(small):
    theta_s = np.linspace(0.0, 89.0, 30 if small else 60)
    phi_s = np.linspace(0.0, 360.0, 61 if small else 121)
    return theta_s, phi_s


def compute(brdf, surface, small):
    """All values for one surface: one batch per model (in-plane and hemisphere queries)."""
    x, ts_in, ps_in = inplane_grid(small)
    th, ph = hemisphere_grid(small)
    TH, PH = np.meshgrid(th, ph, indexing="ij")
    ti = np.concatenate([np.repeat(THETA_I, x.size), np.full(TH.size, HEMI_THETA_I)])
    ts = np.concatenate([np.tile(ts_in, len(THETA_I)), TH.ravel()])
    ps = np.concatenate([np.tile(ps_in, len(THETA_I)), PH.ravel()])
    n_in = len(THETA_I) * x.size
    params = brdfcli.surface_params(surface, surface["wavelength"])
    inplane, hemi = {}, {}
    for model in MODELS + ["g"]:
        v = brdfcli.evaluate(brdf, model, ti, ts, ps, **params)
        inplane[model] = v[:n_in].reshape(len(THETA_I), x.size)
        hemi[model] = v[n_in:].reshape(TH.shape)
    # Per incident angle: g at specular, K, R_spec (same for every theta_s: query at specular).
    # g at specular is on the in-plane grid already (signed theta_s = +theta_i).
    spec = {"g": np.array([inplane["g"][j, np.flatnonzero(x == ti)[0]] for j, ti in enumerate(THETA_I)])}
    for q in ["k", "r-spec"]:
        spec[q] = brdfcli.evaluate(brdf, q, np.array(THETA_I), np.array(THETA_I), 180.0, **params)
    return dict(x=x, inplane=inplane, hemi=hemi, theta_s=th, phi_s=ph, spec=spec)


def value_limits(values_by_model):
    """Log axis limits on whole decades, anchored on mbk (the reference): the top is at most
    HEADROOM x mbk's peak, the bottom DECADES below the top."""
    ref = np.max(values_by_model["mbk"])
    top = max(np.max(v) for v in values_by_model.values())
    top = 10.0 ** np.ceil(np.log10(min(top, HEADROOM * ref) * 1.5))
    return top / 10.0 ** DECADES, top


def shade_regimes(ax, x, g):
    trans = ax.get_xaxis_transform()
    ax.fill_between(x, 0, 1, where=g < G_POLISHED, transform=trans, color="tab:cyan", alpha=0.13, lw=0)
    ax.fill_between(x, 0, 1, where=g > G_VERY_ROUGH, transform=trans, color="tab:brown", alpha=0.15, lw=0)


def plot_surface(surface, data, path):
    x = data["x"]
    fig = plt.figure(figsize=(15, 10.5))
    grid = fig.add_gridspec(len(THETA_I), 2, width_ratios=[1.35, 1], hspace=0.32, wspace=0.12)
    for row, ti in enumerate(THETA_I):
        values = {m: data["inplane"][m][row] for m in MODELS}
        g = data["inplane"]["g"][row]
        lo, hi = value_limits(values)
        g_spec, k_spec, r_spec = (data["spec"][q][row] for q in ["g", "k", "r-spec"])

        ax = fig.add_subplot(grid[row, 0])
        shade_regimes(ax, x, g)
        for m in MODELS:
            v = np.where(values[m] > 0, values[m], np.nan)
            ax.plot(x, v, label=m, **STYLE[m])
        ax.axvline(ti, color="gray", lw=0.9, ls="--", label="specular direction (θs = θi, φs = 180°)")
        ax.axvline(-ti, color="goldenrod", lw=0.9, ls="--", label="incident direction (θs = θi, φs = 0°)")
        ax.set_yscale("log")
        ax.set_ylim(lo, hi)
        ax.set_xlim(-90, 90)
        ax.set_xticks(np.arange(-90, 91, 15))
        ax.set_xlabel("signed θs [deg]   (< 0: back-scatter side, φs = 0°;  > 0: forward, φs = 180°)")
        ax.set_ylabel("BRDF [1/sr]")
        ax.grid(True, which="major", alpha=0.3)
        ax.set_title(f"θi = {ti:g}°: g(θi, θi) = {g_spec:.3g} → {brdfcli.regime(g_spec)};  K = {k_spec:.4g};  "
                     f"specular spike R_spec = {r_spec:.3g} (a delta, not drawn)", fontsize=10)
        if row == 0:
            handles, labels = ax.get_legend_handles_labels()
            handles += [Patch(color="tab:cyan", alpha=0.3), Patch(color="tab:brown", alpha=0.3)]
            labels += [f"polished: g(θi, θs) < {G_POLISHED:g}", f"very rough: g(θi, θs) > {G_VERY_ROUGH:g}"]
            fig.legend(handles, labels, fontsize=9, loc="upper center", ncol=5, bbox_to_anchor=(0.5, 0.955),
                       frameon=False)

        # Polar lobe diagram: angle = signed theta_s (0 = normal, up), radius = decades above `lo`.
        pax = fig.add_subplot(grid[row, 1], projection="polar")
        pax.set_theta_zero_location("N")
        pax.set_theta_direction(-1)       # forward (positive theta_s) to the right
        pax.set_thetamin(-90)
        pax.set_thetamax(90)
        for m in MODELS:
            with np.errstate(divide="ignore"):
                r = np.log10(np.where(values[m] > 0, values[m], lo) / lo)
            pax.plot(np.radians(x), np.clip(r, 0, None), **STYLE[m])
        pax.set_ylim(0, DECADES)
        ticks = np.arange(0, DECADES + 1, 2)
        pax.set_yticks(ticks)
        pax.set_yticklabels([f"$10^{{{round(np.log10(lo)) + t}}}$" for t in ticks], fontsize=8)
        pax.set_xticks(np.radians(np.arange(-90, 91, 30)))
        pax.annotate("", xy=(np.radians(-ti), 0.5), xytext=(np.radians(-ti), DECADES),
                     arrowprops=dict(arrowstyle="->", color="goldenrod", lw=1.5))
        pax.plot([np.radians(ti)] * 2, [0, DECADES], color="gray", lw=0.8, ls="--")
        pax.set_title(f"polar lobe, θi = {ti:g}° (arrow: incident light; radius: log10 BRDF [1/sr])", fontsize=9)
    fig.suptitle(f"{surface['name']}: {surface_title(surface)}", fontsize=13, y=0.99)
    fig.savefig(path, dpi=90, bbox_inches="tight")
    plt.close(fig)


def plot_overview(surfaces, results, path):
    fig, ax = plt.subplots(figsize=(10, 5.5))
    metals = [s for s in surfaces if s["material"] == surfaces[0]["material"]]
    ramp = iter(plt.cm.plasma(np.linspace(0.0, 0.85, len(metals))))
    colors = [next(ramp) if s in metals else "tab:cyan" for s in surfaces]
    row = THETA_I.index(30.0)
    for s, c in zip(surfaces, colors):
        d = results[s["name"]]
        v = d["inplane"]["mbk"][row]
        ls = "-" if s in metals else "--"
        ax.plot(d["x"], np.where(v > 0, v, np.nan), color=c, ls=ls, lw=1.8,
                label=f"{s['name']}: g(30°,30°) = {d['spec']['g'][row]:.3g}, R_spec = {d['spec']['r-spec'][row]:.2g}")
    top = max(np.max(results[s["name"]]["inplane"]["mbk"][row]) for s in surfaces) * 3
    ax.set_yscale("log")
    ax.set_ylim(top / 1e10, top)
    ax.set_xlim(-90, 90)
    ax.set_xticks(np.arange(-90, 91, 15))
    ax.axvline(30, color="gray", lw=0.8, ls="--")
    ax.set_xlabel("signed θs [deg]   (< 0: back-scatter side, φs = 0°;  > 0: forward, φs = 180°)")
    ax.set_ylabel("mbk BRDF [1/sr]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_title("mbk in the plane of incidence at θi = 30°, λ = 0.55 µm: from polished to very rough "
                 "(R_spec: the specular spike, not drawn)", fontsize=10)
    fig.savefig(path, dpi=90, bbox_inches="tight")
    plt.close(fig)


def plot_hemisphere(surfaces, results, path):
    fig, axes = plt.subplots(len(surfaces), len(MODELS), figsize=(2.3 * len(MODELS) + 1.5, 2.45 * len(surfaces)),
                             subplot_kw={"projection": "polar"}, gridspec_kw={"hspace": 0.35, "wspace": 0.25})
    for r, s in enumerate(surfaces):
        d = results[s["name"]]
        P, T = np.meshgrid(np.radians(d["phi_s"]), d["theta_s"])
        top = np.max(d["hemi"]["mbk"]) * 2
        norm = LogNorm(vmin=top / 1e6, vmax=top)
        for c, m in enumerate(MODELS):
            ax = axes[r, c]
            ax.grid(False)
            v = np.clip(d["hemi"][m], top / 1e6, top)
            mesh = ax.pcolormesh(P, T, v, shading="gouraud", cmap="magma", norm=norm, rasterized=True)
            ax.set_theta_zero_location("W")
            ax.plot([np.pi], [HEMI_THETA_I], marker="o", markerfacecolor="none", markeredgecolor="cyan", markersize=11, markeredgewidth=0.8, linestyle="none")
            ax.set_ylim(0, 90)
            ax.set_yticks([30, 60])
            ax.set_yticklabels([])
            ax.set_xticks(np.radians([0, 90, 180, 270]))
            ax.set_xticklabels([])
            ax.grid(color="white", alpha=0.25, lw=0.5)
            if r == 0:
                ax.set_title(m, fontsize=11, pad=10)
        axes[r, 0].text(-0.35, 0.5, f"{s['name']}\nσs/λ = {s['sigma_over_lambda']:g}", transform=axes[r, 0].transAxes,
                        ha="right", va="center", fontsize=10)
        cbar = fig.colorbar(mesh, ax=axes[r, :], shrink=0.85, pad=0.015, aspect=12)
        cbar.ax.tick_params(labelsize=7)
        cbar.set_label("1/sr", fontsize=8)
    fig.suptitle(f"Every model over the scattered hemisphere at θi = {HEMI_THETA_I:g}°, λ = 0.55 µm "
                 "(polar angle φs with 180° = forward on the right, radius θs; ○ around the specular direction;\n"
                 "log colour per row: 6 decades below 2 × the mbk peak; values above are clipped to the top colour)",
                 fontsize=11)
    fig.savefig(path, dpi=80, bbox_inches="tight")
    plt.close(fig)


def surface_job(job):
    brdf, surface, small, out = job
    brdfcli.progress(f"models for {surface['name']}")
    data = compute(brdf, surface, small)
    plot_surface(surface, data, os.path.join(out, f"models_{surface['name']}.png"))
    return data


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--brdf", required=True, help="path of the brdf executable")
    parser.add_argument("--out", required=True, help="output directory")
    parser.add_argument("--small", action="store_true", help="coarser angular grids")
    parser.add_argument("--materials", default=brdfcli.MATERIALS_FILE, help="material set (JSON)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    config = brdfcli.load_materials(args.materials)
    surfaces = config["surfaces"]
    for s in surfaces:
        s["wavelength"] = config["design_wavelength_um"]
    # Surfaces in parallel (the time goes mostly into matplotlib).
    jobs = [(args.brdf, s, args.small, args.out) for s in surfaces]
    with multiprocessing.Pool(min(len(jobs), os.cpu_count() or 1)) as pool:
        results = dict(zip([s["name"] for s in surfaces], pool.map(surface_job, jobs)))

    brdfcli.progress("overview and hemisphere plots")
    plot_overview(surfaces, results, os.path.join(args.out, "models_overview.png"))
    plot_hemisphere(surfaces, results, os.path.join(args.out, "models_hemisphere.png"))

    with open(os.path.join(args.out, "surfaces.csv"), "w", newline="") as f:
        w = csv.writer(f)
        header = ["name", "material", "sigma_s_um", "sigma_over_lambda", "lc_um", "wavelength_um"]
        for ti in THETA_I:
            header += [f"g_spec_{ti:g}", f"regime_{ti:g}", f"K_{ti:g}", f"R_spec_{ti:g}"]
        w.writerow(header)
        for s in surfaces:
            sp = results[s["name"]]["spec"]
            row = [s["name"], s["material"], f"{s['sigma_s_um']:.4g}", s["sigma_over_lambda"], s["lc_um"], s["wavelength"]]
            for j in range(len(THETA_I)):
                row += [f"{sp['g'][j]:.4g}", brdfcli.regime(sp["g"][j]), f"{sp['k'][j]:.5g}", f"{sp['r-spec'][j]:.4g}"]
            w.writerow(row)
    np.savez(os.path.join(args.out, "models_inplane.npz"), signed_theta_s=results[surfaces[0]["name"]]["x"],
             theta_i=np.array(THETA_I), surfaces=np.array([s["name"] for s in surfaces]), models=np.array(MODELS),
             values=np.array([[results[s["name"]]["inplane"][m] for m in MODELS] for s in surfaces]))


if __name__ == "__main__":
    try:
        main()
    except brdfcli.BrdfError as e:
        sys.exit(f"model_plots: {e}")
