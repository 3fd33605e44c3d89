"""Per-pixel check of a libbrdf Blender render against `brdf eval` (plain Python: numpy, OpenImageIO).

Shared by tests/blender/test_blender_render.py and tools/render_blender_comparison.py. The
reference radiance of a pixel is the library's BRDF at the pixel's angles (from its Normal-pass
normal, the sun direction and the orthographic view direction) times cos(theta_i) and the sun's
strength and colour; R_spec(theta_v) times the world colour is the mirror lobe's part.
"""

import json
import os
import sys

import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "report"))
import brdfcli  # noqa: E402  (the one wrapper around `brdf eval`)


PASS_ALIASES = {"Emission": "Emit"}  # Blender 5.0's name of the Emit pass


def read_passes(path):
    """{pass name: HxWxC float array} of a Blender multilayer EXR (rows top to bottom). Blender
    3.4 and 4.5 write one part with every pass; 5.0 one part per pass and calls Emit "Emission"."""
    passes = {}
    first = oiio.ImageBuf(path)
    if first.has_error:
        raise RuntimeError(f"{path}: {first.geterror()}")
    for subimage in range(max(first.nsubimages, 1)):
        buf = oiio.ImageBuf(path, subimage, 0)
        spec = buf.spec()
        pixels = buf.get_pixels(oiio.FLOAT).reshape(spec.height, spec.width, spec.nchannels)
        for index, name in enumerate(spec.channelnames):
            parts = name.split(".")
            layer_pass, channel = ".".join(parts[-2:-1]), parts[-1]
            layer_pass = PASS_ALIASES.get(layer_pass, layer_pass)
            passes.setdefault(layer_pass, {})[channel] = pixels[:, :, index]
    out = {}
    for name, channels in passes.items():
        order = [c for c in ("R", "G", "B", "X", "Y", "Z", "A") if c in channels]
        out[name] = np.stack([channels[c] for c in order], axis=-1)
    return out


def erode(mask, steps):
    m = mask.copy()
    for _ in range(steps):
        m[1:, :] &= m[:-1, :].copy()
        m[:-1, :] &= m[1:, :].copy()
        m[:, 1:] &= m[:, :-1].copy()
        m[:, :-1] &= m[:, 1:].copy()
    return m


def pixel_angles(normals, light, view):
    """theta_i, theta_s, phi_s (degrees) per normal (N x 3) for world-space unit L and V."""
    n = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    light = np.asarray(light, float) / np.linalg.norm(light)
    view = np.asarray(view, float) / np.linalg.norm(view)
    cos_i = np.clip(n @ light, -1.0, 1.0)
    cos_s = np.clip(n @ view, -1.0, 1.0)
    # Azimuth between the projections of L and V on the tangent plane (phi_i = 0; conventions.md).
    lt = light[None, :] - cos_i[:, None] * n
    vt = view[None, :] - cos_s[:, None] * n
    denominator = np.linalg.norm(lt, axis=1) * np.linalg.norm(vt, axis=1)
    cos_phi = np.where(denominator > 1e-12, np.sum(lt * vt, axis=1) / np.maximum(denominator, 1e-300), -1.0)
    return (np.degrees(np.arccos(cos_i)), np.degrees(np.arccos(cos_s)),
            np.degrees(np.arccos(np.clip(cos_phi, -1.0, 1.0))))


def description_surface(description_path):
    """(description, model, [per-channel parameter dict]) of an exported material description."""
    with open(description_path, encoding="utf-8") as f:
        d = json.load(f)
    return d, d["model"], d.get("channels")


def brdf_eval(brdf, model, p, angles):
    """`brdf eval` of one channel (a dict of the description's "channels") at N angle triples."""
    return brdfcli.evaluate(brdf, model, *angles, wavelength=p["wavelength_um"], sigma_s=p["sigma_s_um"],
                            lc=p["lc_um"], n=p["n"], k=p["kappa"], k_mode=p.get("k_mode"))


def predicted_radiance(brdf, model, channels, normals, light, view, strength, colour):
    """Per-pixel radiance (N x 3) = f_r cos(theta_i) E C, from `brdf eval` at each channel."""
    ti, ts, ps = pixel_angles(normals, light, view)
    cos_i = np.cos(np.radians(ti))
    out = np.zeros((normals.shape[0], 3))
    lit = (ti < 89.9) & (ts < 89.9)  # elsewhere the radiance is 0 (sun or camera below the horizon)
    for rgb in range(3):
        p = channels[min(rgb, len(channels) - 1)]
        out[lit, rgb] = brdf_eval(brdf, model, p, (ti[lit], ts[lit], ps[lit])) * cos_i[lit] * strength * colour[rgb]
    return out, (ti, ts, ps)


