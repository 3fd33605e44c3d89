"""The add-on's node graphs, run without Blender (graph_interpreter.py), against `brdf eval`.

LUT graph, factored form (MBK, BK: exporters/include/exporters/blender.h, kernel): at random
geometries in random world frames (theta_i, theta_s <= 70 deg, any azimuth), the group's Radiance
output / (cos theta_i E C) must match the library's BRDF where the BRDF is above 1% of its maximum:
per point and channel median <= 0.3%, p95 <= 1.5% (issue 10) and max <= 1%, at n = 1.5 + 1i with
sigma_s = 0.02 / 0.2 / 1.0 um, l_c = 2 / 2 / 5 um (polished, intermediate, rough), Au, and BK7 with
the original BK model (closed-form F_bk^2); Specular Weight must match R_spec within 0.5%.
The Sigma image alone: its bilinear reconstruction (the graph's formula, in numpy) against an
independent log-space sum of the series (eq. 11), at random (g, c) where Sigma is within e^-10 of
Sigma(g, 0): max error of ln Sigma <= 5e-4.
LUT graph, rusinkiewicz atlas (microfacet): within 2.5% where above 1% of the maximum (table
interpolation error; a wrong phi_d convention, atlas packing or texel convention gives tens of
percent). FIT graph: its Beckmann roughness, colour and spike weight must follow the description.
"""

import dataclasses
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

from blender_test_env import BRDF, HERE, ROOT  # noqa: F401 (sys.path first)

import checks  # noqa: E402
import graph_interpreter  # noqa: E402
import render_check  # noqa: E402
from checks import check  # noqa: E402
from libbrdf_materials import core, nodegraph  # noqa: E402



