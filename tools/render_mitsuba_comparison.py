"""Mitsuba 3 renders of the default materials with libbrdf.mitsuba (issue 36), checked per pixel.

    venv=$(scripts/python_env.sh mitsuba)
    PYTHONPATH=build/python $venv/bin/python tools/render_mitsuba_comparison.py --brdf build/cli/brdf \\
        --out DIR [--model mbk] [--exposure X] [--resolution 128] [--small]
        [--to-sun X Y Z] [--towards-camera X Y Z] [--half-width 1.05] [--no-cost]

One sphere per surface of tools/report/materials.json (in its order), lit by one sun of irradiance
1 from upper left in front (to the sun (-1, 1, 1.5) with the camera on +z: POV-Ray's comparison
scene, (-1, 1, -1.5) in its left-handed frame), orthographic camera, direct light, one sample per
pixel (llvm_ad_rgb; RGB = 0.65, 0.55, 0.45 um). --to-sun, --towards-camera and --half-width set
another scene in this frame (camera up +y; tools/render_summary.py uses them for the report's
first screen). Writes
  DIR/mitsuba_comparison.png   the spheres side by side: exposure x L, x/(1+x), sRGB
  DIR/mitsuba_difference.png   |L / L_brdf_eval - 1| per pixel, log colour scale 1e-8 (dark) .. 1e-2 (white),
                               grey where the value is below float32's range (< 1e-30) or unlit
  DIR/mitsuba/<surface>.exr    the linear radiance (1/sr per unit irradiance) and the hit positions
  DIR/mitsuba_comparison.json  exposure, scene, per surface the per-pixel relative difference to
                               `brdf eval` (median, 99th percentile, max) and the cost per sample
Cost per sample: a sun and a uniform grey sky (0.1), path tracing to depth 3, the plugin against
Mitsuba's own `roughconductor` (Beckmann, the plugin's proxy alpha, the material's index at
0.55 um) in the same variant and Dr.Jit mode, timed in one run after one warm-up each; the ratio
is against the same `roughconductor` in Dr.Jit's default symbolic mode as well.
"""
import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mitsuba_common as mc  # noqa: E402

TO_SUN = mc.unit([-1.0, 1.0, 1.5])
TOWARDS_CAMERA = (0.0, 0.0, 1.0)
FLOAT32_FLOOR = 1e-30
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def srgb(linear):
    linear = np.clip(linear, 0.0, 1.0)
    return np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * np.power(linear, 1 / 2.4) - 0.055)


def error_colour(relative):
    """log10 of a relative difference, 1e-8 .. 1e-2, on a dark-blue -> orange -> white ramp."""
    t = np.clip((np.log10(np.maximum(relative, 1e-12)) + 8.0) / 6.0, 0.0, 1.0)[..., None]
    anchors = np.array([[0.02, 0.02, 0.15], [0.1, 0.35, 0.7], [0.95, 0.55, 0.1], [1.0, 1.0, 1.0]])
    position = t * (len(anchors) - 1)
    k = np.minimum(position.astype(int), len(anchors) - 2)
    f = position - k
    return anchors[k[..., 0]] * (1 - f) + anchors[k[..., 0] + 1] * f


def write_png(mi, path, rgb):
    """rgb: display values in [0, 1], already sRGB-encoded. Written through a temporary + rename."""
    bitmap = mi.Bitmap(np.ascontiguousarray((np.clip(rgb, 0, 1) * 255 + 0.5).astype(np.uint8)))
    temporary = f"{path}.tmp{os.getpid()}.png"
    bitmap.write(temporary)
    os.replace(temporary, path)


def write_exr(mi, path, pixels):
    temporary = f"{path}.tmp{os.getpid()}.exr"
    mi.Bitmap(np.ascontiguousarray(pixels, np.float32), mi.Bitmap.PixelFormat.MultiChannel,
              channel_names=["R", "G", "B", "position.X", "position.Y", "position.Z"]).write(temporary)
    os.replace(temporary, path)


