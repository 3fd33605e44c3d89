"""What the POV-Ray and Blender model comparisons share, so that they show the same thing the same way
(tools/render_povray_comparison.py, tools/render_blender_comparison.py):

  the same surfaces (Au, l_c = 2 um, sigma_s/lambda below at lambda = 0.55 um) and models, in the
  same layout (rows: models, columns: roughness); the same sun (irradiance 3, at the same angle to the
  camera); one exposure for every sphere (1 / the 99th percentile of the luminance, x/(1+x), sRGB;
  the Blender comparison reuses the POV-Ray one when it is on hand); and one difference metric,
  |L - L_mbk| / L_mbk per pixel (luminance), median and 90th percentile where mbk is above 1% of
  its peak.
"""
import json
import os

import numpy as np

ROWS = (("mbk", "MBK (eq. 11, K)"), ("bk", "BK original (eq. 26)"), ("bk-modified", "BK modified (eq. 28)"),
        ("microfacet", "microfacet, mapped (eqs 20/25)"))
MODELS = [model for model, _ in ROWS]
LAMBDA_UM = 0.55
SIGMA_OVER_LAMBDA = (0.002, 0.01, 0.05, 0.15, 0.5)
SIGMA_OVER_LAMBDA_SMALL = (0.002, 0.05, 0.5)
MATERIAL, LC_UM = "Au", 2.0
# The sun: Blender world (z up, camera on -y) and the same direction in POV-Ray's (y up, camera on -z).
SUN_IRRADIANCE = 3.0
BLENDER_SUN_DIRECTION = (0.45, -1.0, 0.55)
POVRAY_SUN_DIRECTION = (0.45, 0.55, -1.0)
EXPOSURE_PERCENTILE = 99.0
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def columns(small):
    return SIGMA_OVER_LAMBDA_SMALL if small else SIGMA_OVER_LAMBDA


def exposure_of(image):
    """One exposure for a whole comparison: the 99th percentile of the luminance maps to 1/2."""
    y = image[..., :3] @ LUMINANCE
    return 1.0 / np.percentile(y[y > 0], EXPOSURE_PERCENTILE)


def shared_exposure(out_dir):
    """The POV-Ray comparison's exposure (povray_comparison.json beside it), or None."""
    path = os.path.join(out_dir, "povray_comparison.json")
    if not os.path.isfile(path):
        return None
    with open(path, encoding="utf-8") as f:
        return json.load(f).get("exposure")


def srgb(x):
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def label_axes(axes, sigma_over_lambda):
    for c, ratio in enumerate(sigma_over_lambda):
        axes[0][c].set_title(f"sigma_s/lambda = {ratio:g}\n(sigma_s = {ratio * LAMBDA_UM:.4g} um)", fontsize=9)
    for r, (_, name) in enumerate(ROWS):
        axes[r][0].set_ylabel(name, fontsize=9)
    for a in np.ravel(axes):
        a.set_xticks([])
        a.set_yticks([])


def comparison_figure(grid, sigma_over_lambda, exposure, title, path):
    """grid[model row][roughness column]: RGB radiance; one exposure, x/(1+x), sRGB."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(ROWS), len(sigma_over_lambda),
                             figsize=(2.2 * len(sigma_over_lambda) + 1.2, 2.2 * len(ROWS) + 0.8), squeeze=False)
    for r in range(len(ROWS)):
        for c in range(len(sigma_over_lambda)):
            x = np.clip(grid[r][c][..., :3], 0.0, None) * exposure
            axes[r][c].imshow(srgb(x / (1.0 + x)))
    label_axes(axes, sigma_over_lambda)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def difference_figure(grid, sigma_over_lambda, mask, title, path):
    """|L - L_mbk| / L_mbk per pixel (luminance; mbk floored at 1e-3 of its peak) inside `mask`;
    returns per cell the median and 90th percentile where mbk is above 1% of its peak."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm
    fig, axes = plt.subplots(len(ROWS), len(sigma_over_lambda),
                             figsize=(2.2 * len(sigma_over_lambda) + 2.0, 2.2 * len(ROWS) + 0.8), squeeze=False)
    norm = LogNorm(vmin=1e-3, vmax=10.0)
    cells, shown = [], None
    for r, (model, _) in enumerate(ROWS):
        for c in range(len(sigma_over_lambda)):
            ref = grid[0][c][..., :3] @ LUMINANCE
            cur = grid[r][c][..., :3] @ LUMINANCE
            rel = np.abs(cur - ref) / np.maximum(ref, 1e-3 * ref[mask].max())
            rel = np.where(mask, np.maximum(rel, 1e-4), np.nan)
            shown = axes[r][c].imshow(rel, norm=norm, cmap="magma")
            above = mask & (ref > 1e-2 * ref[mask].max())
            median, p90 = float(np.median(rel[above])), float(np.percentile(rel[above], 90))
            if r > 0:
                axes[r][c].text(0.03, 0.03, f"median {median:.2f}", transform=axes[r][c].transAxes, color="w", fontsize=7)
            cells.append({"model": model, "sigma_over_lambda": sigma_over_lambda[c], "median_relative": median,
                          "p90_relative": p90})
    label_axes(axes, sigma_over_lambda)
    fig.colorbar(shown, ax=axes, fraction=0.03, label="|L - L_mbk| / L_mbk  (luminance)")
    fig.suptitle(title, fontsize=9)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return cells
