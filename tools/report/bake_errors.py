"""Where the default bakes' error comes from (bake_materials.py calls this after baking).

The Rusinkiewicz tables interpolate the BRDF linearly between nodes in (theta_h, theta_d, phi_d).
Their measured max relative error (`brdf bake`'s own measurement, bakes.csv) is compared here with
the same surface baked in the kernel layout (the factored form K F P x Sigma(g, c), lut.h), and
located: at seeded random angle triples (half of them near the specular direction, where the lobes
are) the table's G channel (0.55 um) is looked up and compared with the model (libbrdf.Model, the
values of `brdf eval`), over values above 1e-3 of the largest sampled one (the bake's floor), and
the relative error is binned by the half-vector angle theta_h (from the normal) and by the larger
polar angle max(theta_i, theta_s).

Writes into the bakes directory: bake_errors.csv (per surface and layout: the measured errors, where
the largest one is, and the largest per theta_h band and per horizon band) and bake_errors.png.
"""
import csv
import os
import subprocess

import numpy as np

import brdfcli

THETA_H_EDGES = [0.0, 0.5, 2.0, 10.0, 30.0, 90.0]  # deg
HORIZON_EDGES = [0.0, 60.0, 85.0, 90.0]            # deg, max(theta_i, theta_s)
FLOOR = 1e-3
CHANNEL, WAVELENGTH = 1, 0.55  # the G channel of the bakes (0.65, 0.55, 0.45 um)


def sample_angles(count, seed=1):
    """theta_i, theta_s (uniform in solid angle up to 89.9 deg) and phi_s in [0, 180]; half of the
    triples near the specular direction (theta_s = theta_i +- 2 deg, phi_s = 180 -+ 3 deg)."""
    rng = np.random.default_rng(seed)
    top = np.cos(np.radians(89.9))
    ti = np.degrees(np.arccos(rng.uniform(top, 1.0, count)))
    ts = np.degrees(np.arccos(rng.uniform(top, 1.0, count)))
    ps = rng.uniform(0.0, 180.0, count)
    near = count // 2
    ts[:near] = np.clip(ti[:near] + rng.normal(0.0, 2.0, near), 0.0, 89.9)
    ps[:near] = np.clip(180.0 - np.abs(rng.normal(0.0, 3.0, near)), 0.0, 180.0)
    return ti, ts, ps


def half_and_difference_angles(ti, ts, ps):
    """theta_h (half vector from the normal) and theta_d (light from the half vector), degrees
    (Rusinkiewicz 1998, the table's first two axes; phi_i = 0)."""
    t_i, t_s, p_s = np.radians(ti), np.radians(ts), np.radians(ps)
    light = np.stack([np.sin(t_i), np.zeros_like(t_i), np.cos(t_i)], -1)
    view = np.stack([np.sin(t_s) * np.cos(p_s), np.sin(t_s) * np.sin(p_s), np.cos(t_s)], -1)
    half = light + view
    half /= np.linalg.norm(half, axis=-1, keepdims=True)
    return (np.degrees(np.arccos(np.clip(half[:, 2], -1, 1))),
            np.degrees(np.arccos(np.clip(np.sum(light * half, -1), -1, 1))))


def band_maxima(rel, value, edges, where):
    return [float(rel[where & (value >= lo) & (value < hi)].max(initial=0.0)) for lo, hi in zip(edges[:-1], edges[1:])]


def bake_kernel(brdf, surface, wavelengths, path):
    """`brdf bake --layout kernel` of the surface; returns its stdout (the measured error)."""
    command = [brdf, "bake", "--model", "mbk", "--material", surface["material"], "--sigma-s",
               f"{surface['sigma_s_um']:.6g}", "--lc", f"{surface['lc_um']:g}", "--wavelength", wavelengths,
               "--layout", "kernel", "--output", path]
    run = subprocess.run(command, capture_output=True, text=True)
    if run.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed ({run.returncode}): {run.stderr.strip()}")
    return run.stdout