def sphere_and_error(mi, brdf, model, surface, resolution, to_sun=TO_SUN, towards_camera=TOWARDS_CAMERA, half_width=1.05):
    image = mc.render(mi, mc.sun_sphere_scene(mi, mc.plugin_dict(model, surface), to_sun, resolution, towards_camera,
                                              half_width), seed=1)
    radiance, positions, pixels = mc.sphere_pixels(image)
    predicted, asked = mc.predicted_sun_radiance(brdf, model, surface, positions, to_sun, towards_camera)
    representable = asked[:, None] & (predicted >= FLOAT32_FLOOR)
    relative = np.full(predicted.shape, np.nan)
    relative[representable] = np.abs(radiance[representable] / predicted[representable] - 1)
    error_image = np.full(image.shape[:2], np.nan)
    error_image[pixels[:, 0], pixels[:, 1]] = np.nanmax(np.where(representable, relative, -1.0), axis=1)
    error_image[error_image < 0] = np.nan
    values = relative[representable]
    stats = {"pixels_on_sphere": int(len(positions)), "channel_values_compared": int(representable.sum()),
             "channel_values_below_1e-30": int((asked[:, None] & (predicted > 0) & ~representable).sum()),
             "median": float(np.median(values)), "p99": float(np.percentile(values, 99)), "max": float(values.max())}
    return image, error_image, stats


def cost_scene(mi, bsdf, resolution, spp):
    return mi.load_dict({
        "type": "scene", "integrator": {"type": "path", "max_depth": 3},
        "sensor": mc.orthographic_sensor(mi, TOWARDS_CAMERA, 1.05, resolution, spp),
        "sun": {"type": "directional", "direction": (-TO_SUN).tolist(), "irradiance": {"type": "rgb", "value": 1.0}},
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": 0.1}},
        "sphere": {"type": "sphere", "bsdf": bsdf},
    })


def seconds_per_sample(mi, scene, samples):
    mc.render(mi, scene, seed=0)  # warm-up: kernels compiled, models built
    start = time.perf_counter()
    mc.render(mi, scene, seed=1)
    return (time.perf_counter() - start) / samples