def random_geometries(rng, count, max_theta_deg):
    """Unit N, L, V (count x 3 each) and their (theta_i, theta_s, phi_s) in degrees."""
    n = rng.normal(size=(count, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    helper = np.where(np.abs(n[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    t = np.cross(n, helper)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    b = np.cross(n, t)
    ti = np.radians(rng.uniform(0, max_theta_deg, count))
    ts = np.radians(rng.uniform(0, max_theta_deg, count))
    ps = np.radians(rng.uniform(0, 180, count))
    phi0 = rng.uniform(0, 2 * math.pi, count)  # incident azimuth in the frame: anything

    def direction(theta, phi):
        return (np.sin(theta)[:, None] * (np.cos(phi)[:, None] * t + np.sin(phi)[:, None] * b)
                + np.cos(theta)[:, None] * n)

    light = direction(ti, phi0)
    view = direction(ts, phi0 + ps)
    return n, light, view, (np.degrees(ti), np.degrees(ts), np.degrees(ps))


def lut_case(directory, request, rng, targets):
    """targets: (median, p95, max) relative error bounds of Radiance against brdf eval."""
    request = request.validated()
    path = core.run_export(BRDF, request, directory)
    description = core.load_description(path)
    graph = nodegraph.graph_for(description, path)
    images = {key: graph_interpreter.load_image(p) for key, p in graph.images.items()}
    _, model, channels = render_check.description_surface(path)

    count = 4000
    n, light, view, angles = random_geometries(rng, count, 70.0)
    strength, colour = 2.5, (1.0, 0.5, 0.25)
    # One sun for all points is not needed by the interpreter: the group input is per point here.
    out = graph_interpreter.evaluate(graph, n, view, {"Light Direction": light, "Sun Strength": strength,
                                                      "Sun Color": np.array(colour + (1.0,))}, images)
    cos_i = np.cos(np.radians(angles[0]))
    errors = []
    for rgb in range(3):
        expected = render_check.brdf_eval(BRDF, model, channels[rgb], angles)
        got = out["Radiance"][:, rgb] / (cos_i * strength * colour[rgb])
        above = expected > 0.01 * expected.max()
        errors.append(np.abs(got - expected)[above] / expected[above])
        check(bool(np.all(np.isfinite(out["Radiance"][:, rgb]))), f"{request.name} channel {rgb}: finite")
        spec = render_check.brdf_eval(BRDF, "r-spec", channels[rgb], (angles[1], angles[1], np.full(count, 180.0))) \
            if description["fit"]["has_spike"] else np.zeros(count)  # microfacet: no spike
        spec_rel = np.abs(out["Specular Weight"][:, rgb] - spec) / np.maximum(spec, 1e-12)
        check(spec_rel.max() <= 5e-3, f"{request.name} channel {rgb}: Specular Weight vs r-spec, max rel "
                                       f"{spec_rel.max():.2e} <= 5e-3")
    # The group's two evaluations of the same tables: Linear fetches (Cycles) and Closest fetches
    # interpolated in nodes (EEVEE) agree to float rounding.
    scale = np.maximum(np.abs(out["Radiance"]), 1e-3 * np.abs(out["Radiance"]).max())
    both = float((np.abs(out["EEVEE Radiance"] - out["Radiance"]) / scale).max())
    check(both <= 1e-4, f"{request.name}: Cycles (Linear fetches) and EEVEE (Closest) radiance agree, max rel {both:.1e}")
    rel = np.concatenate(errors)
    stats = (np.median(rel), np.percentile(rel, 95), rel.max())
    check(rel.size >= 300 and all(v <= t for v, t in zip(stats, targets)),
          f"{request.name} ({graph.notes['layout']}, {len(graph.nodes)} nodes): LUT graph vs brdf eval, {rel.size} values, "
          f"median {stats[0]:.2e}, p95 {stats[1]:.2e}, max {stats[2]:.2e} <= {targets}")

    # Sun below the horizon or camera behind the surface: no radiance.
    flipped = graph_interpreter.evaluate(graph, n, view, {"Light Direction": -light, "Sun Strength": strength,
                                                          "Sun Color": np.array(colour + (1.0,))}, images)
    check(float(np.abs(flipped["Radiance"]).max()) == 0.0, f"{request.name}: zero radiance with the sun behind")
    return description, path


def series_ln_sigma(g, c):
    """ln Sigma(g, c) of eq. 11 by an independent log-space sum over m (numpy; every term to
    g + 14 sqrt(g) + 80, far beyond where the Poisson weights leave double precision)."""
    top = int(g.max() + 14 * np.sqrt(g.max()) + 80)
    m = np.arange(1, top + 1, dtype=float)
    log_factorial = np.concatenate([[0.0], np.cumsum(np.log(m))])[1:]
    x = np.log(g)[:, None]
    terms = -g[:, None] + m * x - log_factorial - np.log(m) - c[:, None] / m
    peak = terms.max(axis=1, keepdims=True)
    return (peak + np.log(np.exp(terms - peak).sum(axis=1, keepdims=True)))[:, 0]


def sigma_image_case(description_path, rng):
    """The Sigma image through the graph's bilinear reconstruction against the series."""
    description = core.load_description(description_path)
    sigma = description["lut"]["sigma"]
    texels = graph_interpreter.load_image(core.sibling(description_path, sigma["file"]))[:, :, 0].astype(float)
    check(texels.shape == (sigma["height"], sigma["width"]) and bool(np.all(np.isfinite(texels))),
          f"Sigma image {sigma['width']}x{sigma['height']}, finite")
    count = 3000
    g = np.exp(rng.uniform(np.log(1e-5), np.log(1e3), count))
    # z^2 = c/(g+1) up to where Sigma falls to ~e^-10 of Sigma(g, 0) (beyond, no pixel is bright)
    z = rng.uniform(0.0, 3.2, count)
    c = (g + 1.0) * z * z
    x = np.log(g)
    ux = (np.clip(x, sigma["x_min"], sigma["x_min"] + (sigma["width"] - 1) * sigma["dx"]) - sigma["x_min"]) / sigma["dx"]
    uz = z / sigma["dz"]
    i = np.clip(np.floor(ux), 0, sigma["width"] - 2).astype(int)
    j = np.clip(np.floor(uz), 0, sigma["height"] - 2).astype(int)
    tx, tz = ux - i, uz - j
    s = ((1 - tz) * ((1 - tx) * texels[j, i] + tx * texels[j, i + 1]) + tz * ((1 - tx) * texels[j + 1, i] + tx * texels[j + 1, i + 1]))
    ln_sigma = s + x - np.log1p(g * g) - z * z
    reference = np.concatenate([series_ln_sigma(g[k:k + 200], c[k:k + 200]) for k in range(0, count, 200)])
    peak = np.concatenate([series_ln_sigma(g[k:k + 200], 0 * c[k:k + 200]) for k in range(0, count, 200)])
    inside = reference > peak - 10.0
    error = np.abs(ln_sigma - reference)[inside]
    check(inside.sum() > 1000 and error.max() <= 5e-4,
          f"Sigma image, bilinear, vs the series at {inside.sum()} random (g, c), 1e-5 <= g <= 1e3, within e^-10 of "
          f"Sigma(g, 0): max |error of ln Sigma| {error.max():.1e} <= 5e-4 (median {np.median(error):.1e})")


def fit_case(directory, request):
    request = request.validated()
    path = core.run_export(BRDF, request, directory)
    description = core.load_description(path)
    check("lut" not in description and not os.path.exists(path.replace(".json", ".exr")),
          "FIT export bakes no table")
    graph = nodegraph.graph_for(description, path)
    fit = description["fit"]
    glossy = [node for node in graph.nodes if node.type == "ShaderNodeBsdfGlossy"
              and node.props["distribution"] == "BECKMANN"]
    check(len(glossy) == len(fit["lobes"]) >= 1, f"FIT graph has one Beckmann Glossy per fitted lobe ({len(glossy)})")
    # Each lobe's roughness at N.V from 0.02 to 1: sqrt(alpha(N.V)) of the description (fit.h, lobe_alpha).
    mu = np.array([0.02, 0.1, 0.3, 0.5, 0.7, 0.9, 1.0])
    probe_normal = np.tile([[0.0, 0.0, 1.0]], (mu.size, 1))
    probe_view = np.stack([np.sqrt(1 - mu * mu), np.zeros(mu.size), mu], axis=1)
    links = {(to, sock): src for src, to, sock in graph.links}
    check(any(lobe["alpha_slope"] > 0 for lobe in fit["lobes"]), "some FIT lobe's alpha follows N.V (alpha_slope > 0)")
    for node, lobe in zip(glossy, fit["lobes"]):
        source = links.get((node.id, "Roughness"))
        if source is None:
            roughness = np.full(mu.size, node.inputs["Roughness"])
        else:
            probe = dataclasses.replace(graph, outputs=[("Roughness", "NodeSocketFloat")],
                                        links=graph.links + [(source, "GROUP_OUTPUT", "Roughness")])
            roughness = graph_interpreter.evaluate(probe, probe_normal, probe_view, {}, {})["Roughness"]
        expected = np.sqrt(np.minimum(lobe["alpha"] * np.maximum(mu, fit["min_view_cosine"]) ** -lobe["alpha_slope"], 1.0))
        error = float(np.max(np.abs(roughness / expected - 1)))
        check(error < 1e-5, f"FIT lobe roughness(N.V)^2 = alpha {lobe['alpha']:.4g} N.V^-{lobe['alpha_slope']:.3f} "
                            f"(at most 1) at N.V 0.02..1: max relative error {error:.1e}")
    error = fit["error"]
    check(0 <= error["median"] <= error["p95"] <= error["max"] and error["values"] > 100,
          f"FIT stores its measured error (median {error['median']:.2%}, p95 {error['p95']:.2%})")
    check(core.fit_error_text(description).startswith(f"{len(fit['lobes'])} lobe"),
          f"panel text: {core.fit_error_text(description)}")
    text = core.fit_error_text(description)
    for engine, stated in (("Cycles", fit["error"]), ("EEVEE", fit["eevee"]["error"])):
        bands = stated["by_sun_angle"]
        line = next((line for line in text.split("\n") if line.startswith(engine + " by light-camera angle")), "")
        check([(b["from_deg"], b["to_deg"]) for b in bands] == [(0, 30), (30, 60), (60, 90), (90, 120), (120, 140)]
              and all(f"{b['from_deg']:g}-{b['to_deg']:g} {b['median']:.1%}/{b['p95']:.0%}" in line for b in bands)
              and line.count("(!)") == sum(b["median"] > 0.05 or b["p95"] > 0.2 for b in bands),
              f"panel states {engine}'s error per band of light-camera angle, flagging the bands off target: {line}")
    low, high = fit["eevee"]["excluded_roughness"]
    check(0.3 < low < high < 0.95 and not any(low < lobe["roughness"] < high for lobe in fit["eevee"]["lobes"]),
          f"EEVEE's GGX lobes stay out of the roughness band ({low}, {high}) EEVEE does not render as GGX: "
          f"{[round(lobe['roughness'], 3) for lobe in fit['eevee']['lobes']]}")
    check(f"EEVEE median {fit['eevee']['error']['median']:.1%}" in core.fit_error_text(description),
          f"panel text states EEVEE's own fit error: {core.fit_error_text(description)}")
    eevee = [node for node in graph.nodes if node.type == "ShaderNodeShaderToRGB"]
    check(len(eevee) == len(fit["eevee"]["lobes"]) and fit["eevee"]["signed"],
          f"EEVEE output: one Shader to RGB per signed GGX lobe ({len(eevee)})")
    f0 = float(subprocess.run([BRDF, "eval", "--model", "fresnel", "--material", request.material, "--wavelength",
                               "0.55", "--at", "0,0,180"], capture_output=True, text=True,
                              check=True).stdout.splitlines()[1].split(",")[3])
    check(abs(fit["f0"][1] - f0) < 1e-9, f"FIT f0 {fit['f0'][1]:.6f} = brdf eval fresnel at normal incidence {f0:.6f}")
    m = 5
    n = np.tile([[0.0, 0.0, 1.0]], (m, 1))
    theta = np.radians(np.linspace(0, 80, m))
    view = np.stack([np.sin(theta), np.zeros(m), np.cos(theta)], axis=1)
    out = graph_interpreter.evaluate(graph, n, view, {"Light Direction": view, "Sun Strength": 1.0,
                                                      "Sun Color": np.ones(4)}, {})
    for rgb in range(3):
        f = fit["f0"][rgb] + (1 - fit["f0"][rgb]) * (1 - np.cos(theta)) ** 5
        expected = f * np.exp(-fit["g0"][rgb] * np.cos(theta) ** 2)
        rel = np.abs(out["Specular Weight"][:, rgb] - expected) / expected
        check(rel.max() < 1e-5, f"FIT spike weight channel {rgb} = Schlick F exp(-g0 cos^2), max rel {rel.max():.1e}")


def main():
    rng = np.random.default_rng(20151229)
    n15 = dict(model="mbk", n=1.5, k=1.0, mode="LUT")
    issue = (0.003, 0.015, 0.01)  # median, p95 (issue 10), max
    with tempfile.TemporaryDirectory() as directory:
        for name, surface in (("polished", dict(sigma_s=0.02, lc=2.0)), ("intermediate", dict(sigma_s=0.2, lc=2.0)),
                              ("rough", dict(sigma_s=1.0, lc=5.0))):
            _, path = lut_case(directory, core.MaterialRequest(**n15, **surface, name=f"n 1.5+1i {name}"), rng, issue)
        lut_case(directory, core.MaterialRequest(model="mbk", material="Au", sigma_s=0.1, lc=2.0, mode="LUT",
                                                 name="Au"), rng, issue)
        lut_case(directory, core.MaterialRequest(model="bk", material="BK7", sigma_s=0.15, lc=1.5, mode="LUT",
                                                 name="BK7 bk"), rng, issue)
        sigma_image_case(path, rng)
        lut_case(directory, core.MaterialRequest(model="microfacet", material="Au", sigma_s=0.1, lc=2.0, mode="LUT",
                                                 resolution=(128, 64, 48), name="Au microfacet"), rng, (1.0, 1.0, 0.025))
        fit_case(directory, core.MaterialRequest(model="mbk", material="Al", sigma_s=0.03, lc=2.0, mode="FIT"))
    checks.finish("all node-graph checks passed")


if __name__ == "__main__":
    main()
