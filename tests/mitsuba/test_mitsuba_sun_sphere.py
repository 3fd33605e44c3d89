"""Issue 36: one sun on a sphere, rendered by Mitsuba with libbrdf.mitsuba, equals `brdf eval` per pixel.

A unit sphere, an orthographic camera and one sun of irradiance 1 (tools/mitsuba_common.
sun_sphere_scene: direct light, sun samples only, one sample per pixel at a random point of the
pixel, its hit position in an AOV). Each pixel's radiance must be f_r cos(theta_i) with f_r from
the `brdf` program (`brdf eval --queries`, CSV) at that sample's geometry: median relative
difference <= 0.5% (float32 rendering gives ~1e-6), every channel, over the lit pixels whose
value float32 can hold (>= 1e-30: far off a polished lobe f_r falls to 1e-40 and below, which
float32 flushes to 0; those pixels are counted and printed). Seeded random suns (10-75 deg from
the camera axis), models (each in its regime), materials and roughness (polished, intermediate,
rough), in llvm_ad_rgb and scalar_rgb.
scalar_spectral: eval() of the plugin called directly at random directions (the light within a
few degrees of the view's mirror direction) and wavelengths (380-780 nm, four per call, as
Mitsuba samples them) against `brdf eval --wavelength` at each.
Importance transport (light tracing): eval() of a rough mbk, which is not reciprocal, takes wi as
the direction to the light; both modes against `brdf eval` with the roles set accordingly.
"""
import time

import numpy as np

import mitsuba_test_env as env
from checks import check, finish

mc = env.mitsuba_common
BRDF = mc.brdf_exe()
rng = np.random.default_rng(env.seed())
FLOAT32_FLOOR = 1e-30


def sun_sphere_case(mi, variant, roughness, resolution):
    model = str(rng.choice(env.models_for(roughness)))
    surface = env.random_surface(rng, roughness)
    to_sun = env.random_direction(rng, (10.0, 75.0))
    t0 = time.time()
    image = mc.render(mi, mc.sun_sphere_scene(mi, mc.plugin_dict(model, surface), to_sun, resolution), seed=int(rng.integers(1 << 31)))
    seconds = time.time() - t0
    radiance, positions, _ = mc.sphere_pixels(image)
    predicted, asked = mc.predicted_sun_radiance(BRDF, model, surface, positions, to_sun)
    representable = asked[:, None] & (predicted >= FLOAT32_FLOOR)
    relative = np.abs(radiance[representable] / predicted[representable] - 1)
    unlit_dark = np.all(radiance[predicted.max(axis=1) == 0] == 0)
    median = float(np.median(relative))
    label = f"{variant} {roughness} {model} {surface} sun {np.round(to_sun, 3)}"
    print(f"  {label}: {len(positions)} sphere pixels, {representable.sum()} channel values >= 1e-30 "
          f"({(asked[:, None] & (predicted > 0) & ~representable).sum()} below), relative difference median "
          f"{median:.2e}, 99th percentile {np.percentile(relative, 99):.2e}, max {relative.max():.2e}; render {seconds:.1f} s")
    tiny = asked[:, None] & (predicted < FLOAT32_FLOOR)
    check(len(relative) >= 100 and median <= 0.005,
          f"sun on a sphere = brdf eval per pixel, median {median * 100:.2e}% <= 0.5%: {label}")
    check(unlit_dark and np.all(radiance[tiny] < 1e-29),
          f"unlit pixels are black, and those below 1e-30 stay there (max {radiance[tiny].max() if tiny.any() else 0:.1e}): {label}")
    return median


medians = []
mi, plugin = mc.load("llvm_ad_rgb")
for roughness in ("polished", "intermediate", "rough", str(rng.choice(list(env.ROUGHNESS)))):
    medians.append(sun_sphere_case(mi, "llvm_ad_rgb", roughness, 128))
mi, plugin = mc.load("scalar_rgb")
medians.append(sun_sphere_case(mi, "scalar_rgb", str(rng.choice(list(env.ROUGHNESS))), 32))

# --- scalar_spectral: every sampled wavelength evaluated exactly ----------------------------
mi, plugin = mc.load("scalar_spectral")
import drjit as dr  # noqa: E402

