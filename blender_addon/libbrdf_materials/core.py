"""Everything of the add-on that does not need Blender: the material request, its validation,
the `brdf export blender` command line, the bake cache and the description file.

Importable and testable with plain Python (tests/blender/test_addon_core.py). The physics lives
in libbrdf; this module only builds the command that asks libbrdf for a material and reads back
what it wrote (the description format: exporters/include/exporters/blender.h).
"""

import dataclasses
import hashlib
import json
import math
import os
import shutil
import subprocess

# Models a table can be baked from (libbrdf: is_brdf), with a one-line description.
MODELS = (
    ("mbk", "MBK", "Modified Beckmann-Kirchhoff, full series with K (eqs 11, 13)"),
    ("mbk-polished", "MBK polished", "MBK polished-surface limit (eq. 14)"),
    ("mbk-rough", "MBK rough", "MBK very-rough limit (eq. 15)"),
    ("mbk-fg", "MBK F G/S", "MBK in eq. 31's form K F G / S A"),
    ("bk", "Beckmann-Kirchhoff", "Original Beckmann-Kirchhoff (eq. 26)"),
    ("bk-modified", "BK modified", "The paper's modified BK, 1/S (eq. 28)"),
    ("microfacet", "Microfacet", "Microfacet with sigma_g mapped from the surface (eqs 2, 7, 20, 25)"),
)
MODEL_NAMES = tuple(m[0] for m in MODELS)

# Built-in optical constants of libbrdf (materials.h); '' means: use n and k.
MATERIALS = ("Au", "Ag", "Al", "Cu", "Cr", "Ni", "Ti", "Si", "BK7")

MODES = (
    ("LUT", "Baked table", "Emission from baked tables lit by every Sun (MBK/BK: the factored form with the "
                           "universal Sigma image), plus the specular spike as a mirror lobe; Cycles and EEVEE"),
    ("FIT", "Native BSDF", "GGX Glossy lobes fitted to the model (colour following the view angle) plus "
                           "the spike as a mirror lobe; any lights, shadows, world; no table"),
    ("OSL", "OSL shader", "Script node with a generated OSL shader doing the table lookups; Cycles with OSL"),
)
MODE_NAMES = tuple(m[0] for m in MODES)

DEFAULT_WAVELENGTHS = (0.65, 0.55, 0.45)  # um, R G B
# The models exported in the factored form (exporters/include/exporters/blender.h, kernel): their
# table is the smooth angular factor P~ (default 54^3, `brdf bake --layout kernel`), the lobe's
# sharpness comes from the universal Sigma image. The other models bake a rusinkiewicz table.
KERNEL_MODELS = ("mbk", "mbk-fg", "bk", "bk-modified")
# Rusinkiewicz table nodes (theta_h, theta_d, phi_d) of the other models. theta_h carries the specular peak (square-mapped), so it
# gets the most nodes. Measured through the node graph against `brdf eval` (theta_i, theta_s <= 70
# deg, values above 1% of the maximum, 6000 random geometries, green channel), max relative error
# 128x64x48 vs the bake's default 90x90x90 (1.85x the nodes): polished Au 3.1% vs 6.6%, satin Cu
# 1.3% vs 2.6%, rough Ti 0.7% vs 1.1%, rough BK7 0.7% vs 0.9%.
DEFAULT_RESOLUTION = (128, 64, 48)
# FIT mode: p95 per-pixel relative error the number of fitted lobes must meet (exporters/fit.h).
DEFAULT_TARGET_ERROR = 0.1

# Presets: name -> (label, description, parameters). Metals from libbrdf's material table.
PRESETS = {
    "POLISHED_AU": ("Polished gold", "Au, sigma_s = 0.005 um, l_c = 2 um: mirror with a faint halo",
                    dict(model="mbk", material="Au", sigma_s=0.005, lc=2.0)),
    "POLISHED_AG": ("Polished silver", "Ag, sigma_s = 0.005 um, l_c = 2 um",
                    dict(model="mbk", material="Ag", sigma_s=0.005, lc=2.0)),
    "SATIN_CU": ("Satin copper", "Cu, sigma_s = 0.05 um, l_c = 2 um: spike and glossy lobe",
                 dict(model="mbk", material="Cu", sigma_s=0.05, lc=2.0)),
    "ROUGH_AL": ("Rough aluminium", "Al, sigma_s = 0.2 um, l_c = 2 um: broad lobe, no spike",
                 dict(model="mbk", material="Al", sigma_s=0.2, lc=2.0)),
    "ROUGH_AU": ("Rough gold", "Au, sigma_s = 0.2 um, l_c = 2 um",
                 dict(model="mbk", material="Au", sigma_s=0.2, lc=2.0)),
    "ROUGH_TI": ("Rough titanium", "Ti, sigma_s = 0.3 um, l_c = 3 um",
                 dict(model="mbk", material="Ti", sigma_s=0.3, lc=3.0)),
    "ROUGH_BK7": ("Rough glass (BK7)", "BK7, sigma_s = 0.2 um, l_c = 2 um: dielectric, surface reflection only",
                  dict(model="mbk", material="BK7", sigma_s=0.2, lc=2.0)),
    "POLISHED_SI": ("Polished silicon", "Si, sigma_s = 0.01 um, l_c = 2 um",
                    dict(model="mbk", material="Si", sigma_s=0.01, lc=2.0)),
}


