"""The add-on's node graphs, run without Blender (graph_interpreter.py), against `brdf eval`.

LUT graph: at random geometries in random world frames (theta_i, theta_s <= 70 deg, any azimuth),
the group's Radiance output / (cos theta_i E C) must match the library's BRDF within 2.5% where
the BRDF is above 1% of its maximum (table interpolation error; a wrong phi_d convention, atlas
packing or texel convention gives tens of percent), and Specular Weight must match R_spec within
0.5%. FIT graph: its Beckmann roughness, colour and spike weight must follow the description.
"""

import math
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.environ.get("LIBBRDF_ROOT", os.path.normpath(os.path.join(HERE, "..", "..")))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "blender_addon"))
sys.path.insert(0, os.path.dirname(HERE))

import checks  # noqa: E402
import graph_interpreter  # noqa: E402
import render_check  # noqa: E402
from checks import check  # noqa: E402
from libbrdf_materials import core, nodegraph  # noqa: E402

BRDF = os.environ.get("BRDF_EXE", "brdf")


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


def lut_case(directory, request, rng):
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
    worst = 0.0
    for rgb in range(3):
        expected = render_check.brdf_eval(BRDF, model, channels[rgb], angles)
        got = out["Radiance"][:, rgb] / (cos_i * strength * colour[rgb])
        above = expected > 0.01 * expected.max()
        rel = np.abs(got - expected)[above] / expected[above]
        worst = max(worst, rel.max())
        check(bool(np.all(np.isfinite(out["Radiance"][:, rgb]))), f"{request.name} channel {rgb}: finite")
        spec = render_check.brdf_eval(BRDF, "r-spec", channels[rgb], (angles[1], angles[1], np.full(count, 180.0)))
        spec_rel = np.abs(out["Specular Weight"][:, rgb] - spec) / np.maximum(spec, 1e-12)
        check(spec_rel.max() <= 5e-3, f"{request.name} channel {rgb}: Specular Weight vs r-spec, max rel "
                                       f"{spec_rel.max():.2e} <= 5e-3")
        print(f"     channel {rgb}: {above.sum()} points above 1% of max, max rel {rel.max():.4f}, "
              f"median {np.median(rel):.5f}")
    check(worst <= 0.025, f"{request.name}: LUT graph vs brdf eval max relative error {worst:.4f} <= 0.025")

    # Sun below the horizon or camera behind the surface: no radiance.
    flipped = graph_interpreter.evaluate(graph, n, view, {"Light Direction": -light, "Sun Strength": strength,
                                                          "Sun Color": np.array(colour + (1.0,))}, images)
    check(float(np.abs(flipped["Radiance"]).max()) == 0.0, f"{request.name}: zero radiance with the sun behind")
    return description


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
    for node, lobe in zip(glossy, fit["lobes"]):
        check(abs(node.inputs["Roughness"] ** 2 - lobe["alpha"]) < 1e-12,
              f"FIT lobe roughness^2 {node.inputs['Roughness'] ** 2:.6f} = fitted alpha {lobe['alpha']:.6f}")
    error = fit["error"]
    check(0 <= error["median"] <= error["p95"] <= error["max"] and error["values"] > 100,
          f"FIT stores its measured error (median {error['median']:.2%}, p95 {error['p95']:.2%})")
    check(core.fit_error_text(description).startswith(f"{len(fit['lobes'])} lobe"),
          f"panel text: {core.fit_error_text(description)}")
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
    with tempfile.TemporaryDirectory() as directory:
        lut_case(directory, core.MaterialRequest(model="mbk", material="Au", sigma_s=0.1, lc=2.0, mode="LUT",
                                                 resolution=(128, 64, 48), name="Au rough"), rng)
        lut_case(directory, core.MaterialRequest(model="bk", material="BK7", sigma_s=0.15, lc=1.5, mode="LUT",
                                                 resolution=(128, 64, 48), name="BK7 bk"), rng)
        fit_case(directory, core.MaterialRequest(model="mbk", material="Al", sigma_s=0.2, lc=2.0, mode="FIT"))
    checks.finish("all node-graph checks passed")


if __name__ == "__main__":
    main()
