"""Issue 36: a white furnace rendered by Mitsuba with libbrdf.mitsuba equals `brdf albedo` within 0.5%.

A plane under a constant sky of radiance 1, seen at theta_v (tools/mitsuba_common.furnace_scene):
every pixel is the energy the surface sends towards the camera, spike included. Passes of 64 x 64
pixels x 64 samples (new seed each) are added until the standard error of every channel's mean is
below 0.1% (at most 16 passes; 0.125% must be reached, a quarter of the tolerance), then each
channel (0.65, 0.55, 0.45 um) must be within 0.5%.

What the render measures is the integral over the light's directions for a fixed view,
a_view(theta_v) = int f(l -> v) cos theta_l dl + R_spec(theta_v); `brdf albedo` integrates over the
scattered directions for a fixed light, a(theta_i). They are equal for reciprocal BRDFs:
bk-modified, mbk-polished (K = 1) and microfacet with a given rho_s, here on seeded random polished,
intermediate and rough surfaces at random theta_v. mbk's K(theta_i) (eq. 13) and microfacet's
default rho_s = K(theta_i) make those models non-reciprocal: on polished surfaces (a lobe of a few
percent) the two albedos still agree within 0.5%, which is checked; on intermediate and rough ones
the render is checked against a_view by an independent quadrature (Gauss-Legendre in cos theta_l x
the trapezoid rule in azimuth over libbrdf.Model, converged to 0.05% or the check fails) and the
gap to `brdf albedo`, the non-reciprocity, is printed.
llvm_ad_rgb renders (the batch API on whole wavefronts); one polished case again in scalar_rgb
and in scalar_spectral (a narrow band of the spectral film, each wavelength exact) at fewer samples
(6 standard errors).
"""
import time

import numpy as np

import mitsuba_test_env as env
from checks import check, finish

mc = env.mitsuba_common
BRDF = mc.brdf_exe()
rng = np.random.default_rng(env.seed())
TOLERANCE = 0.005
TARGET_STANDARD_ERROR = 0.001
REQUIRED_STANDARD_ERROR = 0.00125


def furnace(mi, bsdf, theta_view, resolution=64, spp=64, max_passes=16, target=TARGET_STANDARD_ERROR):
    """(mean per channel, standard error per channel, passes) of the furnace's pixels."""
    scene = mc.furnace_scene(mi, bsdf, theta_view, resolution, spp)
    pixels = []
    for k in range(max_passes):
        pixels.append(mc.render(mi, scene, seed=k).reshape(-1, 3))
        all_pixels = np.concatenate(pixels)
        mean = all_pixels.mean(axis=0)
        error = all_pixels.std(axis=0) / np.sqrt(len(all_pixels))
        if np.all(error <= target * mean):
            break
    return mean, error, len(pixels)


def albedo_rgb(model, surface, theta):
    return np.array([mc.brdf_albedo(BRDF, model, surface, theta, w)[0] for w in mc.RGB_WAVELENGTHS_UM])


def view_albedo_quadrature(model, surface, theta_view, wavelength, nodes):
    """a_view(theta_v) = int f(l -> v) cos theta_l dl + R_spec(theta_v) over the light's hemisphere."""
    import libbrdf
    m = libbrdf.Model(model, wavelength=wavelength, **surface)
    x, w = np.polynomial.legendre.leggauss(nodes)
    mu, w_mu = (x + 1) / 2, w / 2                         # cos theta_l in (0, 1)
    phi = np.linspace(0.0, 2 * np.pi, 2 * nodes, endpoint=False)  # periodic: the trapezoid rule
    MU, PHI = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1 - MU * MU)
    light = np.stack([s * np.cos(PHI), s * np.sin(PHI), MU], -1).reshape(-1, 3)
    t = np.radians(theta_view)
    f = m.directions(light, np.array([np.sin(t), 0.0, np.cos(t)])).reshape(MU.shape)
    return float((f * MU * w_mu[:, None]).sum() * (2 * np.pi / (2 * nodes)) + m.specular_reflectance(theta_view))


def report(label, got, error, passes, reference, seconds):
    relative = got / reference - 1
    print(f"  {label}: render {np.round(got, 5)} (+- {np.round(error / got * 100, 3)}%, {passes} passes, {seconds:.1f} s), "
          f"reference {np.round(reference, 5)}: {np.round(relative * 100, 3)}%")
    return relative


mi, plugin = mc.load("llvm_ad_rgb")
started = time.time()
worst = 0.0
RECIPROCAL = (("bk-modified", {}), ("mbk-polished", {}), ("microfacet", {"rho_s": 1.0}))
for roughness in env.ROUGHNESS:
    for model, extra in RECIPROCAL:
        if model not in env.models_for(roughness):
            continue
        surface = {**env.random_surface(rng, roughness), **extra}
        theta = float(rng.uniform(0.0, 80.0))
        t0 = time.time()
        got, error, passes = furnace(mi, mc.plugin_dict(model, surface), theta)
        reference = albedo_rgb(model, surface, theta)
        relative = report(f"{roughness} {model} {surface} theta_v {theta:.1f}", got, error, passes, reference, time.time() - t0)
        worst = max(worst, np.max(np.abs(relative)))
        check(np.all(error <= REQUIRED_STANDARD_ERROR * got) and np.all(np.abs(relative) <= TOLERANCE),
              f"furnace = brdf albedo within 0.5%: {roughness} {model} theta_v {theta:.1f} (max {np.max(np.abs(relative)) * 100:.3f}%)")

