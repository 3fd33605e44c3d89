"""The generated OSL shaders (`brdf export blender --mode osl`) compiled and run by real OSL.

Debian has neither oslc nor testshade; `tools/osl/build_osl.sh SNAPSHOT_GIT_DIR [PREFIX]` builds
both (OSL 1.13.9) from a snapshot of github:AcademySoftwareFoundation/OpenShadingLanguage. This test
finds them through OSL_PREFIX (default: that script's prefix, ~/.cache/libbrdf-osl) and exits 77
(ctest: skipped), saying so, where they are absent, as on CI; test_osl_shader.py checks the same
shaders everywhere through its C++ shim.

Per material (the kernel form at n = 1.5 + 1i polished, intermediate, rough; Cu with bk-modified;
the rusinkiewicz atlas of the microfacet model):
  - oslc compiles the exported .osl file unchanged;
  - a wrapper shader made of the file's own functions and macros (everything before its `shader`
    declaration, unchanged) evaluates LIBBRDF_BRDF and LIBBRDF_SPECULAR on testshade's grid:
    theta_i = 80 deg u, theta_s = 80 deg v at three azimuths (N = z, L in the x-z plane), written
    with the angles it used as float OpenEXR images;
  - each value against `brdf eval` at those angles, per channel where above 1% of the maximum:
    median <= 0.3%, p95 <= 1.5% (issue 10), max as test_osl_shader.py (1% kernel, 2.5% atlas);
    SpecularWeight against `brdf eval --model r-spec` within 0.5%.
Usage: test_osl_real.py   (env BRDF_EXE, LIBBRDF_ROOT, OSL_PREFIX)
"""

import os
import re
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

from blender_test_env import BRDF, HERE, ROOT  # noqa: F401 (sys.path first)

import checks  # noqa: E402
import render_check  # noqa: E402
from checks import check  # noqa: E402
from libbrdf_materials import core  # noqa: E402
from test_osl_shader import osl_requests  # noqa: E402

PREFIX = os.environ.get("OSL_PREFIX") or os.path.join(os.path.expanduser("~"), ".cache", "libbrdf-osl")
GRID = 40                   # testshade's grid: GRID x GRID shading points per azimuth
AZIMUTHS = (180.0, 135.0, 60.0)  # deg: forward in-plane, oblique, towards back-scatter
THETA_MAX = 80.0


def tool(name):
    return os.path.join(PREFIX, "bin", name)


def run(argv, cwd):
    env = dict(os.environ, LD_LIBRARY_PATH=os.path.join(PREFIX, "lib") + os.pathsep + os.environ.get("LD_LIBRARY_PATH", ""))
    return subprocess.run(argv, cwd=cwd, env=env, capture_output=True, text=True, timeout=300)


def wrapper_source(source):
    """The exported file's functions and macros, unchanged, then a shader that evaluates them on
    testshade's (u, v) grid; its string parameters are the exported shader's own (the images)."""
    head, _, tail = source.partition("\nshader ")
    check(tail != "", "the exported file declares its shader after its functions")
    images = re.findall(r"^\s*string (\w+) = (\"[^\"]*\"),$", tail, re.M)
    check(len(images) >= 1, f"the exported shader's image parameters: {[name for name, _ in images]}")
    parameters = "".join(f"    string {name} = {path},\n" for name, path in images)
    return head + f"""
shader libbrdf_real_check(
    float PhiDeg = 180.0,
{parameters}    output color Value = 0,
    output color Spec = 0,
    output float ThetaI = 0,
    output float ThetaS = 0)
{{
    float ti = radians({THETA_MAX}) * u;
    float ts = radians({THETA_MAX}) * v;
    float phi = radians(PhiDeg);
    vector Nn = vector(0.0, 0.0, 1.0);
    vector Ln = vector(sin(ti), 0.0, cos(ti));
    vector Vn = vector(sin(ts) * cos(phi), sin(ts) * sin(phi), cos(ts));
    Value = LIBBRDF_BRDF(Nn, Ln, Vn);
    Spec = LIBBRDF_SPECULAR(ts);
    ThetaI = ti;
    ThetaS = ts;
}}
"""


def read_exr(path):
    image = oiio.ImageBuf(path)
    check(not image.has_error, f"testshade wrote {os.path.basename(path)} ({image.geterror()})")
    pixels = image.get_pixels(oiio.FLOAT)
    return pixels.reshape(-1, pixels.shape[-1])


