"""The generated OSL shader (`brdf export blender --mode osl`), checked without OSL.

Debian's Blender has no OSL and Debian has no oslc, so the shader is compiled as C++: its text is
included, unchanged but for the shader's parameter list (turned into a C++ signature: outputs by
reference, defaults dropped), after osl_shim.h, which maps OSL's types and builtins to C++ and
texture() onto the atlas EXR the exporter wrote (read here with OpenImageIO, OSL's t from the top).
The compiled shader then runs at random geometries and must agree with
  - `brdf eval` (Radiance / (cos theta_i E C) within 2.5% where above 1% of the maximum;
    R_spec within 0.5%),
  - the add-on's node graph for the same atlas (graph_interpreter.py), to 1e-4 relative: the two
    lookups are independent code for one layout,
  - its own closures: BSDF = Radiance * emission() + SpecularWeight * reflection(N).
Usage: test_osl_shader.py [C++ compiler]   (env BRDF_EXE, LIBBRDF_ROOT)
"""

import os
import re
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
from test_nodegraph import random_geometries  # noqa: E402

BRDF = os.environ.get("BRDF_EXE", "brdf")
CXX = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("CXX", "c++")


def split_top_level(text):
    parts, depth, current = [], 0, ""
    for ch in text:
        depth += ch == "("
        depth -= ch == ")"
        if ch == "," and depth == 0:
            parts.append(current)
            current = ""
        else:
            current += ch
    return parts + [current]


def shader_as_cpp(source):
    """The OSL source with its `shader NAME(params)` header turned into a C++ function header."""
    match = re.search(r"^shader\s+(\w+)\s*\((.*?)\)\s*\{", source, re.S | re.M)
    if not match:
        raise SystemExit("no shader declaration in the generated OSL")
    params, names = [], []
    for raw in split_top_level(match.group(2)):
        declaration = raw.split("=")[0].split()
        is_output = declaration[0] == "output"
        if is_output:
            declaration = declaration[1:]
        name = declaration[-1]
        type_ = "Closure" if declaration[:-1] == ["closure", "color"] else " ".join(declaration[:-1])
        params.append(f"{type_}{'&' if is_output else ''} {name}")
        names.append(name)
    header = f"void shader_entry({', '.join(params)}) {{"
    return source[:match.start()] + header + source[match.end():], names, match.group(2)


HARNESS = r"""
#include "osl_shim.h"
#include <OpenImageIO/imageio.h>
#include <iostream>
namespace osl {
#include "shader_body.inc"
}
int main(int argc, char** argv) {
  auto in = OIIO::ImageInput::open(argv[1]);
  if (!in) { std::cerr << "cannot open atlas\n"; return 2; }
  const OIIO::ImageSpec& spec = in->spec();
  osl::atlas.path = argv[1];
  osl::atlas.width = spec.width;
  osl::atlas.height = spec.height;
  osl::atlas.rgb.resize(std::size_t(spec.width) * spec.height * 3);
  if (!in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, osl::atlas.rgb.data())) return 2;
  float n[3], l[3], v[3], e, c[3];
  while (std::cin >> n[0] >> n[1] >> n[2] >> l[0] >> l[1] >> l[2] >> v[0] >> v[1] >> v[2] >> e >> c[0] >> c[1] >> c[2]) {
    osl::N = osl::Triple(n[0], n[1], n[2]);
    osl::I = -osl::Triple(v[0], v[1], v[2]);
    osl::Closure bsdf;
    osl::color radiance, specular;
    osl::shader_entry(argv[1], osl::Triple(l[0], l[1], l[2]), e, osl::Triple(c[0], c[1], c[2]), bsdf, radiance, specular);
    std::printf("%.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", radiance.x, radiance.y, radiance.z,
                specular.x, specular.y, specular.z, bsdf.emission.x, bsdf.emission.y, bsdf.emission.z,
                bsdf.reflection.x, bsdf.reflection.y, bsdf.reflection.z);
  }
  return osl::texture_calls > 0 ? 0 : 4;
}
"""