for roughness in env.ROUGHNESS:
    surface = env.random_surface(rng, roughness)
    theta = float(rng.uniform(0.0, 80.0))
    t0 = time.time()
    got, error, passes = furnace(mi, mc.plugin_dict("mbk", surface), theta)
    albedo = albedo_rgb("mbk", surface, theta)
    if roughness == "polished":
        relative = report(f"polished mbk {surface} theta_v {theta:.1f}", got, error, passes, albedo, time.time() - t0)
        worst = max(worst, np.max(np.abs(relative)))
        check(np.all(np.abs(relative) <= TOLERANCE), f"furnace = brdf albedo within 0.5%: polished mbk theta_v {theta:.1f}")
        continue
    coarse = np.array([view_albedo_quadrature("mbk", surface, theta, w, 300) for w in mc.RGB_WAVELENGTHS_UM])
    fine = np.array([view_albedo_quadrature("mbk", surface, theta, w, 600) for w in mc.RGB_WAVELENGTHS_UM])
    check(np.all(np.abs(coarse / fine - 1) < 5e-4), f"the quadrature of a_view converged: 300 vs 600 nodes {np.round(coarse / fine - 1, 6)}")
    relative = report(f"{roughness} mbk {surface} theta_v {theta:.1f}", got, error, passes, fine, time.time() - t0)
    worst = max(worst, np.max(np.abs(relative)))
    print(f"    a_view / brdf albedo - 1 (mbk's non-reciprocity through K(theta_i)): {np.round((fine / albedo - 1) * 100, 2)}%")
    check(np.all(error <= REQUIRED_STANDARD_ERROR * got) and np.all(np.abs(relative) <= TOLERANCE),
          f"furnace = a_view within 0.5%: {roughness} mbk theta_v {theta:.1f} (max {np.max(np.abs(relative)) * 100:.3f}%)")
print(f"llvm_ad_rgb: worst |render/reference - 1| = {worst * 100:.3f}% in {time.time() - started:.1f} s")

# --- scalar variants: the same plugin one sample at a time ----------------------------------
surface = env.random_surface(rng, "polished")
theta = float(rng.uniform(0.0, 80.0))
reference = albedo_rgb("bk-modified", surface, theta)
mi, plugin = mc.load("scalar_rgb")
t0 = time.time()
got, error, passes = furnace(mi, mc.plugin_dict("bk-modified", surface), theta, resolution=16, spp=32, max_passes=1)
relative = report(f"scalar_rgb polished bk-modified {surface} theta_v {theta:.1f}", got, error, passes, reference, time.time() - t0)
check(np.all(np.abs(got - reference) <= 6 * error + 1e-6), f"scalar_rgb furnace = brdf albedo within 6 standard errors ({np.round(relative * 100, 3)}%)")

# scalar_spectral: a spectral film of one band 549-551 nm (the sensor samples wavelengths inside
# it); the film integrates over the band, so the render is divided by that of a white Lambertian
# (`diffuse`, reflectance 1: albedo 1 exactly) in the same scene. Reference: brdf albedo averaged
# over the band (Simpson; the albedo is smooth there).
mi, plugin = mc.load("scalar_spectral")


def spectral_furnace(bsdf, spp):
    t = np.radians(theta)
    band = {"type": "regular", "wavelength_min": 549.0, "wavelength_max": 551.0, "values": "1, 1"}
    scene = mi.load_dict({
        "type": "scene", "integrator": {"type": "path", "max_depth": 2},
        "sensor": {**mc.orthographic_sensor(mi, [np.sin(t), 0.0, np.cos(t)], 0.5, 16, spp),
                   "film": {"type": "specfilm", "width": 16, "height": 16, "rfilter": {"type": "box"}, "band": band}},
        "sky": {"type": "constant", "radiance": {"type": "uniform", "value": 1.0}},
        "plane": {"type": "rectangle", "to_world": mi.ScalarTransform4f().scale([20.0, 20.0, 1.0]), "bsdf": bsdf},
    })
    return mc.render(mi, scene).reshape(-1)


t0 = time.time()
white_pixels = spectral_furnace({"type": "diffuse", "reflectance": {"type": "uniform", "value": 1.0}}, 2048)  # Mitsuba's own: fast
white, white_error = white_pixels.mean(), white_pixels.std() / np.sqrt(white_pixels.size)
pixels = spectral_furnace(mc.plugin_dict("bk-modified", surface), 32) / white
got = pixels.mean()
error = got * np.hypot(pixels.std() / np.sqrt(pixels.size) / got, white_error / white)  # both renders' noise
reference = np.dot([1 / 6, 4 / 6, 1 / 6], [mc.brdf_albedo(BRDF, "bk-modified", surface, theta, w)[0] for w in (0.549, 0.550, 0.551)])
print(f"  scalar_spectral polished bk-modified {surface} theta_v {theta:.1f}, 549-551 nm: render / white {got:.5f} "
      f"(+- {error / got * 100:.3f}%, white Lambertian {white:.5f} +- {white_error / white * 100:.3f}%, {time.time() - t0:.1f} s), brdf albedo {reference:.5f}: "
      f"{(got / reference - 1) * 100:.3f}%")
check(abs(got - reference) <= 6 * error + 1e-6, "scalar_spectral furnace = brdf albedo over the band within 6 standard errors")

finish(f"ok: white furnace = brdf albedo (reciprocal models, polished mbk) and = a_view (mbk), worst {worst * 100:.3f}%")