def predicted_spike(brdf, model, channels, normals, view, world):
    """Mirror-lobe radiance R_spec(theta_v) x world colour per pixel (N x 3)."""
    _, ts, _ = pixel_angles(normals, view, view)
    out = np.zeros((normals.shape[0], 3))
    seen = ts < 89.9
    for rgb in range(3):
        p = channels[min(rgb, len(channels) - 1)]
        out[seen, rgb] = brdf_eval(brdf, "r-spec", p, (ts[seen], ts[seen], np.full(seen.sum(), 180.0))) * world[rgb]
    return out


def in_folder(keep, prefix, function):
    """function(folder) in `keep` (created, kept) or in a fresh temporary folder removed afterwards."""
    import shutil
    import tempfile

    folder = keep or tempfile.mkdtemp(prefix=prefix)
    os.makedirs(folder, exist_ok=True)
    try:
        return function(folder)
    finally:
        if not keep:
            shutil.rmtree(folder, ignore_errors=True)


def blender_command(blender, script, *arguments):
    """The command that runs `script` (with `arguments` after "--") in a headless Blender:
    `blender` is a Blender program (Debian's 3.4) or the Python of a venv holding bpy from PyPI
    (Blender 4.5 LTS / 5.0 as a module; BLENDER_USER_CONFIG keeps its settings factory)."""
    if os.path.basename(blender).startswith("python"):
        return [blender, script, "--", *arguments]
    return [blender, "-b", "--factory-startup", "--python-exit-code", "1", "--python", script, "--", *arguments]


def run_blender_job(tmp, renders, blender, brdf, root, addon_zip, eevee_hint="", brdf_for_addon=True):
    """Runs tools/blender_render_job.py in a headless Blender (factory settings, the add-on
    installed from its zip into a private user-scripts folder) on `renders`. Returns the results
    list; exits 77 (skip) when EEVEE has no OpenGL context (`eevee_hint`: the job uses EEVEE) and
    fails the check with the log's tail when Blender fails otherwise."""
    import shutil
    import subprocess

    import checks
    from checks import check

    # addon_zip: a function of the job folder returning a legacy zip (package.addon_zip) or a
    # dict ({"extension": PATH}) for an extension zip.
    addon = addon_zip(tmp)
    job = {"addon": addon if isinstance(addon, dict) else {"zip": addon}, "results": os.path.join(tmp, "results.json"),
           "renders": renders}
    job_path = os.path.join(tmp, "job.json")
    with open(job_path, "w", encoding="utf-8") as f:
        json.dump(job, f, indent=1)
    # brdf_for_addon False: the add-on gets no `brdf` program (it must bake in process: extension + wheel).
    env = {k: v for k, v in os.environ.items() if brdf_for_addon or k != "LIBBRDF_BRDF_EXE"}
    if brdf_for_addon:
        env["LIBBRDF_BRDF_EXE"] = os.path.abspath(brdf) if os.path.sep in brdf else shutil.which(brdf)
    env = dict(env,
               BLENDER_USER_SCRIPTS=os.path.join(tmp, "user_scripts"), BLENDER_USER_CONFIG=os.path.join(tmp, "user_config"),
               BLENDER_USER_EXTENSIONS=os.path.join(tmp, "user_extensions"),
               TMPDIR=tmp, XDG_CACHE_HOME=os.path.join(tmp, "cache"))
    done = subprocess.run(blender_command(blender, os.path.join(root, "tools", "blender_render_job.py"), job_path),
                          env=env, capture_output=True, text=True)
    log = done.stdout + done.stderr
    if done.returncode != 0 or not os.path.isfile(job["results"]):
        if eevee_hint and ("EGL" in log or "OpenGL" in log or "GPU" in log):
            print(f"SKIP: EEVEE needs an OpenGL context{eevee_hint}:\n" + log[-1500:])
            sys.exit(77)
        print(log[-4000:])
        check(False, f"blender ran the job (exit {done.returncode})")
        checks.finish()
    with open(job["results"], encoding="utf-8") as f:
        return json.load(f)