def cost_per_sample(mi, plugin, model, surface, resolution, spp):
    import gc
    import drjit as dr
    import libbrdf
    index = libbrdf.Model("fresnel", wavelength=0.55, **{k: v for k, v in surface.items() if k in ("material", "n", "k")}).parameters
    alpha = plugin.proxy_alpha(model, surface, mc.RGB_WAVELENGTHS_UM[1])
    reference = {"type": "roughconductor", "distribution": "beckmann", "alpha": float(alpha),
                 "eta": {"type": "rgb", "value": float(index["n"])}, "k": {"type": "rgb", "value": float(index["k"])}}
    samples = resolution * resolution * spp
    ours = seconds_per_sample(mi, cost_scene(mi, mc.plugin_dict(model, surface), resolution, spp), samples)
    theirs = seconds_per_sample(mi, cost_scene(mi, reference, resolution, spp), samples)
    # A symbolic virtual call traces every live BSDF, the plugin's too (which needs values): none may be left.
    gc.collect()
    flags = {flag: dr.flag(flag) for flag in (dr.JitFlag.SymbolicLoops, dr.JitFlag.SymbolicCalls, dr.JitFlag.SymbolicConditionals)}
    for flag in flags:
        dr.set_flag(flag, True)
    symbolic = seconds_per_sample(mi, cost_scene(mi, reference, resolution, spp), samples)
    for flag, value in flags.items():
        dr.set_flag(flag, value)
    return {"samples": samples, "libbrdf_ns_per_sample": ours * 1e9, "roughconductor_ns_per_sample": theirs * 1e9,
            "roughconductor_symbolic_ns_per_sample": symbolic * 1e9, "ratio": ours / theirs, "ratio_to_symbolic": ours / symbolic,
            "roughconductor": {"alpha": reference["alpha"], "eta": reference["eta"]["value"], "k": reference["k"]["value"]}}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--brdf", required=True, help="the brdf program (per-pixel reference: brdf eval)")
    parser.add_argument("--out", required=True)
    parser.add_argument("--model", default="mbk")
    parser.add_argument("--exposure", type=float, help="radiance multiplier before x/(1+x); default 1 / the 99th percentile luminance")
    parser.add_argument("--resolution", type=int, default=128, help="pixels per sphere (square)")
    parser.add_argument("--cost-spp", type=int, default=16, help="samples per pixel of the cost renders (64 x 64 pixels)")
    parser.add_argument("--small", action="store_true", help="64 pixels per sphere, 4 samples per pixel for the cost")
    parser.add_argument("--to-sun", type=float, nargs=3, default=TO_SUN.tolist(), metavar=("X", "Y", "Z"),
                        help="direction to the sun (normalised; camera frame: +z towards the camera, +y up)")
    parser.add_argument("--towards-camera", type=float, nargs=3, default=list(TOWARDS_CAMERA), metavar=("X", "Y", "Z"))
    parser.add_argument("--half-width", type=float, default=1.05, help="half the orthographic view's width")
    parser.add_argument("--no-cost", action="store_true", help="skip the cost renders")
    args = parser.parse_args()
    if args.small:
        args.resolution, args.cost_spp = 64, 4
    for name in ("to_sun", "towards_camera"):
        if not (np.all(np.isfinite(getattr(args, name))) and np.linalg.norm(getattr(args, name)) > 0):
            sys.exit(f"--{name.replace('_', '-')}: must be a finite non-zero vector (got {getattr(args, name)})")
    if not (np.isfinite(args.half_width) and args.half_width > 0):
        sys.exit(f"--half-width: must be a positive number (got {args.half_width})")
    if args.resolution < 1:
        sys.exit(f"--resolution: must be at least 1 (got {args.resolution})")
    to_sun, towards_camera = mc.unit(args.to_sun), mc.unit(args.towards_camera)
    if args.exposure is not None and not (np.isfinite(args.exposure) and args.exposure > 0):
        sys.exit(f"--exposure: must be a positive number (got {args.exposure})")
    out = Path(args.out)
    (out / "mitsuba").mkdir(parents=True, exist_ok=True)

    mi, plugin = mc.load("llvm_ad_rgb")
    config = mc.brdfcli.load_materials()
    surfaces = []
    for s in config["surfaces"]:
        surface = {"material": s["material"], "sigma_s": s["sigma_s_um"], "lc": s["lc_um"]}
        started = time.time()
        image, error_image, stats = sphere_and_error(mi, args.brdf, args.model, surface, args.resolution, to_sun,
                                                     towards_camera, args.half_width)
        write_exr(mi, out / "mitsuba" / f"{s['name']}.exr", image)
        cost = None if args.no_cost else cost_per_sample(mi, plugin, args.model, surface, 64, args.cost_spp)
        mc.brdfcli.progress(f"mitsuba {s['name']}: median {stats['median']:.1e}"
                            + (f", cost x{cost['ratio']:.2f} roughconductor" if cost else "")
                            + f" ({time.time() - started:.1f} s)")
        surfaces.append({"name": s["name"], "surface": surface, "error": stats, "cost": cost,
                         "image": image, "error_image": error_image})

    radiance = np.concatenate([s["image"][..., :3] for s in surfaces], axis=1)
    luminance = radiance @ LUMINANCE
    exposure = args.exposure or float(1.0 / np.percentile(luminance[luminance > 0], 99.0))
    x = radiance * exposure
    write_png(mi, out / "mitsuba_comparison.png", srgb(x / (1.0 + x)))
    errors = np.concatenate([s["error_image"] for s in surfaces], axis=1)
    difference = np.where(np.isnan(errors)[..., None], 0.25, error_colour(np.nan_to_num(errors, nan=1.0)))
    write_png(mi, out / "mitsuba_difference.png", difference)

    summary = {
        "renderer": f"Mitsuba {mi.__version__} llvm_ad_rgb, libbrdf.mitsuba plugin '{args.model}'",
        "scene": {"to_sun": to_sun.tolist(), "towards_camera": towards_camera.tolist(), "sun_irradiance": 1.0,
                  "camera": f"orthographic, half width {args.half_width:g}", "spp": 1, "resolution": args.resolution,
                  "rgb_wavelengths_um": list(mc.RGB_WAVELENGTHS_UM)},
        "exposure": exposure, "tone": "exposure x L, x/(1+x), sRGB",
        "surfaces_left_to_right": [{k: s[k] for k in ("name", "surface", "error", "cost")} for s in surfaces],
        "cost_note": "ns per sample of a 64 x 64 path-traced sun + sky render (depth 3), one timed render each after a warm-up",
    }
    temporary = out / f".mitsuba_comparison.json.tmp{os.getpid()}"
    temporary.write_text(json.dumps(summary, indent=1))
    os.replace(temporary, out / "mitsuba_comparison.json")
    print(f"wrote {out}/mitsuba_comparison.png, mitsuba_difference.png, mitsuba_comparison.json; exposure x{exposure:.3g}; "
          f"worst per-pixel median {max(s['error']['median'] for s in surfaces):.1e}"
          + ("" if args.no_cost else "; cost ratios " + ", ".join(f"{s['name']} {s['cost']['ratio']:.2f}" for s in surfaces)))


if __name__ == "__main__":
    main()