def check_material(request, max_error, tmp):
    path = core.run_export(BRDF, request, tmp)
    description = core.load_description(path)
    osl_path = core.sibling(path, description["osl"]["file"])
    with open(osl_path, encoding="utf-8") as f:
        source = f.read()
    work = os.path.join(tmp, re.sub(r"\W", "_", request.name))
    os.makedirs(work)
    compiled = run([tool("oslc"), "-I" + os.path.join(PREFIX, "shaders"), "-o", os.path.join(work, "exported.oso"), osl_path], work)
    if not check(compiled.returncode == 0, f"{request.name}: oslc compiles the exported shader unchanged ({compiled.stderr.strip()[-300:]})"):
        return
    wrapper = wrapper_source(source)
    with open(os.path.join(work, "libbrdf_real_check.osl"), "w", encoding="utf-8") as f:
        f.write(wrapper)
    compiled = run([tool("oslc"), "-I" + os.path.join(PREFIX, "shaders"), "libbrdf_real_check.osl"], work)
    if not check(compiled.returncode == 0, f"{request.name}: oslc compiles the wrapper ({compiled.stderr.strip()[-300:]})"):
        return

    _, model, channels = render_check.description_surface(path)
    value, spec, ti, ts, phi = [], [], [], [], []
    for azimuth in AZIMUTHS:
        outputs = {name: os.path.join(work, f"{name}_{azimuth:g}.exr") for name in ("Value", "Spec", "ThetaI", "ThetaS")}
        argv = [tool("testshade"), "-g", str(GRID), str(GRID), "--param:type=float", "PhiDeg", f"{azimuth:.1f}", "-od", "float"]
        for name, out in outputs.items():
            argv += ["-o", name, out]
        shaded = run(argv + ["libbrdf_real_check"], work)
        if not check(shaded.returncode == 0, f"{request.name}: testshade ran at phi {azimuth:g} ({shaded.stderr.strip()[-300:]})"):
            return
        value.append(read_exr(outputs["Value"])[:, :3])
        spec.append(read_exr(outputs["Spec"])[:, :3])
        ti.append(np.degrees(read_exr(outputs["ThetaI"])[:, 0]))
        ts.append(np.degrees(read_exr(outputs["ThetaS"])[:, 0]))
        phi.append(np.full(GRID * GRID, azimuth))
    value, spec = np.concatenate(value), np.concatenate(spec)
    angles = (np.concatenate(ti), np.concatenate(ts), np.concatenate(phi))
    check(bool(np.all(np.isfinite(value))) and value.shape == (len(AZIMUTHS) * GRID * GRID, 3),
          f"{request.name}: {value.shape[0]} finite shader values")
    check(np.ptp(angles[0]) > 0.9 * THETA_MAX and np.ptp(angles[1]) > 0.9 * THETA_MAX,
          f"{request.name}: testshade's grid spans theta_i, theta_s up to {angles[0].max():.1f}, {angles[1].max():.1f} deg")
    errors = []
    for rgb in range(3):
        expected = render_check.brdf_eval(BRDF, model, channels[rgb], angles)
        above = expected > 0.01 * expected.max()
        errors.append(np.abs(value[above, rgb] - expected[above]) / expected[above])
        if description["fit"]["has_spike"]:
            r_spec = render_check.brdf_eval(BRDF, "r-spec", channels[rgb], (angles[1], angles[1], np.full(angles[1].size, 180.0)))
            srel = np.abs(spec[:, rgb] - r_spec) / np.maximum(r_spec, 1e-12)
            check(srel.max() <= 5e-3, f"{request.name} channel {rgb}: real OSL SpecularWeight vs r-spec, max rel {srel.max():.2e}")
    rel = np.concatenate(errors)
    median, p95, worst = np.median(rel), np.percentile(rel, 95), rel.max()
    check(rel.size >= 300 and median <= 0.003 and p95 <= 0.015 and worst <= max_error,
          f"{request.name}: real OSL (oslc + testshade) vs brdf eval ({model}), {rel.size} values, median {median:.2e}, "
          f"p95 {p95:.2e}, max {worst:.2e} <= (0.003, 0.015, {max_error})")


def main():
    missing = [name for name in ("oslc", "testshade") if not os.access(tool(name), os.X_OK)]
    if missing:
        print(f"SKIPPED: no {' or '.join(missing)} under OSL_PREFIX={PREFIX} (Debian has no OSL; build them with "
              "tools/osl/build_osl.sh SNAPSHOT_GIT_DIR PREFIX); test_osl_shader.py checks the shaders through its C++ shim")
        sys.exit(77)
    requests = osl_requests()
    with tempfile.TemporaryDirectory() as tmp:
        for request, max_error in requests:
            check_material(request.validated(), max_error, tmp)
    checks.finish("real OSL checks passed")


if __name__ == "__main__":
    main()
