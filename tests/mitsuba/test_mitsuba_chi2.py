"""Issue 36: libbrdf.mitsuba's sample() and pdf() agree, by Mitsuba's own statistical test.

mitsuba.chi2.ChiSquareTest with its BSDFAdapter (llvm_ad_rgb: the test needs a vectorized
variant) on the glossy component (ctx.component = 0; the spike is a delta, outside any density):
a polished, an intermediate and a rough surface (seeded random model in its regime, material,
sigma_s, l_c; mitsuba_test_env.py) at
four incident angles each (random in 0-20, 20-45, 45-70 and 70-85 deg), 1e6 samples, significance
0.01 with Sidak's correction over the 12 tests. ires = 16 points per cell edge for the density's
integral: the polished lobe spans a few cells, where Mitsuba's default 4 misjudges the cell
integrals by more than the sampling noise (measured: p = 1e-15 with 4, p = 0.78 with 16, same lobe).
The domain is Mitsuba's SphericalDomain turned so that its pole is +y, normal to the plane of
incidence: the lobes lie on its equator, where its (phi, cos theta) cells are even. With the pole
on +z, a polished lobe near normal incidence is thinner than one cell in cos theta (1 - cos 3 deg
= 0.0014 against cells of 0.02) and the cell integrals fail instead (measured: p = 4e-8 at 0.6 deg).
Then the parts chi2 cannot see, with the full context: the spike is chosen with probability
P_spec and weighs R_spec / P_spec, R_spec equal to `brdf eval --model r-spec`; the glossy pdf
is (1 - P_spec) x the lobe's; and a lobe sample's weight is eval / pdf at its direction.
"""
import time

import numpy as np

import mitsuba_test_env as env
from checks import check, finish

mc = env.mitsuba_common
mi, plugin = mc.load("llvm_ad_rgb")
import drjit as dr  # noqa: E402
from mitsuba.chi2 import BSDFAdapter, ChiSquareTest, SphericalDomain  # noqa: E402

BRDF = mc.brdf_exe()
rng = np.random.default_rng(env.seed())


class EquatorialDomain(SphericalDomain):
    """SphericalDomain with its pole on +y (x, y, z -> x, z, y): the plane of incidence (x-z) is its equator."""

    def map_forward(self, p):
        v = super().map_forward(p)
        return mi.Vector3f(v.x, v.z, v.y)

    def map_backward(self, p):
        return super().map_backward(mi.Vector3f(p.x, p.z, p.y))

ANGLE_RANGES = ((0.0, 20.0), (20.0, 45.0), (45.0, 70.0), (70.0, 85.0))
TESTS = len(env.ROUGHNESS) * len(ANGLE_RANGES)

glossy_only = mi.BSDFContext()
glossy_only.component = 0
started = time.time()
p_values = []
for roughness in env.ROUGHNESS:
    model = str(rng.choice(env.models_for(roughness)))
    surface = env.random_surface(rng, roughness)
    bsdf = mc.plugin_dict(model, surface)
    for low, high in ANGLE_RANGES:
        theta = float(rng.uniform(low, high))
        wi = [float(np.sin(np.radians(theta))), 0.0, float(np.cos(np.radians(theta)))]
        sample_func, pdf_func = BSDFAdapter("libbrdf", bsdf, wi=wi, ctx=glossy_only)
        test = ChiSquareTest(domain=EquatorialDomain(), sample_func=sample_func, pdf_func=pdf_func, sample_dim=3, ires=16,
                             seed=int(rng.integers(1 << 31)))
        accepted = test.run(0.01, test_count=TESTS, quiet=True)
        p_values.append(test.p_value)
        check(accepted, f"chi2 {roughness} {model} {surface} theta_i {theta:.1f} deg: p = {test.p_value:.4g}"
                        + ("" if accepted else f"\n{test.messages}"))

print(f"chi2: {TESTS} tests in {time.time() - started:.1f} s, p-values {', '.join(f'{p:.3g}' for p in p_values)}")