# K of eq. 13 ("plane", the paper's) or renormalized to the total integrated scatter ("tis": the
# energy-conserving choice, README "brdf albedo").
K_MODES = ("plane", "tis")


class RequestError(ValueError):
    """A bad parameter: the message is one line naming the parameter and its range."""


@dataclasses.dataclass
class MaterialRequest:
    model: str = "mbk"
    sigma_s: float = 0.1          # um, >= 0
    lc: float = 2.0               # um, > 0
    n: float = 1.5                # used when material == ''
    k: float = 0.0                # kappa >= 0
    material: str = ""            # one of MATERIALS, or '' for n, k
    wavelengths: tuple = DEFAULT_WAVELENGTHS  # um, R G B
    mode: str = "LUT"
    resolution: tuple = ()        # table nodes; () or zeros: the default of the model's table
    name: str = ""
    target_error: float = DEFAULT_TARGET_ERROR  # FIT mode only
    k_mode: str = "plane"         # K of mbk, mbk-rough, mbk-fg: plane (eq. 13) | tis (conserves energy)


    def validated(self):
        """Returns a normalized copy or raises RequestError (parameter named, range given)."""
        r = dataclasses.replace(self)
        if r.model not in MODEL_NAMES:
            raise RequestError(f"model: must be one of {'|'.join(MODEL_NAMES)} (got {r.model!r})")
        if r.mode not in MODE_NAMES:
            raise RequestError(f"mode: must be one of {'|'.join(MODE_NAMES)} (got {r.mode!r})")
        _finite_at_least("sigma_s", r.sigma_s, 0.0, inclusive=True, unit="um")
        _finite_at_least("lc", r.lc, 0.0, inclusive=False, unit="um")
        if r.material:
            if r.material not in MATERIALS:
                raise RequestError(f"material: must be one of {'|'.join(MATERIALS)} or empty for n, k (got {r.material!r})")
        else:
            _finite_at_least("n", r.n, 0.0, inclusive=False)
            _finite_at_least("k", r.k, 0.0, inclusive=True)
        waves = tuple(float(w) for w in r.wavelengths)
        if len(waves) not in (1, 3):
            raise RequestError(f"wavelengths: give 1 or 3 wavelengths in um (R, G, B; got {len(waves)})")
        for w in waves:
            _finite_at_least("wavelengths", w, 0.0, inclusive=False, unit="um")
        r.wavelengths = waves
        res = tuple(int(v) for v in (r.resolution or ()))
        if not any(res):  # the default: the exporter's for the factored form, else DEFAULT_RESOLUTION
            res = () if r.model in KERNEL_MODELS else DEFAULT_RESOLUTION
        elif len(res) != 3 or any(v < 2 or v > 4096 for v in res):
            raise RequestError(f"resolution: three node counts in [2, 4096], or 0, 0, 0 for the default (got {tuple(r.resolution)})")
        r.resolution = res
        if not (isinstance(r.target_error, (int, float)) and math.isfinite(r.target_error) and 0.0 < r.target_error <= 1.0):
            raise RequestError(f"target_error: must be a relative error in (0, 1] (got {r.target_error!r})")
        if r.k_mode not in K_MODES:
            raise RequestError(f"k_mode: must be one of {'|'.join(K_MODES)} (got {r.k_mode!r})")
        if not r.name:
            r.name = default_name(r)
        return r


def _finite_at_least(parameter, value, lo, inclusive, unit=""):
    unit_text = f" {unit}" if unit else ""
    ok = isinstance(value, (int, float)) and math.isfinite(value) and (value >= lo if inclusive else value > lo)
    if not ok:
        relation = ">=" if inclusive else ">"
        raise RequestError(f"{parameter}: must be a finite number {relation} {lo:g}{unit_text} (got {value!r})")


def default_name(request):
    surface = request.material or f"n{request.n:g}k{request.k:g}"
    return f"{request.model} {surface} s{request.sigma_s:g} lc{request.lc:g}"


