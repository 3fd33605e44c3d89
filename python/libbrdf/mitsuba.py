"""Mitsuba 3 BSDF plugins for libbrdf's BRDF models (docs/mitsuba.md).

    import mitsuba as mi
    mi.set_variant("scalar_rgb")          # or scalar_spectral, llvm_ad_rgb
    import libbrdf.mitsuba
    libbrdf.mitsuba.register()            # for the variant set now
    mi.load_dict({"type": "libbrdf", "model": "mbk", "material": "Au", "sigma_s": 0.0275, "lc": 2.0})

Plugins: "libbrdf" (property `model`, default mbk) and one per model, "libbrdf_mbk",
"libbrdf_mbk_polished", ..., "libbrdf_microfacet". Properties are the CLI's surface options with
Python's spelling (sigma_s, lc, n, k, material, sigma_g, rho_s, rho_d, g_term, k_mode,
sigma_g_mapping, tolerance), lengths in um; RGB variants add `wavelengths` (um, one per channel,
default "0.65,0.55,0.45" as `brdf bake`).

What each method computes:
  eval()   the model through the batch API (Model.directions) at its tolerance (1e-6 by default),
           times cos(theta_o) as Mitsuba's BSDF::eval expects. Radiance transport: libbrdf's incident
           direction (towards the light) is Mitsuba's wo and the scattered one (towards the viewer)
           its wi; importance transport swaps them (mbk, bk and microfacet with its default
           rho_s = K(theta_i) are not reciprocal).
  sample() chooses the specular spike with probability P_spec = R_spec / F(theta) (= exp(-g) for
           the MBK family, eq. 11's m = 0 term), else the proxy lobe: a Beckmann distribution of
           normals (alpha = sqrt(2) sigma_g, sigma_g as the `microfacet` model maps it, eqs 20/25,
           at the shortest and the longest wavelength) mixed with a cosine lobe for the tails.
           Weight = eval / pdf, the pdf of the whole mixture.
  pdf()    the exact density of sample()'s glossy part (solid angle), times (1 - P_spec).
  spike    a delta lobe (component 1, DeltaReflection) in the mirror direction whose reflectance is
           R_spec(theta) = F(theta) exp(-g(theta, theta)) (conventions: "The specular spike").
Spectral variants evaluate every sampled wavelength exactly: a Model per wavelength (nm -> um),
so g ~ 1/lambda^2 and the index n + i k of a `material` follow the wavelength. mbk builds its K
table per wavelength (~6 ms), so those Models are cached (the last 512 wavelengths).
LLVM variants (llvm_ad_rgb) hand the batch API whole wavefronts; they need Dr.Jit's evaluated
mode (enable_evaluated_mode()), since a symbolic trace has no values to give the library.
"""
import collections

import numpy as np

try:
    import drjit as dr
    import mitsuba as mi
except ImportError as e:  # an optional dependency of the package
    raise ImportError(f"libbrdf.mitsuba needs Mitsuba 3 ({e}): pip install 'mitsuba==3.7.1' (or libbrdf[mitsuba])") from e

from . import _core

BRDF_MODELS = ("mbk", "mbk-polished", "mbk-rough", "mbk-fg", "bk", "bk-modified", "microfacet")
DEFAULT_RGB_WAVELENGTHS_UM = (0.65, 0.55, 0.45)  # `brdf bake`'s default channels
SUPPORTED_VARIANTS = ("scalar_rgb", "scalar_spectral", "llvm_ad_rgb")

_FLOAT_KEYS = ("sigma_s", "lc", "n", "k", "sigma_g", "rho_s", "rho_d", "tolerance")
_STRING_KEYS = ("material", "g_term", "k_mode", "sigma_g_mapping")

COSINE_FRACTION = 0.2  # share of the glossy samples drawn from the cosine lobe (covers the tails)
MIN_COSINE = 1e-7  # directions closer to the horizon than this cos theta scatter nothing
# Below this f cos theta_o (1/sr) in every channel the lobe draws no sample and pdf() is 0 there
# (eval() still gives the value): far off a polished lobe f falls to 1e-50 and less, which is 0 in
# float32, and a sample of weight 0 counts as no sample (Mitsuba's convention, its chi2 adapter's).
SUPPORT_FLOOR = 1e-30
_LOBE, _SPIKE = 0, 1  # component indices
SPECTRAL_RANGE_UM = (0.36, 0.83)  # Mitsuba's spectral range: the proxy's lobes at its ends