def numbers(x):
    return np.asarray(x.numpy(), np.float64)


# --- the spike and the mixture, with the full context ---------------------------------------
full = mi.BSDFContext()
count = 200_000
for roughness in ("polished", "intermediate"):
    model = str(rng.choice([m for m in env.models_for(roughness) if m != "microfacet"]))  # microfacet has no spike
    surface = env.random_surface(rng, roughness)
    bsdf = mi.load_dict(mc.plugin_dict(model, surface))
    theta = float(rng.uniform(0.0, 80.0))
    wi = mi.Vector3f(float(np.sin(np.radians(theta))), 0.0, float(np.cos(np.radians(theta))))
    si = dr.zeros(mi.SurfaceInteraction3f)
    si.wi = wi
    u = rng.random((3, count))
    bs, weight = bsdf.sample(full, si, mi.Float(u[0]), mi.Point2f(u[1], u[2]))
    spike = (np.asarray(bs.sampled_type.numpy()) & int(mi.BSDFFlags.DeltaReflection)) != 0
    index = {key: surface[key] for key in ("material", "n", "k") if key in surface}  # fresnel reads only these
    r_spec = np.array([mc.brdfcli.evaluate_cli(BRDF, "r-spec", theta, theta, 180.0, wavelength=w, **surface)
                       for w in mc.RGB_WAVELENGTHS_UM], dtype=float).ravel()
    f = np.array([mc.brdfcli.evaluate_cli(BRDF, "fresnel", theta, theta, 180.0, wavelength=w, **index)
                  for w in mc.RGB_WAVELENGTHS_UM], dtype=float).ravel()
    p_spec = r_spec.sum() / f.sum()
    fraction = spike.mean()
    sigma = np.sqrt(p_spec * (1 - p_spec) / count)
    check(abs(fraction - p_spec) <= 5 * sigma + 1e-12,
          f"{roughness} {model} theta {theta:.1f}: spike chosen {fraction:.5f} of the time, P_spec = R_spec/F = {p_spec:.5f} (5 sigma {5 * sigma:.1e})")
    w = numbers(weight)[:, spike]
    pdf = numbers(bs.pdf)[spike]
    spike_reflectance = (w * pdf).mean(axis=1)
    check(np.allclose(spike_reflectance, r_spec, rtol=2e-6, atol=0),
          f"spike weight x P_spec = R_spec {np.round(spike_reflectance, 6)} = brdf eval r-spec {np.round(r_spec, 6)}")
    lobe = ~spike & (numbers(bs.pdf) > 0)
    wo = mi.Vector3f(numbers(bs.wo)[:, lobe].astype(np.float32))
    si_lobe = dr.zeros(mi.SurfaceInteraction3f, int(lobe.sum()))
    si_lobe.wi = wi
    value, pdf_full = bsdf.eval_pdf(full, si_lobe, wo)
    pdf_glossy = numbers(bsdf.pdf(glossy_only, si_lobe, wo))
    ratio = numbers(pdf_full) / pdf_glossy
    check(np.allclose(ratio, 1 - p_spec, rtol=1e-5), f"glossy pdf with the spike on = (1 - P_spec) x alone: {ratio.min():.6f}..{ratio.max():.6f}, 1 - P_spec = {1 - p_spec:.6f}")
    # Channels whose value float32 holds with full precision (subnormals below ~1e-38 keep few digits).
    normal = numbers(value) >= 1e-30
    expected = numbers(value)[normal] / np.broadcast_to(numbers(pdf_full), normal.shape)[normal]
    got = numbers(weight)[:, lobe][normal]
    relative = np.abs(got / expected - 1)
    check(normal.sum() > 50 and np.max(relative) < 1e-5,
          f"lobe sample weight = eval / pdf at its direction: max relative difference {np.max(relative):.1e} over {normal.sum()} channel values of {lobe.sum()} samples")

finish(f"ok: Mitsuba's chi2 test accepts the proxy's sampling at {TESTS} surface/angle pairs")
