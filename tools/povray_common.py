"""Shared pieces of libbrdf's POV-Ray tooling (tools/render_povray_comparison.py, tests/povray/).

Runs POV-Ray 3.7 headless, reads its OpenEXR output, decodes the normal pass of povray/libbrdf.inc,
exports includes with `brdf export povray` and predicts radiance with `brdf eval` (through
tools/report/brdfcli.py). Debian's /usr/bin/python3 (numpy, OpenImageIO).
"""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
POVRAY_DIR = ROOT / "povray"
sys.path.insert(0, str(ROOT / "tools" / "report"))
import brdfcli  # noqa: E402  (the one wrapper around `brdf eval`)
NORMAL_FREQUENCY = 64  # fine normal pass: frac(64 s), see Brdf_Normal_Texture


def blender_to_povray(v):
    """A Blender world vector (z up, right-handed) in POV-Ray's world (y up, left-handed): (x, z, y)."""
    return (v[0], v[2], v[1])


def find_povray():
    exe = shutil.which("povray")
    if not exe:
        sys.exit("povray: not found on PATH (Debian: apt-get install povray)")
    return exe


def run_povray(scene, output, width, height, library_paths=(), declares=None, workdir=None):
    """Renders `scene` to the OpenEXR file `output` (half float, alpha on, no antialiasing, no
    display) and returns the image as float64 H x W x 4 (RGBA). POV-Ray 3.7 only writes files
    it is permitted to (povray.conf); the output goes through the working directory."""
    output = Path(output).resolve()
    workdir = Path(workdir or output.parent)
    workdir.mkdir(parents=True, exist_ok=True)
    command = [find_povray(), f"+I{Path(scene).resolve()}", f"+O{output.name}", f"+W{width}", f"+H{height}",
               "+FE", "+UA", "-D", "-A", "-P", "-V", "+WL0"]
    command += [f"+L{Path(p).resolve()}" for p in [POVRAY_DIR, *library_paths]]
    for key, value in (declares or {}).items():
        command.append(f"Declare={key}={value}")
    result = subprocess.run(command, cwd=output.parent, capture_output=True, text=True)
    if result.returncode != 0 or not output.exists():
        tail = "\n".join((result.stderr + result.stdout).strip().splitlines()[-15:])
        raise RuntimeError(f"povray failed ({result.returncode}) on {scene}:\n{tail}")
    return read_exr(output)


def read_exr(path):
    import OpenImageIO as oiio  # here, not at the top: tools/mitsuba_common.py imports this module in a venv without it
    image = oiio.ImageBuf(str(path))
    if image.has_error:
        raise RuntimeError(f"{path}: {image.geterror()}")
    pixels = image.get_pixels(oiio.FLOAT)
    if pixels is None or pixels.size == 0:
        raise RuntimeError(f"{path}: no pixels")
    return pixels.astype(np.float64)


def write_exr(path, pixels):
    pixels = np.ascontiguousarray(pixels, dtype=np.float32)
    import OpenImageIO as oiio
    spec = oiio.ImageSpec(pixels.shape[1], pixels.shape[0], pixels.shape[2], oiio.FLOAT)
    out = oiio.ImageBuf(spec)
    out.set_pixels(oiio.ROI(), pixels)
    temporary = Path(path).with_name(f".{Path(path).name}.tmp{os.getpid()}.exr")
    if not out.write(str(temporary)):
        raise RuntimeError(f"{path}: {out.geterror()}")
    os.replace(temporary, path)


def decode_normals(coarse, fine, frequency=NORMAL_FREQUENCY):
    """World normals from the two normal passes (RGB = frac(F s) of the slope values of x, y, z;
    s = 1/2 + asin(N.d)/pi). The coarse pass (F = 1) picks the period of the fine one."""
    s1, f = coarse[..., :3], fine[..., :3]
    s = (np.round(frequency * s1 - f) + f) / frequency
    normals = np.sin(np.pi * (s - 0.5))
    norm = np.linalg.norm(normals, axis=-1, keepdims=True)
    return normals / np.where(norm > 0, norm, 1.0)