def enable_evaluated_mode():
    """LLVM variants: run loops and virtual calls wavefront by wavefront (Dr.Jit's evaluated mode),
    so that eval()/sample() receive arrays with values the batch API can read."""
    dr.set_flag(dr.JitFlag.SymbolicLoops, False)
    dr.set_flag(dr.JitFlag.SymbolicCalls, False)
    dr.set_flag(dr.JitFlag.SymbolicConditionals, False)


def register():
    """Registers "libbrdf" and "libbrdf_<model>" for the variant set now (mi.set_variant)."""
    variant = mi.variant()
    if variant not in SUPPORTED_VARIANTS:
        raise ValueError(f"libbrdf.mitsuba: variant {variant!r} is not supported (supported: {', '.join(SUPPORTED_VARIANTS)})")
    cls = bsdf_class()
    mi.register_bsdf("libbrdf", lambda props: cls(props))
    for name in BRDF_MODELS:
        mi.register_bsdf("libbrdf_" + name.replace("-", "_"), lambda props, name=name: cls(props, model=name))


_classes = {}


def bsdf_class():
    """The plugin's class for the variant set now: Mitsuba's BSDF base class is one per variant."""
    variant = mi.variant()
    if variant not in _classes:
        # nanobind types take one base: the methods are copied into a subclass of this variant's BSDF.
        methods = {k: v for k, v in vars(LibbrdfBSDFMethods).items() if k not in ("__dict__", "__weakref__")}
        _classes[variant] = type("LibbrdfBSDF", (mi.BSDF,), methods)
    return _classes[variant]


def surface_from_properties(props, model=None):
    """(model name, surface keywords, RGB channel wavelengths) from a plugin's Properties."""
    known = set(_FLOAT_KEYS) | set(_STRING_KEYS) | {"model", "wavelengths"}
    unknown = sorted(k for k in props.keys() if k not in known)
    if unknown:
        raise ValueError(f"libbrdf: unknown propert{'ies' if len(unknown) > 1 else 'y'} {', '.join(unknown)} "
                         f"(allowed: {', '.join(sorted(known))})")
    name = props.get("model", model or "mbk")
    if model is not None and name != model:
        raise ValueError(f"model: plugin libbrdf_{model.replace('-', '_')} is model {model!r} (got {name!r})")
    if name not in BRDF_MODELS:
        raise ValueError(f"model: must be one of {', '.join(BRDF_MODELS)} (got {name!r})")
    surface = {key: float(props[key]) for key in _FLOAT_KEYS if key in props}
    surface.update({key: str(props[key]) for key in _STRING_KEYS if key in props})
    text = props.get("wavelengths", ",".join(str(w) for w in DEFAULT_RGB_WAVELENGTHS_UM))
    try:
        wavelengths = tuple(float(w) for w in str(text).split(","))
    except ValueError:
        raise ValueError(f"wavelengths: expected three numbers in um, comma-separated (got {text!r})") from None
    if len(wavelengths) != 3:
        raise ValueError(f"wavelengths: expected three numbers in um (R, G, B channels), got {len(wavelengths)}")
    return name, surface, wavelengths


class SurfaceAtWavelength:
    """The model and its Fresnel term (for P_spec) of one surface at one wavelength (um)."""

    def __init__(self, name, surface, wavelength_um):
        self.model = _core.Model(name, wavelength=wavelength_um, **surface)
        index = {key: surface[key] for key in ("n", "k", "material") if key in surface}
        self.fresnel = _core.Model("fresnel", wavelength=wavelength_um, **index)
        self.has_spike = name != "microfacet"

    def values(self, to_light, to_view):
        return self.model.directions(to_light, to_view)

    def spike(self, theta_deg):
        """(R_spec, F) at incidence theta (degrees): the spike's reflectance and the Fresnel it is part of."""
        if not self.has_spike:
            zero = np.zeros_like(theta_deg)
            return zero, zero
        r_spec = np.asarray(self.model.specular_reflectance(theta_deg), float)
        fresnel = np.asarray(self.fresnel(theta_deg, theta_deg, 180.0), float)
        return r_spec, fresnel


