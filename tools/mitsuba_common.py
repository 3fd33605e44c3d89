"""Shared pieces of libbrdf's Mitsuba 3 tooling (tools/render_mitsuba_comparison.py, tests/mitsuba/).

Runs in the pinned venv of scripts/python_env.sh mitsuba (Mitsuba, numpy) with PYTHONPATH holding
the built package (build/python). Scenes: a white furnace (a plane under a constant sky) and one
sun on a unit sphere seen by an orthographic camera, whose position pass gives each pixel's exact
geometry for `brdf eval`.
"""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import povray_common  # noqa: E402  (scatter_angles: the angle convention of every render check)
from povray_common import brdfcli  # noqa: E402

RGB_WAVELENGTHS_UM = (0.65, 0.55, 0.45)  # the plugin's default channels, as `brdf bake`'s


def load(variant):
    """Sets the Mitsuba variant and registers libbrdf's plugins; returns (mitsuba, libbrdf.mitsuba)."""
    import mitsuba as mi
    mi.set_variant(variant)
    import libbrdf.mitsuba as plugin
    plugin.register()
    if variant.startswith("llvm"):
        plugin.enable_evaluated_mode()
    return mi, plugin


def plugin_dict(model, surface):
    """The plugin's load_dict entry; surface: Python keywords (sigma_s, lc, material, n, k, ...)."""
    return {"type": "libbrdf", "model": model, **surface}


def unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


def orthographic_sensor(mi, towards_camera, half_width, resolution, spp, distance=10.0):
    """An orthographic camera `distance` away along towards_camera (far enough that no ray starts
    behind the surface), seeing [-half_width, half_width]^2 around the origin."""
    d = unit(towards_camera)
    up = [0.0, 1.0, 0.0] if abs(d[1]) < 0.9 else [0.0, 0.0, 1.0]
    to_world = mi.ScalarTransform4f().look_at(origin=(distance * d).tolist(), target=[0, 0, 0], up=up) @ \
        mi.ScalarTransform4f().scale([half_width, half_width, 1.0])
    return {"type": "orthographic", "to_world": to_world,
            "film": {"type": "hdrfilm", "width": resolution, "height": resolution, "rfilter": {"type": "box"},
                     "pixel_format": "rgb", "component_format": "float32"},
            "sampler": {"type": "independent", "sample_count": spp}}


def furnace_scene(mi, bsdf, theta_view_deg, resolution, spp):
    """A white furnace: a plane (20 x 20, normal +z) under a constant sky of radiance 1, seen at
    theta_view from the normal; one bounce (a plane does not see itself). Every pixel is the
    plane's directional albedo for light arriving from the whole sky, spike included."""
    t = np.radians(theta_view_deg)
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 2},
        "sensor": orthographic_sensor(mi, [np.sin(t), 0.0, np.cos(t)], 0.5, resolution, spp),
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": 1.0}},
        "plane": {"type": "rectangle", "to_world": mi.ScalarTransform4f().scale([20.0, 20.0, 1.0]), "bsdf": bsdf},
    })


def sun_sphere_scene(mi, bsdf, to_sun, resolution, towards_camera=(0.0, 0.0, 1.0), half_width=1.05, spp=1):
    """One sun (irradiance 1 on a surface facing it) on a unit sphere at the origin, seen by an
    orthographic camera; direct light only, sun samples only (a BSDF sample never hits a sun).
    The image has the radiance (R, G, B) and the hit position (x, y, z) of each pixel's samples:
    with spp = 1 the position is that of the one sample, and the geometry `brdf eval` needs."""
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "aov", "aovs": "position:position",
                       "radiance": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0}},
        "sensor": orthographic_sensor(mi, towards_camera, half_width, resolution, spp),
        "sun": {"type": "directional", "direction": (-unit(to_sun)).tolist(), "irradiance": {"type": "rgb", "value": 1.0}},
        "sphere": {"type": "sphere", "bsdf": bsdf},
    })


def render(mi, scene, seed=0, spp=None):
    image = mi.render(scene, seed=seed, spp=spp or 0)
    return np.array(image, dtype=np.float64)


def sphere_pixels(image):
    """(radiance N x 3, positions N x 3, pixel indices) of the pixels whose sample hit the sphere."""
    radiance, position = image[..., :3], image[..., 3:6]
    radius = np.linalg.norm(position, axis=-1)
    hit = np.abs(radius - 1.0) < 1e-3
    return radiance[hit], position[hit], np.argwhere(hit)


def predicted_sun_radiance(brdf, model, surface, positions, to_sun, towards_camera=(0.0, 0.0, 1.0),
                           wavelengths=RGB_WAVELENGTHS_UM):
    """f_r cos(theta_i) E (E = 1) per channel from `brdf eval` (the program, CSV) at each sphere
    point; 0 where unlit. Returns (radiance N x C, mask of the points `brdf eval` was asked about)."""
    normals = positions / np.linalg.norm(positions, axis=-1, keepdims=True)
    theta_i, theta_s, phi_s = povray_common.scatter_angles(normals, to_sun, towards_camera)
    asked = (theta_i < 90.0 - 1e-6) & (theta_s < 90.0 - 1e-6)
    radiance = np.zeros((len(normals), len(wavelengths)))
    for c, wavelength in enumerate(wavelengths):
        f = brdfcli.evaluate_cli(brdf, model, theta_i[asked], theta_s[asked], phi_s[asked], wavelength=wavelength, **surface)
        radiance[asked, c] = f * np.cos(np.radians(theta_i[asked]))
    return radiance, asked


def brdf_albedo(brdf, model, surface, theta_deg, wavelength):
    """`brdf albedo` at one angle and wavelength: (albedo, lobe, specular)."""
    command = [brdf, "albedo", "--model", model, *brdfcli.cli_options(**surface), "--wavelength", f"{wavelength:.17g}",
               "--theta-i", f"{theta_deg:.17g}"]
    run = subprocess.run(command, capture_output=True, text=True)
    if run.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed ({run.returncode}): {run.stderr.strip()}")
    fields = run.stdout.splitlines()[1].split(",")
    return float(fields[1]), float(fields[2]), float(fields[3])


def brdf_exe():
    exe = os.environ.get("BRDF_EXE") or str(ROOT / "build" / "cli" / "brdf")
    if not os.path.exists(exe):
        sys.exit(f"brdf: not found at {exe} (set BRDF_EXE)")
    return exe
