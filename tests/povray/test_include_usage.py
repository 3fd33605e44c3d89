#!/usr/bin/python3
"""The usage comment of every include `brdf export povray` writes, rendered VERBATIM (issue 34).

For seeded random surfaces (model, material or n + i k, sigma_s, l_c) and random light and view
directions (the angle between them 10..110 deg; any view, vertical ones too): the include's
"Usage" lines are copied into a .pov file as they stand (the comment marker taken off, nothing
else changed), once as written (NAME_Exact) and once with the sphere line replaced by the lines
the comment says replace it (a sun + NAME_Fit). POV-Ray 3.7 renders each (+FE +UA -D, no
antialiasing). Expected per pixel: the unit sphere's normal at the pixel centre, from the camera
the comment itself declares (orthographic, location 100*View_Direction, look_at 0, right
2.4 x W/H, up 2.4 y: POV-Ray's look_at gives right = sky x direction, up = direction x right),
and L = f_r cos(theta_i) E with f_r from `brdf eval` (E = NAME_Irradiance = 1).
Asserted per render (pixels with the mask eroded by 2, all channels above 1e-3 of the maximum, >= 50 of them):
the object is lit (>= 95% of the pixels expected lit render > 0), mean rendered / mean expected
in [0.8, 1.25] and the median per-pixel relative error <= 2% (NAME_Exact) / 25% (NAME_Fit); no
NaN/Inf. Control: the same check on the camera of the old comment (location -100*View_Direction)
must FAIL for every render (it sees the back of the sphere: a rim for NAME_Exact, black for
NAME_Fit), so the check can tell the two apart.
Environment (set by ctest): BRDF_EXE, LIBBRDF_ROOT, LIBBRDF_BUILD.
"""
import os
import random
import sys
from pathlib import Path

import numpy as np

ROOT = Path(os.environ["LIBBRDF_ROOT"])
BRDF = os.environ["BRDF_EXE"]
OUT = Path(os.environ.get("LIBBRDF_BUILD", "/tmp")) / "povray_test" / "include_usage"
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "tests"))
import checks  # noqa: E402
import povray_common as pc  # noqa: E402
from checks import check  # noqa: E402

WAVELENGTHS = [0.65, 0.55, 0.45]  # export povray's default R, G, B
SIZE = 128  # pixels, square
HALF_WIDTH = 1.2  # the comment's "right 2.4*x*image_width/image_height up 2.4*y"
CASES = 6
SEED = 34
LIMITS = {"Exact": dict(median=0.02, ratio=(0.8, 1.25)), "Fit": dict(median=0.25, ratio=(0.8, 1.25))}


def random_direction(rng):
    while True:
        v = np.array([rng.gauss(0, 1) for _ in range(3)])
        if np.linalg.norm(v) > 1e-3:
            return v / np.linalg.norm(v)


def random_case(rng, index):
    view = random_direction(rng)
    if index == 0:
        view = np.array([0.0, 1.0, 0.0])  # straight down from above: the comment's camera needs another sky
    while True:  # the sun 10..110 deg from the camera, so that a good part of the visible half is lit
        light = random_direction(rng)
        if 10.0 <= np.degrees(np.arccos(np.clip(light @ view, -1, 1))) <= 110.0:
            break
    model = rng.choice(["mbk", "bk-modified", "microfacet"])
    surface = rng.choice([dict(material=rng.choice(["Au", "Al", "Ag", "Cu"])),
                          dict(n=round(rng.uniform(1.3, 2.5), 3), k=round(rng.uniform(0.0, 4.0), 3))])
    params = dict(surface, sigma_s=round(10 ** rng.uniform(np.log10(0.03), np.log10(0.4)), 4),
                  lc=round(rng.uniform(1.0, 4.0), 3))
    return dict(name=f"case{index}_{model}", model=model, params=params, light=light, view=view)


def usage_scenes(include_text):
    """The two scenes the include's usage comment spells out: {"Exact": text, "Fit": text}.
    Code lines are the comment's "//   " lines, taken verbatim; the "// Or, ... replace the sphere
    line by:" paragraph's lines replace the line that starts "sphere {"."""
    lines = include_text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("// Usage"))
    exact, fit_lines = [], []
    target = exact
    for line in lines[start + 1:]:
        if line == "//":
            break
        if line.startswith("//   "):
            target.append(line[len("//   "):])
        elif line.startswith("// Or,") and "replace the sphere line by" in line:
            target = fit_lines
        else:
            raise AssertionError(f"unexpected line in the usage comment: {line!r}")
    spheres = [i for i, line in enumerate(exact) if line.startswith("sphere {")]
    check(len(spheres) == 1 and fit_lines, f"usage comment has one sphere line and a Fit alternative: {exact} {fit_lines}")
    fit = exact[:spheres[0]] + fit_lines + exact[spheres[0] + 1:]
    return {"Exact": "\n".join(exact) + "\n", "Fit": "\n".join(fit) + "\n"}