def proxy_alpha(name, surface, wavelength_um):
    """Beckmann alpha = sqrt(2) sigma_g (eq. 7) of the microfacet lobe that stands for the model's:
    microfacet's own sigma_g; eq. 20's rough mapping for mbk-rough (eq. 15), eq. 25's polished one
    for mbk-polished (eq. 14), the automatic choice (`--sigma-g-mapping auto`) for the rest, whose
    lobe is the ASF's (eq. 11) at any roughness."""
    if name == "microfacet":
        keys = dict(surface)
    else:
        keys = {key: surface[key] for key in ("sigma_s", "lc", "n", "k", "material", "tolerance") if key in surface}
        keys["sigma_g_mapping"] = {"mbk-rough": "rough", "mbk-polished": "polished"}.get(name, "auto")
    if keys.get("sigma_s", 0.0) == 0.0 and "sigma_g" not in keys:
        return 1e-3  # a mirror: no lobe to sample; any alpha gives an exact pdf
    keys.pop("rho_s", None)  # amplitudes do not change the lobe's shape
    keys.pop("rho_d", None)
    sigma_g = _core.Model("microfacet", wavelength=wavelength_um, **keys).sigma_g
    return max(np.sqrt(2.0) * sigma_g, 1e-3)


# --- the proxy lobe, in numpy (float64, arrays of N directions in the local frame) ---------------

def beckmann_normal_pdf(m, alpha):
    """D(m) cos theta_m: Beckmann (eq. 7 with alpha = sqrt(2) sigma_g) projected on the macro-surface."""
    cos_m = m[:, 2]
    ok = cos_m > MIN_COSINE
    cos2 = np.where(ok, cos_m * cos_m, 1.0)
    tan2 = (1.0 - cos2) / cos2
    d = np.exp(-tan2 / (alpha * alpha)) / (np.pi * alpha * alpha * cos2 * cos2)
    return np.where(ok, d * cos_m, 0.0)


def glossy_pdf(wi, wo, alphas):
    """Density (solid angle of wo) of the glossy proxy: (1 - c) x the mean of the Beckmann
    reflections of each alpha + c cos/pi."""
    h = wi + wo
    length = np.linalg.norm(h, axis=1)
    ok = (wo[:, 2] > MIN_COSINE) & (wi[:, 2] > MIN_COSINE) & (length > 0)
    m = h / np.where(length > 0, length, 1.0)[:, None]
    wo_dot_m = np.einsum("ij,ij->i", wo, m)
    ok &= wo_dot_m > 0
    normals = sum(beckmann_normal_pdf(m, alpha) for alpha in alphas) / len(alphas)
    reflection = normals / (4.0 * np.where(ok, wo_dot_m, 1.0))  # Jacobian of reflection
    cosine = np.maximum(wo[:, 2], 0.0) / np.pi
    return np.where(ok, (1.0 - COSINE_FRACTION) * reflection + COSINE_FRACTION * cosine, 0.0)


def sample_glossy(wi, u_choice, u2, alphas):
    """Directions wo from the glossy proxy (u_choice in [0,1) picks the cosine or a Beckmann part)."""
    phi = 2.0 * np.pi * u2[:, 1]
    # Cosine lobe (Malley): a uniform disk point lifted to the hemisphere.
    r = np.sqrt(u2[:, 0])
    cosine_wo = np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(np.maximum(1.0 - u2[:, 0], 0.0))], axis=1)
    # Beckmann normals: tan^2 theta_m = -alpha^2 ln(1 - u), then mirror wi about m.
    which = np.clip(((u_choice - COSINE_FRACTION) / (1.0 - COSINE_FRACTION) * len(alphas)).astype(int), 0, len(alphas) - 1)
    alpha = np.asarray(alphas, np.float64)[which]
    tan2 = -alpha * alpha * np.log1p(-u2[:, 0])
    cos_m = 1.0 / np.sqrt(1.0 + tan2)
    sin_m = np.sqrt(np.maximum(1.0 - cos_m * cos_m, 0.0))
    m = np.stack([sin_m * np.cos(phi), sin_m * np.sin(phi), cos_m], axis=1)
    reflected = 2.0 * np.einsum("ij,ij->i", wi, m)[:, None] * m - wi
    return np.where((u_choice < COSINE_FRACTION)[:, None], cosine_wo, reflected)


def theta_degrees(w):
    return np.degrees(np.arccos(np.clip(w[:, 2] / np.linalg.norm(w, axis=1), -1.0, 1.0)))