def analyse(brdf, config, bakes_dir, samples):
    module = brdfcli.module_for(brdf)
    if module is None:
        brdfcli.progress("bake_errors: no Python module beside brdf (build libbrdf_python): error map skipped")
        return None
    wavelengths = ",".join(f"{w:g}" for w in config["bake_wavelengths_um"])
    ti, ts, ps = sample_angles(samples)
    theta_h, theta_d = half_and_difference_angles(ti, ts, ps)
    horizon = np.maximum(ti, ts)
    rows, curves = [], {}
    for s in config["surfaces"]:
        model = module.Model("mbk", material=s["material"], sigma_s=s["sigma_s_um"], lc=s["lc_um"], wavelength=WAVELENGTH)
        exact = model(ti, ts, ps)
        kernel_path = os.path.join(bakes_dir, f"{s['name']}.kernel.exr")
        bake_kernel(brdf, s, wavelengths, kernel_path)
        for layout, path in [("rusinkiewicz", os.path.join(bakes_dir, f"{s['name']}.exr")), ("kernel", kernel_path)]:
            lut = module.Lut.open(path)
            looked_up = lut(ti, ts, ps, channel=CHANNEL)
            counted = exact > FLOOR * exact.max()
            rel = np.where(counted, np.abs(looked_up - exact) / np.where(counted, exact, 1.0), 0.0)
            inside = counted & (horizon <= 85.0)
            worst = int(np.argmax(np.where(inside, rel, 0.0)))
            error = lut.error
            rows.append({
                "surface": s["name"], "layout": layout, "shape": "x".join(str(n) for n in lut.shape),
                "bake_max_relative": f"{error['max_relative']:.3g}", "bake_max_relative_to_horizon": f"{error['max_relative_all']:.3g}",
                "sampled_max_relative": f"{rel[inside].max():.3g}",
                "worst_theta_i": f"{ti[worst]:.1f}", "worst_theta_s": f"{ts[worst]:.1f}", "worst_phi_s": f"{ps[worst]:.1f}",
                "worst_theta_h": f"{theta_h[worst]:.2f}", "worst_theta_d": f"{theta_d[worst]:.1f}",
                **{f"max_theta_h_{lo:g}_{hi:g}": f"{m:.3g}" for lo, hi, m in
                   zip(THETA_H_EDGES[:-1], THETA_H_EDGES[1:], band_maxima(rel, theta_h, THETA_H_EDGES, inside))},
                **{f"max_theta_{lo:g}_{hi:g}": f"{m:.3g}" for lo, hi, m in
                   zip(HORIZON_EDGES[:-1], HORIZON_EDGES[1:], band_maxima(rel, horizon, HORIZON_EDGES, counted))},
            })
            curves[(s["name"], layout)] = (band_maxima(rel, theta_h, THETA_H_EDGES, inside),
                                           band_maxima(rel, horizon, HORIZON_EDGES, counted))
            brdfcli.progress(f"bake_errors {s['name']} {layout}: sampled max {rel[inside].max():.3g}")
    with open(os.path.join(bakes_dir, "bake_errors.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    plot(curves, config, os.path.join(bakes_dir, "bake_errors.png"), samples)
    return rows


def plot(curves, config, path, samples):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(12.8, 5.2), sharey=True)
    colours = plt.get_cmap("viridis")(np.linspace(0, 0.9, len(config["surfaces"])))
    for colour, s in zip(colours, config["surfaces"]):
        for layout, style in [("rusinkiewicz", "-o"), ("kernel", "--s")]:
            by_h, by_horizon = curves[(s["name"], layout)]
            label = f"{s['name']} {layout}"
            axes[0].plot(range(len(by_h)), np.maximum(by_h, 1e-8), style, color=colour, ms=4, label=label)
            axes[1].plot(range(len(by_horizon)), np.maximum(by_horizon, 1e-8), style, color=colour, ms=4)
    axes[0].set_xticks(range(len(THETA_H_EDGES) - 1),
                       [f"{lo:g}–{hi:g}°" for lo, hi in zip(THETA_H_EDGES[:-1], THETA_H_EDGES[1:])])
    axes[0].set_xlabel("half-vector angle θh (θi, θs ≤ 85°)")
    axes[1].set_xticks(range(len(HORIZON_EDGES) - 1),
                       [f"{lo:g}–{hi:g}°" for lo, hi in zip(HORIZON_EDGES[:-1], HORIZON_EDGES[1:])])
    axes[1].set_xlabel("max(θi, θs): towards the horizon")
    axes[0].set_ylabel("max relative error of the table (G, 0.55 µm)")
    for ax in axes:
        ax.set_yscale("log")
        ax.axhline(1e-3, color="gray", lw=0.6, ls=":")
        ax.grid(True, alpha=0.3)
    fig.legend(*axes[0].get_legend_handles_labels(), loc="lower center", ncol=len(config["surfaces"]), fontsize=7,
               frameon=False)
    fig.suptitle(f"Default bakes (mbk, solid: Rusinkiewicz, dashed: kernel layout) against the model at {samples} "
                 "random angle triples (half near specular), values above 1e-3 of the maximum", fontsize=10)
    fig.tight_layout(rect=(0, 0.09, 1, 0.95))
    temporary = path + ".tmp.png"
    fig.savefig(temporary, dpi=100)
    plt.close(fig)
    os.replace(temporary, path)