def main():
    rng = np.random.default_rng(29100)
    with tempfile.TemporaryDirectory() as tmp:
        request = core.MaterialRequest(model="bk-modified", material="Cu", sigma_s=0.08, lc=1.5, mode="OSL",
                                       resolution=(128, 64, 48), name="Cu osl").validated()
        path = core.run_export(BRDF, request, tmp)
        description = core.load_description(path)
        osl_path = core.sibling(path, description["osl"]["file"])
        atlas_path = core.sibling(path, description["lut"]["file"])
        with open(osl_path, encoding="utf-8") as f:
            source = f.read()
        cpp, names, params = shader_as_cpp(source)
        check(names == ["Atlas", "LightDirection", "SunStrength", "SunColor", "BSDF", "Radiance", "SpecularWeight"],
              f"shader parameters {names}")
        default_atlas = re.search(r'string Atlas = "([^"]*)"', params).group(1)
        check(default_atlas == os.path.abspath(atlas_path), "Atlas default is the exported EXR's absolute path")
        check(f"shader {description['osl']['shader']}(" in source, "shader name as in the description")

        with open(os.path.join(tmp, "shader_body.inc"), "w", encoding="utf-8") as f:
            f.write(cpp)
        with open(os.path.join(tmp, "harness.cpp"), "w", encoding="utf-8") as f:
            f.write(HARNESS)
        exe = os.path.join(tmp, "osl_harness")
        compile_cmd = [CXX, "-std=c++17", "-O1", "-I", HERE, "-I", tmp, os.path.join(tmp, "harness.cpp"),
                       "-o", exe, "-lOpenImageIO", "-lOpenImageIO_Util"]
        built = subprocess.run(compile_cmd, capture_output=True, text=True)
        check(built.returncode == 0, "generated OSL compiles as C++ with the shim" +
              ("" if built.returncode == 0 else ":\n" + built.stderr[-3000:]))
        if built.returncode != 0:
            checks.finish()

        count = 3000
        n, light, view, angles = random_geometries(rng, count, 70.0)
        strength, colour = 1.7, (0.9, 0.6, 0.3)
        lines = "\n".join(" ".join(f"{x:.9g}" for x in (*n[i], *light[i], *view[i], strength, *colour))
                          for i in range(count))
        ran = subprocess.run([exe, atlas_path], input=lines, capture_output=True, text=True)
        check(ran.returncode == 0, f"OSL harness ran ({ran.stderr.strip()})")
        out = np.loadtxt(ran.stdout.splitlines(), ndmin=2)
        check(out.shape == (count, 12) and bool(np.all(np.isfinite(out))), f"{out.shape[0]} finite results")
        radiance, specular, emission, reflection = out[:, 0:3], out[:, 3:6], out[:, 6:9], out[:, 9:12]
        check(np.array_equal(emission, radiance) and np.array_equal(reflection, specular),
              "BSDF = Radiance * emission() + SpecularWeight * reflection(N)")

        _, model, channels = render_check.description_surface(path)
        cos_i = np.cos(np.radians(angles[0]))
        for rgb in range(3):
            expected = render_check.brdf_eval(BRDF, model, channels[rgb], angles)
            got = radiance[:, rgb] / (cos_i * strength * colour[rgb])
            above = expected > 0.01 * expected.max()
            rel = np.abs(got - expected)[above] / expected[above]
            check(rel.max() <= 0.025, f"channel {rgb}: OSL vs brdf eval ({model}), {above.sum()} points, max rel "
                                      f"{rel.max():.4f} <= 0.025 (median {np.median(rel):.5f})")
            spec = render_check.brdf_eval(BRDF, "r-spec", channels[rgb], (angles[1], angles[1], np.full(count, 180.0)))
            srel = np.abs(specular[:, rgb] - spec) / np.maximum(spec, 1e-12)
            check(srel.max() <= 5e-3, f"channel {rgb}: OSL SpecularWeight vs r-spec, max rel {srel.max():.2e}")

        # The node group the add-on builds for the same atlas.
        graph = nodegraph.lut_graph(description, atlas_path)
        images = {"atlas": graph_interpreter.load_image(atlas_path)}
        nodes_out = graph_interpreter.evaluate(graph, n, view, {"Light Direction": light, "Sun Strength": strength,
                                                                "Sun Color": np.array(colour + (1.0,))}, images)
        scale = np.maximum(np.abs(nodes_out["Radiance"]), 1e-3 * np.abs(nodes_out["Radiance"]).max())
        diff = np.abs(nodes_out["Radiance"] - radiance) / scale
        check(diff.max() <= 1e-4, f"OSL and node graph agree: max relative difference {diff.max():.1e} <= 1e-4")
        sdiff = np.abs(nodes_out["Specular Weight"] - specular) / np.maximum(specular, 1e-6)
        check(sdiff.max() <= 1e-4, f"OSL and node graph R_spec agree: {sdiff.max():.1e} <= 1e-4")
    checks.finish("OSL shader checks passed")


if __name__ == "__main__":
    main()