class LibbrdfBSDFMethods:
    """A libbrdf model as a Mitsuba BSDF (module docstring: what eval, sample and pdf compute); mixed
    into each variant's mi.BSDF by bsdf_class()."""

    def __init__(self, props, model=None):
        mi.BSDF.__init__(self, props)  # this variant's BSDF (bsdf_class)
        self.model_name, self.surface, self.rgb_wavelengths = surface_from_properties(props, model)
        self.variant = mi.variant()
        self.spectral = mi.is_spectral
        self.vectorized = dr.is_jit_v(mi.Float)
        if self.spectral and self.vectorized:
            raise ValueError(f"libbrdf: variant {self.variant} is not supported (a Model per lane's wavelength); "
                             f"use scalar_spectral or llvm_ad_rgb")
        if self.spectral:
            self._cache = collections.OrderedDict()
            low, high = SPECTRAL_RANGE_UM
            if "material" in self.surface:  # a tabulated index: its range (other wavelengths fail in eval)
                table_low, table_high = _core.materials()[self.surface["material"]]["wavelength_range_um"]
                low, high = max(low, table_low), min(high, table_high)
            self.alphas = self.proxy_alphas((low, high))
            probe = self.at_wavelength(0.55)  # bad parameters fail here, at load time
        else:
            self.channels = [SurfaceAtWavelength(self.model_name, self.surface, w) for w in self.rgb_wavelengths]
            self.alphas = self.proxy_alphas(self.rgb_wavelengths)
            probe = self.channels[0]
        self.has_spike = probe.has_spike
        lobe = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
        spike = mi.BSDFFlags.DeltaReflection | mi.BSDFFlags.FrontSide
        self.m_components = [lobe, spike] if self.has_spike else [lobe]
        self.m_flags = (lobe | spike) if self.has_spike else lobe

    def proxy_alphas(self, wavelengths_um):
        """The proxy's alphas at the shortest and longest wavelength: eq. 25's polished lobe widens
        with lambda, and a proxy narrower than the red lobe would leave it to the cosine part
        (rare large weights). One alpha where they agree (eq. 20 does not depend on lambda)."""
        ends = [proxy_alpha(self.model_name, self.surface, w) for w in (min(wavelengths_um), max(wavelengths_um))]
        return tuple(sorted(set(ends)))

    # --- per-wavelength models -------------------------------------------------------------------
    def at_wavelength(self, wavelength_um):
        entry = self._cache.get(wavelength_um)
        if entry is None:
            entry = SurfaceAtWavelength(self.model_name, self.surface, wavelength_um)
            self._cache[wavelength_um] = entry
            if len(self._cache) > 512:
                self._cache.popitem(last=False)
        else:
            self._cache.move_to_end(wavelength_um)
        return entry

    def surfaces_for(self, si):
        """One SurfaceAtWavelength per spectrum entry (RGB: the channels; spectral: si.wavelengths)."""
        if not self.spectral:
            return self.channels
        return [self.at_wavelength(float(w) * 1e-3) for w in np.asarray(si.wavelengths, float).ravel()]

    # --- conversions between Mitsuba values and numpy (N rows) -----------------------------------
    def _vectors(self, v):
        if self.vectorized:
            return np.asarray(v.numpy(), np.float64).reshape(3, -1).T
        return np.asarray(v, np.float64).reshape(1, 3)

    def _floats(self, x):
        return np.asarray(x.numpy() if self.vectorized else x, np.float64).reshape(-1)

    def _mask(self, active):
        return np.asarray(active.numpy() if hasattr(active, "numpy") else active, bool).reshape(-1)

    def _spectrum(self, values):  # values: (N, C)
        if self.vectorized:
            return mi.Spectrum(np.ascontiguousarray(values.T, np.float32))
        return mi.Spectrum(*values[0]) if not self.spectral else mi.Spectrum(values[0])

    def _float(self, values):
        return mi.Float(np.ascontiguousarray(values, np.float32)) if self.vectorized else float(values[0])

    def _vector(self, values):
        if self.vectorized:
            return mi.Vector3f(np.ascontiguousarray(values.T, np.float32))
        return mi.Vector3f(*values[0])

    # --- the BSDF ---------------------------------------------------------------------------------
    def _light_and_view(self, ctx, wi, wo):
        if ctx.mode == mi.TransportMode.Importance:
            return wi, wo
        return wo, wi

    def _lobe_values(self, ctx, surfaces, wi, wo, valid):
        """f(to_light, to_view) cos theta_o for the valid rows (0 elsewhere), shape (N, C)."""
        values = np.zeros((wi.shape[0], len(surfaces)))
        if np.any(valid):
            light, view = self._light_and_view(ctx, wi[valid], wo[valid])
            for c, s in enumerate(surfaces):
                values[valid, c] = s.values(light, view) * wo[valid, 2]
        return values

    def _spike_probability(self, ctx, surfaces, wi, valid):
        """(P_spec, R_spec per channel): the spike's share of the samples, and its reflectance."""
        n = wi.shape[0]
        r_spec = np.zeros((n, len(surfaces)))
        if not (self.has_spike and ctx.is_enabled(mi.BSDFFlags.DeltaReflection, _SPIKE)) or not np.any(valid):
            return np.zeros(n), r_spec
        theta = theta_degrees(wi[valid])
        fresnel = np.zeros((int(valid.sum()), len(surfaces)))
        for c, s in enumerate(surfaces):
            r_spec[valid, c], fresnel[:, c] = s.spike(theta)
        probability = np.zeros(n)
        total_f = fresnel.sum(axis=1)
        probability[valid] = np.where(total_f > 0, r_spec[valid].sum(axis=1) / np.where(total_f > 0, total_f, 1.0), 0.0)
        if not ctx.is_enabled(mi.BSDFFlags.GlossyReflection, _LOBE):
            probability[valid] = np.where(probability[valid] > 0, 1.0, 0.0)
        return np.clip(probability, 0.0, 1.0), r_spec

    def _inputs(self, si, wo, active, *more):
        """numpy rows of wi, wo (None if not given) and `more` (already numpy), broadcast to one count
        (Mitsuba passes width-1 values beside wide ones), and the rows the library may see."""
        wi = self._vectors(si.wi)
        wo_np = self._vectors(wo) if wo is not None else None
        mask = self._mask(active)
        arrays = [wi, mask] + ([wo_np] if wo_np is not None else []) + list(more)
        n = max(a.shape[0] for a in arrays)
        wi = np.broadcast_to(wi, (n, 3))
        valid = np.broadcast_to(mask, (n,)) & np.all(np.isfinite(wi), axis=1) & (wi[:, 2] > MIN_COSINE)
        if wo_np is not None:
            wo_np = np.broadcast_to(wo_np, (n, 3))
            valid &= np.all(np.isfinite(wo_np), axis=1) & (wo_np[:, 2] > MIN_COSINE)
        return wi, wo_np, valid, [np.broadcast_to(a, (n,) + a.shape[1:]) for a in more]

    def _check_evaluated(self):
        if self.vectorized and dr.flag(dr.JitFlag.SymbolicScope):
            raise RuntimeError("libbrdf.mitsuba: a symbolic trace has no values for the batch API; "
                               "call libbrdf.mitsuba.enable_evaluated_mode() before rendering with an LLVM variant")

    def _evaluate(self, ctx, si, wo, active):
        """(wi, wo, valid rows, surfaces, f cos theta_o per channel) of an eval()/pdf() call."""
        self._check_evaluated()
        wi, wo_np, valid, _ = self._inputs(si, wo, active)
        surfaces = self.surfaces_for(si)
        if not ctx.is_enabled(mi.BSDFFlags.GlossyReflection, _LOBE):
            valid = np.zeros_like(valid)
        return wi, wo_np, valid, surfaces, self._lobe_values(ctx, surfaces, wi, wo_np, valid)

    def eval(self, ctx, si, wo, active=True):
        return self._spectrum(self._evaluate(ctx, si, wo, active)[-1])

    def _glossy_pdf(self, ctx, surfaces, wi, wo, valid, values):
        """sample()'s density of wo for the glossy part: (1 - P_spec) x proxy where f cos > floor."""
        if not ctx.is_enabled(mi.BSDFFlags.GlossyReflection, _LOBE):
            return np.zeros(wi.shape[0])
        valid = valid & (values.max(axis=1) > SUPPORT_FLOOR)
        p_spec, _ = self._spike_probability(ctx, surfaces, wi, valid)
        return np.where(valid, (1.0 - p_spec) * glossy_pdf(wi, wo, self.alphas), 0.0)

    def pdf(self, ctx, si, wo, active=True):
        return self.eval_pdf(ctx, si, wo, active)[1]

    def eval_pdf(self, ctx, si, wo, active=True):
        wi, wo_np, valid, surfaces, values = self._evaluate(ctx, si, wo, active)
        return self._spectrum(values), self._float(self._glossy_pdf(ctx, surfaces, wi, wo_np, valid, values))

    def sample(self, ctx, si, sample1, sample2, active=True):
        self._check_evaluated()
        wi, _, valid, (u1, u2) = self._inputs(si, None, active, self._floats(sample1), self._vectors2(sample2))
        n = wi.shape[0]
        surfaces = self.surfaces_for(si)
        lobe_on = ctx.is_enabled(mi.BSDFFlags.GlossyReflection, _LOBE)
        p_spec, r_spec = self._spike_probability(ctx, surfaces, wi, valid)
        take_spike = valid & (u1 < p_spec)
        take_lobe = valid & ~take_spike & lobe_on
        # The lobe reuses u1 past the spike's share to choose between its cosine and Beckmann parts.
        u_lobe = np.where(p_spec < 1.0, (u1 - p_spec) / np.where(p_spec < 1.0, 1.0 - p_spec, 1.0), 0.0)
        wo = np.tile([0.0, 0.0, 1.0], (n, 1))
        wo[take_lobe] = sample_glossy(wi[take_lobe], u_lobe[take_lobe], u2[take_lobe], self.alphas)
        wo[take_spike] = wi[take_spike] * np.array([-1.0, -1.0, 1.0])
        # The direction Mitsuba receives (float32 in every supported variant): weight and pdf are
        # computed there, so that eval(wo) / pdf(wo) later gives this weight again.
        wo = wo.astype(np.float32).astype(np.float64)
        take_lobe &= wo[:, 2] > MIN_COSINE  # Beckmann reflections below the horizon: no sample
        pdf = np.zeros(n)
        weight = np.zeros((n, len(surfaces)))
        if np.any(take_lobe):
            values = self._lobe_values(ctx, surfaces, wi, wo, take_lobe)
            take_lobe &= values.max(axis=1) > SUPPORT_FLOOR  # as _glossy_pdf
            pdf[take_lobe] = (1.0 - p_spec[take_lobe]) * glossy_pdf(wi[take_lobe], wo[take_lobe], self.alphas)
            take_lobe &= pdf > 0
            weight[take_lobe] = values[take_lobe] / pdf[take_lobe, None]
        if np.any(take_spike):
            pdf[take_spike] = p_spec[take_spike]  # a discrete probability, as Mitsuba's delta lobes
            weight[take_spike] = r_spec[take_spike] / p_spec[take_spike, None]
        sampled_type = np.where(take_spike, int(mi.BSDFFlags.DeltaReflection),
                                np.where(take_lobe, int(mi.BSDFFlags.GlossyReflection), int(mi.BSDFFlags.Empty)))
        component = np.where(take_spike, _SPIKE, _LOBE)
        if self.vectorized:
            bs = dr.zeros(mi.BSDFSample3f, n)
            bs.sampled_type = mi.UInt32(sampled_type.astype(np.uint32))
            bs.sampled_component = mi.UInt32(component.astype(np.uint32))
        else:
            bs = mi.BSDFSample3f()
            bs.sampled_type = int(sampled_type[0])
            bs.sampled_component = int(component[0])
        bs.wo = self._vector(wo)
        bs.pdf = self._float(pdf)
        bs.eta = 1.0
        return bs, self._spectrum(weight)

    def _vectors2(self, v):
        if self.vectorized:
            return np.asarray(v.numpy(), np.float64).reshape(2, -1).T
        return np.asarray(v, np.float64).reshape(1, 2)

    def traverse(self, callback):
        pass

    def parameters_changed(self, keys):
        pass

    def to_string(self):
        surface = ", ".join(f"{k}={v}" for k, v in self.surface.items())
        where = "spectral" if self.spectral else f"wavelengths={self.rgb_wavelengths} um"
        return f"LibbrdfBSDF[model={self.model_name}, {surface}, {where}, proxy alpha={', '.join(f'{a:.4g}' for a in self.alphas)}]"