def apply_preset(request, preset):
    """A copy of `request` with a preset's parameters (KeyError names unknown presets)."""
    if preset not in PRESETS:
        raise RequestError(f"preset: must be one of {'|'.join(PRESETS)} (got {preset!r})")
    return dataclasses.replace(request, **PRESETS[preset][2], name="")


def _rounded(x):
    # 7 significant digits: Blender's float properties are 32-bit (0.65 arrives as 0.64999998).
    return float(f"{float(x):.7g}")


def export_keywords(request):
    """The export's parameters for a validated request, in the order `brdf export blender` is given
    them, as libbrdf.export_blender's keywords (without output); lengths, indices and wavelengths
    rounded to 7 significant digits. export_arguments spells the same as command-line options, so
    that the program and the in-process export bake the same table."""
    keywords = {"model": request.model, "sigma_s": _rounded(request.sigma_s), "lc": _rounded(request.lc),
                "wavelength": [_rounded(w) for w in request.wavelengths], "mode": request.mode.lower(),
                "name": request.name}
    if request.material:
        keywords["material"] = request.material
    else:
        keywords.update(n=_rounded(request.n), k=_rounded(request.k))
    if request.mode == "FIT":
        keywords["target_error"] = _rounded(request.target_error)
    elif request.resolution:
        keywords["resolution"] = list(request.resolution)
    if request.k_mode != "plane":
        keywords["k_mode"] = request.k_mode
    return keywords


def export_arguments(request):
    """The `brdf export blender` arguments (without executable and --output) for a validated request:
    export_keywords as options (sigma_s -> --sigma-s; lists comma-separated; floats in 7 digits)."""
    def text(value):
        return f"{value:.7g}" if isinstance(value, float) else str(value)
    args = ["export", "blender"]
    for key, value in export_keywords(request).items():
        args += ["--" + key.replace("_", "-"), ",".join(text(v) for v in value) if isinstance(value, list) else text(value)]
    return args


def albedo_text(description):
    """One line for the panel: the exported model's largest directional albedo and the advice."""
    albedo = description.get("albedo")
    if not albedo:
        return ""
    return f"albedo max {albedo['max']:.3f} (theta_i <= {max(albedo['theta_i_deg']):g} deg): {albedo['advice']}"


# The targets for a FIT render (median, p95 of the per-pixel relative error): a band of
# sun-camera angle whose stated error misses either is flagged in the panel.
FIT_MEDIAN_TARGET, FIT_P95_TARGET = 0.05, 0.20


def fit_angle_text(error, engine):
    """One line: the fit's error per band of sun-camera angle (exporters/fit.h kSunAngleBands), or ''."""
    bands = error.get("by_sun_angle") or []
    if not bands:
        return ""
    parts = []
    for band in bands:
        missed = band["median"] > FIT_MEDIAN_TARGET or band["p95"] > FIT_P95_TARGET
        parts.append(f"{band['from_deg']:g}-{band['to_deg']:g} {band['median']:.1%}/{band['p95']:.0%}"
                     + (" (!)" if missed else ""))
    return f"{engine} by light-camera angle (deg, median/p95): " + ", ".join(parts)


def fit_error_text(description):
    """The panel's text: the FIT lobes' measured per-pixel error, then one line per renderer with
    the error per band of the angle between a light and the camera ((!): the issue's targets,
    median 5% and p95 20%, are not met in that band: the render shows the error stated); lines
    separated by newlines; '' without a fit."""
    error = description.get("fit", {}).get("error")
    if not error:
        return ""
    lobes = len(description["fit"].get("lobes", []))
    met = "" if error.get("target_met", True) else f" (target {error['target_p95']:.0%} not met)"
    # EEVEE gets its own lobes (GGX outside the band EEVEE does not render as GGX): its own error.
    eevee_error = description["fit"].get("eevee", {}).get("error")
    eevee = f"; EEVEE median {eevee_error['median']:.1%}, p95 {eevee_error['p95']:.1%}" if eevee_error else ""
    lines = [f"{lobes} lobe{'s' if lobes != 1 else ''}: error median {error['median']:.1%}, p95 {error['p95']:.1%}{met}{eevee}",
             fit_angle_text(error, "Cycles"), fit_angle_text(eevee_error or {}, "EEVEE")]
    if eevee_error and eevee_error.get("by_sun_angle"):
        # The EEVEE numbers are the exact GGX's; EEVEE's LTC lighting renders longer tails.
        lines.append("EEVEE: medians as stated; its p95 renders higher (docs/fit.md)")
    return "\n".join(line for line in lines if line)


def cache_stem(request):
    """File stem unique to what is baked: a readable prefix and a hash of the arguments."""
    digest = hashlib.sha1("\0".join(export_arguments(request)).encode()).hexdigest()[:16]
    safe = "".join(ch if ch.isalnum() else "_" for ch in request.name)[:40]
    return f"{safe}_{digest}"