def erode(mask, pixels):
    """Mask shrunk by `pixels` (4-neighbourhood, repeated): drops silhouette pixels."""
    out = mask.copy()
    for _ in range(pixels):
        shrunk = out.copy()
        shrunk[0, :] = shrunk[-1, :] = False  # outside the image counts as background
        shrunk[:, 0] = shrunk[:, -1] = False
        shrunk[1:, :] &= out[:-1, :]
        shrunk[:-1, :] &= out[1:, :]
        shrunk[:, 1:] &= out[:, :-1]
        shrunk[:, :-1] &= out[:, 1:]
        out = shrunk
    return out


def analytic_sphere_normals(size, half_width=1.15):
    """Unit sphere seen by Brdf_Ortho_Camera(<0,0,-1>, 0, 2.3, 2.3): pixel centres (i + 1/2)."""
    j, i = np.mgrid[0:size, 0:size]
    x = (i + 0.5) / size * 2 * half_width - half_width
    y = half_width - (j + 0.5) / size * 2 * half_width
    z = -np.sqrt(np.clip(1 - x * x - y * y, 0, None))
    return np.stack([x, y, z], -1)


def unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


def scatter_angles(normals, light, view):
    """(theta_i, theta_s, phi_s) in degrees per normal (conventions.md: phi_s is the angle between
    the tangential parts of the light and view directions, 180 deg for forward specular)."""
    light, view = unit(light), unit(view)
    cos_i = normals @ light
    cos_s = normals @ view
    lt = light - cos_i[..., None] * normals
    vt = view - cos_s[..., None] * normals
    denom = np.linalg.norm(lt, axis=-1) * np.linalg.norm(vt, axis=-1)
    cos_phi = np.where(denom > 1e-12, (lt * vt).sum(-1) / np.where(denom > 1e-12, denom, 1.0), -1.0)
    return (np.degrees(np.arccos(np.clip(cos_i, -1, 1))), np.degrees(np.arccos(np.clip(cos_s, -1, 1))),
            np.degrees(np.arccos(np.clip(cos_phi, -1, 1))))


def predicted_radiance(brdf, model, params, wavelengths, normals, light, view, irradiance=1.0):
    """L = f_r cos(theta_i) E per channel at each normal, f_r from `brdf eval` (tools/report/brdfcli.py);
    0 where the normal is unlit or faces away. Returns (radiance N x C, lit_and_visible mask N)."""
    theta_i, theta_s, phi_s = scatter_angles(normals, light, view)
    ok = (theta_i < 90.0 - 1e-9) & (theta_s < 90.0 - 1e-9)
    radiance = np.zeros((normals.shape[0], len(wavelengths)))
    for c, wavelength in enumerate(wavelengths):
        f = brdfcli.evaluate(brdf, model, theta_i[ok], theta_s[ok], phi_s[ok], wavelength=wavelength, **params)
        radiance[ok, c] = f * np.cos(np.radians(theta_i[ok])) * irradiance
    return radiance, ok


def export_include(brdf, model, params, light, view, name, directory, resolution=None):
    """`brdf export povray` (default wavelengths 0.65, 0.55, 0.45 um for R, G, B); returns its stdout."""
    command = [brdf, "export", "povray", "--model", model, *brdfcli.cli_options(**params),
               "--light-dir", ",".join(f"{v:.12g}" for v in light), "--view-dir", ",".join(f"{v:.12g}" for v in view),
               "--name", name, "-o", str(directory)]
    if resolution:
        command += ["--resolution", str(resolution)]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed ({result.returncode}): {result.stderr.strip()}")
    return result.stdout


def to_srgb(linear):
    linear = np.clip(linear, 0.0, 1.0)
    return np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * np.power(linear, 1 / 2.4) - 0.055)