def sphere_normals(view, sky):
    """Per pixel (centres, row 0 at the top) the unit sphere's world normal seen by the comment's
    orthographic camera, or NaN off the sphere."""
    direction = -pc.unit(view)
    right = np.cross(sky, direction)
    right /= np.linalg.norm(right)
    up = np.cross(direction, right)
    j, i = np.mgrid[0:SIZE, 0:SIZE]
    a = ((i + 0.5) / SIZE - 0.5) * 2 * HALF_WIDTH
    b = (0.5 - (j + 0.5) / SIZE) * 2 * HALF_WIDTH
    depth = np.sqrt(np.clip(1.0 - a * a - b * b, 0.0, None))
    normals = a[..., None] * right + b[..., None] * up - depth[..., None] * direction
    normals[a * a + b * b >= 1.0] = np.nan
    return normals


def lit_check(image, expected_image, mask):
    """(ok, description): is the render the lit object brdf eval predicts?"""
    expected, rendered = expected_image[mask], image[mask][:, :3]
    selected = expected.min(axis=1) > 1e-3 * expected.max()
    if selected.sum() < 50:
        return False, f"only {selected.sum()} pixels expected lit"
    lit_fraction = float(np.mean(rendered[selected].max(axis=1) > 0))
    ratio = float(rendered[selected].mean() / expected[selected].mean())
    median = float(np.median(np.abs(rendered[selected] - expected[selected]) / expected[selected]))
    return (lit_fraction, ratio, median), (f"{selected.sum()} pixels: {lit_fraction:.0%} lit, mean rendered/expected "
                                           f"{ratio:.3f}, median relative error {median:.2%}")


def main():
    rng = random.Random(SEED)
    table = []
    for index in range(CASES):
        case = random_case(rng, index)
        directory = OUT / case["name"]
        directory.mkdir(parents=True, exist_ok=True)
        pc.export_include(BRDF, case["model"], case["params"], case["light"], case["view"], "Material", directory)
        scenes = usage_scenes((directory / "Material.inc").read_text())
        sky = np.array([0.0, 0.0, 1.0]) if abs(case["view"][1]) > 0.999 else np.array([0.0, 1.0, 0.0])
        normals = sphere_normals(case["view"], sky)
        on_sphere = ~np.isnan(normals[..., 0])
        expected = np.zeros((SIZE, SIZE, 3))
        expected[on_sphere], _ = pc.predicted_radiance(BRDF, case["model"], case["params"], WAVELENGTHS,
                                                       normals[on_sphere], case["light"], case["view"], 1.0)
        label = f"{case['name']} {case['params']} L={np.round(case['light'], 3)} V={np.round(case['view'], 3)}"
        for texture, scene in scenes.items():
            old_camera = scene.replace("location 100*Material_View_Direction", "location -100*Material_View_Direction")
            check(old_camera != scene, f"{label}: the usage camera is at location 100*Material_View_Direction")
            results = {}
            for variant, text in [("usage", scene), ("old", old_camera)]:
                path = directory / f"{texture}_{variant}.pov"
                path.write_text(text)
                image = pc.run_povray(path, directory / f"{texture}_{variant}.exr", SIZE, SIZE, [directory])
                check(np.all(np.isfinite(image)), f"{label} {texture} {variant}: render finite")
                mask = pc.erode(image[..., 3] > 0.999, 2) & on_sphere
                check(mask.sum() > 0.5 * on_sphere.sum(), f"{label} {texture} {variant}: the sphere fills the frame "
                      f"as the comment's camera says ({mask.sum()} of {on_sphere.sum()} pixels)")
                results[variant] = lit_check(image, expected, mask)
            limit = LIMITS[texture]
            (measured, text), (old_measured, old_text) = results["usage"], results["old"]

            def passes(m):
                return bool(m) and m[0] >= 0.95 and limit["ratio"][0] <= m[1] <= limit["ratio"][1] and m[2] <= limit["median"]
            check(passes(measured), f"{label} Material_{texture}, usage comment verbatim: {text} (want >= 95% lit, ratio in "
                  f"{limit['ratio']}, median <= {limit['median']:.0%})")
            check(not passes(old_measured), f"{label} Material_{texture}: the check rejects the old camera "
                  f"(-100*View_Direction): {old_text}")
            table.append((case["name"], texture, text, old_text))
    for name, texture, text, old_text in table:
        print(f"  {name} {texture:5s} usage: {text}\n  {'':{len(name)}} {'':5s} old:   {old_text}")
    checks.finish("ok: every include's usage comment renders the lit object brdf eval predicts", context=f" in {OUT}")


if __name__ == "__main__":
    main()