def export_command(executable, request, directory):
    """(argv, description_path) for the export of `request` into `directory` (executable None: the
    in-process export; argv is then what `brdf` would have run)."""
    description = os.path.join(directory, cache_stem(request) + ".json")
    return [executable or "brdf"] + export_arguments(request) + ["--output", description], description


def find_brdf_executable(preference=""):
    """How to bake: the `brdf` program of the add-on preference, else $LIBBRDF_BRDF_EXE, else None
    when the libbrdf Python module can export in Blender's own process (the extension bundles it
    as a wheel: in_process_exporter), else `brdf` on PATH."""
    for candidate in (preference, os.environ.get("LIBBRDF_BRDF_EXE", "")):
        if candidate:
            path = os.path.abspath(os.path.expanduser(candidate))
            if os.path.isfile(path) and os.access(path, os.X_OK):
                return path
            raise RequestError(f"brdf executable: {path!r} is not an executable file "
                               "(add-on preferences or LIBBRDF_BRDF_EXE)")
    if in_process_exporter() is not None:
        return None
    found = shutil.which("brdf")
    if not found:
        raise RequestError("brdf executable: not found; set it in the add-on preferences, "
                           "LIBBRDF_BRDF_EXE, or put `brdf` on PATH (or install the extension with its libbrdf wheel)")
    return found


def in_process_exporter():
    """libbrdf.export_blender (the Python module's twin of `brdf export blender`), or None where
    the module is not importable (the legacy add-on without the wheel)."""
    try:
        import libbrdf
    except ImportError:
        return None
    return getattr(libbrdf, "export_blender", None)


class ExportError(RuntimeError):
    """`brdf` failed: the message is its one-line error."""


def run_export(executable, request, directory, reuse=True, timeout=600):
    """Runs the export unless its result is cached in `directory`; returns the description path."""
    os.makedirs(directory, exist_ok=True)
    argv, description = export_command(executable, request, directory)
    if reuse and os.path.isfile(description):
        try:
            check_outputs(load_description(description), description)
            return description
        except ExportError:
            pass  # incomplete or foreign: bake again
    if executable is None:  # in Blender's process, through the bundled libbrdf module
        import libbrdf
        try:
            libbrdf.export_blender(**export_keywords(request), output=description)
        except (libbrdf.InvalidArgument, OSError, RuntimeError) as e:
            raise ExportError(f"libbrdf: error: {e}") from None
    else:
        done = subprocess.run(argv, capture_output=True, text=True, timeout=timeout)
        if done.returncode != 0:
            lines = [line for line in done.stderr.splitlines() if line.strip()]
            raise ExportError(lines[-1] if lines else f"brdf exited with status {done.returncode}")
    check_outputs(load_description(description), description)
    return description


def load_description(path):
    """The description JSON written by `brdf export blender`, checked for what the add-on reads."""
    try:
        with open(path, encoding="utf-8") as f:
            d = json.load(f)
    except (OSError, ValueError) as e:
        raise ExportError(f"{path}: cannot read the material description ({e})") from None
    if d.get("format") != "libbrdf-blender-material" or d.get("format_version") != 1:
        raise ExportError(f"{path}: not a libbrdf Blender material description (format_version 1)")
    for key in ("name", "mode", "model", "wavelengths_um", "fit"):
        if key not in d:
            raise ExportError(f"{path}: description lacks '{key}'")
    if d["mode"] in ("lut", "osl"):
        lut = d.get("lut", {})
        if lut.get("layout") == "kernel":
            required = ("file", "side", "angular", "sigma", "kernel_channels", "closed_form")
        else:
            required = ("file", "width", "height", "columns", "theta_h", "theta_d", "phi_d", "specular")
        for key in required:
            if key not in lut:
                raise ExportError(f"{path}: description lacks 'lut.{key}'")
    return d


def description_files(description):
    """The file names a description refers to (relative to it): tables, images, OSL shader."""
    names = []
    lut = description.get("lut", {})
    if lut:
        names.append(lut["file"])
        if lut.get("layout") == "kernel":
            names += [lut["angular"]["file"], lut["sigma"]["file"]]
    if "osl" in description:
        names.append(description["osl"]["file"])
    return names


def check_outputs(description, path):
    """Raises ExportError unless the files the description names exist beside it."""
    for name in description_files(description):
        f = sibling(path, name)
        if not os.path.isfile(f):
            raise ExportError(f"{path}: its file {f!r} is missing")


def sibling(path, file_name):
    """Absolute path of a file named in a description, relative to the description."""
    return os.path.join(os.path.dirname(os.path.abspath(path)), file_name)