worst = 0.0
for roughness in env.ROUGHNESS:
    model = str(rng.choice(env.models_for(roughness)))
    surface = env.random_surface(rng, roughness)
    bsdf = mi.load_dict(mc.plugin_dict(model, surface))
    ctx = mi.BSDFContext()
    for _ in range(3):
        # Near the mirror direction, where even a polished lobe is above float32's range.
        to_view = env.random_direction(rng, (0.0, 80.0))
        to_light = mc.unit(to_view * [-1.0, -1.0, 1.0] + rng.normal(0.0, 0.03, 3))
        wavelengths_nm = np.sort(rng.uniform(380.0, 780.0, 4))
        si = dr.zeros(mi.SurfaceInteraction3f)
        si.wi = mi.Vector3f(*to_view.astype(np.float32))
        si.wavelengths = mi.Spectrum(wavelengths_nm.astype(np.float32))
        wo = to_light.astype(np.float32)
        value = np.array(bsdf.eval(ctx, si, mi.Vector3f(*wo)), dtype=np.float64)
        # The geometry Mitsuba saw (float32), in degrees as brdf eval reads it.
        light, view = mc.unit(wo.astype(np.float64)), mc.unit(np.asarray(si.wi, np.float64))
        normal = np.array([[0.0, 0.0, 1.0]])
        angles = mc.povray_common.scatter_angles(normal, light, view)
        expected = np.array([mc.brdfcli.evaluate_cli(BRDF, model, *angles, wavelength=float(np.float32(w)) * 1e-3, **surface)[0]
                             for w in wavelengths_nm]) * light[2]
        ok = expected >= FLOAT32_FLOOR
        relative = np.abs(value[ok] / expected[ok] - 1)
        worst = max(worst, float(relative.max()) if ok.any() else 0.0)
        check(ok.any() and np.all(relative < 1e-5),
              f"scalar_spectral eval = brdf eval at each of {np.round(wavelengths_nm, 2)} nm: {model} {surface}, "
              f"max relative difference {relative.max() if ok.any() else float('nan'):.1e}")
print(f"scalar_spectral: worst relative difference to brdf eval {worst:.1e}")

# --- importance transport: libbrdf's incident direction is then Mitsuba's wi -----------------
# A rough mbk (not reciprocal: K(theta_i)) at directions far apart in theta, where swapping the
# roles changes f by K(theta_1)/K(theta_2): eval must follow the mode, f(to_light, to_view) cos(wo).
mi, plugin = mc.load("scalar_rgb")
surface = env.random_surface(rng, "rough")
bsdf = mi.load_dict(mc.plugin_dict("mbk", surface))
for _ in range(3):
    wi_np, wo_np = env.random_direction(rng, (0.0, 20.0)).astype(np.float32), env.random_direction(rng, (70.0, 85.0)).astype(np.float32)
    si = dr.zeros(mi.SurfaceInteraction3f)
    si.wi = mi.Vector3f(*wi_np)
    values = {}
    for mode in (mi.TransportMode.Radiance, mi.TransportMode.Importance):
        ctx = mi.BSDFContext(mode)
        values[mode] = np.array(bsdf.eval(ctx, si, mi.Vector3f(*wo_np)), dtype=np.float64)
    wi64, wo64 = mc.unit(wi_np.astype(np.float64)), mc.unit(wo_np.astype(np.float64))
    normal = np.array([[0.0, 0.0, 1.0]])
    expected = {}
    for mode, (light, view) in ((mi.TransportMode.Radiance, (wo64, wi64)), (mi.TransportMode.Importance, (wi64, wo64))):
        angles = mc.povray_common.scatter_angles(normal, light, view)
        expected[mode] = np.array([mc.brdfcli.evaluate_cli(BRDF, "mbk", *angles, wavelength=w, **surface)[0]
                                   for w in mc.RGB_WAVELENGTHS_UM]) * wo64[2]
    asymmetry = np.max(np.abs(expected[mi.TransportMode.Importance] / expected[mi.TransportMode.Radiance] - 1))
    relative = max(np.max(np.abs(values[m] / expected[m] - 1)) for m in values)
    check(asymmetry > 1e-3 and relative < 1e-5,
          f"eval follows the transport mode (rough mbk, theta {np.degrees(np.arccos(wi64[2])):.1f} and {np.degrees(np.arccos(wo64[2])):.1f} deg): "
          f"the two modes differ by {asymmetry * 100:.2f}%, each = brdf eval within {relative:.1e}")

finish(f"ok: one sun on a sphere = brdf eval per pixel (medians {', '.join(f'{m:.1e}' for m in medians)}); spectral eval exact")
