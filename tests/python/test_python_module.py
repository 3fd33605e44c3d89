#!/usr/bin/python3
"""The Python module's array contract (issue 12): broadcasting, shapes, scalars, directions,
the GIL released during evaluation, and bad input -- NaN, infinities, wrong shapes, wrong dtypes,
out-of-domain parameters -- as a clear exception naming the parameter, never a crash or a NaN.
Environment: PYTHONPATH with the module's directory (build/python).
"""
import math
import os
import sys
import threading
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from checks import check, finish  # noqa: E402
import libbrdf  # noqa: E402

GOLD = dict(material="Au", sigma_s=0.05, lc=2.0, wavelength=0.55)
m = libbrdf.Model("mbk", **GOLD)


def raises(kind, call, parameter=None, contains=""):
    """The exception call() raises, if it is `kind` (with .parameter and text as expected), else None."""
    try:
        value = call()
    except kind as e:
        if parameter is not None and getattr(e, "parameter", None) != parameter:
            return None
        if parameter is not None and not str(e).startswith(parameter + ":"):
            return None
        return e if contains in str(e) else None
    except Exception as e:  # noqa: BLE001 - the wrong kind is a failure, reported below
        print(f"  raised {type(e).__name__}: {e}")
        return None
    print(f"  returned {value!r}")
    return None


# --- shapes and broadcasting ----------------------------------------------------------------
ti = np.array([[0.0], [30.0]])          # (2, 1)
ts = np.array([10.0, 30.0, 60.0])       # (3,)
out = m(ti, ts, 180)
check(out.shape == (2, 3) and out.dtype == np.float64, f"(2,1) x (3,) x scalar broadcasts to (2, 3) float64: {out.shape}")
loop = np.array([[m(float(a), float(b), 180.0) for b in ts] for a in ti[:, 0]])
check(np.array_equal(out, loop), "broadcast values equal element-wise scalar calls")
scalar = m(30, 30, 180)
check(type(scalar) is float and math.isfinite(scalar), f"scalar input gives a Python float: {scalar!r}")
check(m([], [], []).shape == (0,), "empty input gives an empty array")
f32 = m(np.float32(30), np.arange(3, dtype=np.int32) * 20, np.uint8(180))
check(np.array_equal(f32, m(30.0, [0.0, 20.0, 40.0], 180.0)), "float32, int32 and uint8 inputs are converted to float64")
strided = np.linspace(0, 80, 20)[::3]
check(np.array_equal(m(strided, strided, 180), m(strided.copy(), strided.copy(), 180)), "non-contiguous views give the same values")
check(m(np.zeros((2, 3, 4)), 20, 0).shape == (2, 3, 4), "3-D input keeps its shape")

# --- directions ------------------------------------------------------------------------------
t_i, t_s, p_s = np.radians(30.0), np.radians(40.0), np.radians(135.0)
light = np.array([np.sin(t_i), 0.0, np.cos(t_i)])
view = np.array([np.sin(t_s) * np.cos(p_s), np.sin(t_s) * np.sin(p_s), np.cos(t_s)])
by_dir = m.directions(light * 3.0, view)
check(abs(by_dir - m(30, 40, 135)) <= 1e-12 * m(30, 40, 135), f"directions (unnormalized) = angles: {by_dir} vs {m(30, 40, 135)}")
many = m.directions(light, np.stack([view, view, [0, 0, 1]]))
check(many.shape == (3,), f"(3,) light with (3, 3) views gives (3,): {many.shape}")

# --- R_spec and K ----------------------------------------------------------------------------
r = m.specular_reflectance([0, 30, 60])
k = m.renormalization(np.array([0.0, 60.0]))
check(r.shape == (3,) and np.all((r > 0) & (r < 1)), f"specular_reflectance in (0, 1): {r}")
check(np.all(k >= 1.0) and np.all(np.isfinite(k)), f"renormalization K >= 1: {k}")
check(libbrdf.Model("microfacet", **GOLD).specular_reflectance(30) == 0.0, "microfacet has no specular spike")

# --- the GIL is released during evaluation ---------------------------------------------------
count = 0
stop = False


def spin():
    global count
    while not stop:
        count += 1


rough = libbrdf.Model("mbk", material="Au", sigma_s=0.5, lc=5.0, wavelength=0.45, tolerance=0.0)
grid = np.linspace(0, 85, 200_000)
thread = threading.Thread(target=spin)
thread.start()
time.sleep(0.05)
before = count
start = time.perf_counter()
rough(grid, grid[::-1], 180)
took = time.perf_counter() - start
during = count - before
stop = True
thread.join()
check(during > 1000, f"another Python thread ran during a {took:.2f} s call ({during} iterations): the GIL is released")

# --- bad input: one clear exception, never a NaN --------------------------------------------
V, T = libbrdf.InvalidArgument, TypeError
small_lut = libbrdf.bake("mbk", resolution=[6, 6, 6], error_samples=100, **GOLD)  # one channel
check(issubclass(V, ValueError) and issubclass(libbrdf.LutFileError, OSError), "InvalidArgument is a ValueError, LutFileError an OSError")
nan, inf = float("nan"), float("inf")
cases = [
    ("NaN theta_i", V, lambda: m(nan, 10, 0), "theta_i"),
    ("NaN theta_s in an array", V, lambda: m(10, [10, nan], 0), "theta_s"),
    ("NaN phi_s", V, lambda: m(10, 10, nan), "phi_s"),
    ("infinite phi_s", V, lambda: m(10, 10, inf), "phi_s"),
    ("theta_i = 90", V, lambda: m(90, 10, 0), "theta_i"),
    ("negative theta_s", V, lambda: m(10, -1, 0), "theta_s"),
    ("NaN in directions", V, lambda: m.directions([0, nan, 1], [0, 0, 1]), "to_light"),
    ("view below the horizon", V, lambda: m.directions([0, 0, 1], [1, 0, -0.1]), "to_view"),
    ("zero light vector", V, lambda: m.directions([0, 0, 0], [0, 0, 1]), "to_light"),
    ("NaN theta_i for K", V, lambda: m.renormalization(nan), "theta_i"),
    ("negative roughness", V, lambda: libbrdf.Model("mbk", material="Au", sigma_s=-0.1, lc=2.0), "sigma_s"),
    ("NaN roughness", V, lambda: libbrdf.Model("mbk", material="Au", sigma_s=nan, lc=2.0), "sigma_s"),
    ("zero correlation length", V, lambda: libbrdf.Model("mbk", material="Au", sigma_s=0.1, lc=0.0), "lc"),
    ("negative wavelength", V, lambda: libbrdf.Model("mbk", material="Au", sigma_s=0.1, lc=2.0, wavelength=-0.5), "wavelength"),
    ("NaN wavelength", V, lambda: libbrdf.Model("mbk", material="Au", sigma_s=0.1, lc=2.0, wavelength=nan), "wavelength"),
    ("wavelength outside the material's table", V, lambda: libbrdf.Model("mbk", material="Au", sigma_s=0.1, lc=2.0, wavelength=50.0), "wavelength"),
    ("unknown model", V, lambda: libbrdf.Model("mbx", **GOLD), "model"),
    ("unknown material", V, lambda: libbrdf.Model("mbk", material="Xx", sigma_s=0.1, lc=2.0), "material"),
    ("material and n", V, lambda: libbrdf.Model("mbk", material="Au", n=1.5, sigma_s=0.1, lc=2.0), "material"),
    ("k without n", V, lambda: libbrdf.Model("mbk", k=0.5, sigma_s=0.1, lc=2.0), "n"),
    ("negative kappa", V, lambda: libbrdf.Model("mbk", n=1.5, k=-1.0, sigma_s=0.1, lc=2.0), None),
    ("bad g_term", V, lambda: libbrdf.Model("microfacet", g_term="smyth", **GOLD), "g_term"),
    ("bad k_mode", V, lambda: libbrdf.Model("mbk", k_mode="x", **GOLD), "k_mode"),
    ("negative tolerance", V, lambda: libbrdf.Model("mbk", tolerance=-1.0, **GOLD), "tolerance"),
    ("string angles", T, lambda: m("30", 10, 0), None),
    ("bool angles", T, lambda: m(np.array([True]), 10, 0), None),
    ("complex angles", T, lambda: m(30 + 0j, 10, 0), None),
    ("object arrays", T, lambda: m(np.array([None, 1.0]), 10, 0), None),
    ("ragged lists", T, lambda: m([[1, 2], [3]], 10, 0), None),
    ("shapes that do not broadcast", T, lambda: m([1, 2], [1, 2, 3], 0), None),
    ("directions not (..., 3)", T, lambda: m.directions([0, 1], [0, 0, 1]), None),
    ("directions of a scalar", T, lambda: m.directions(1.0, [0, 0, 1]), None),
    ("directions that do not broadcast", T, lambda: m.directions(np.ones((2, 3)), np.ones((3, 3))), None),
    ("sigma_s as a string", T, lambda: libbrdf.Model("mbk", material="Au", sigma_s="0.1", lc=2.0), None),
    ("unknown keyword", T, lambda: libbrdf.Model("mbk", sigma=0.1), None),
    ("missing table file", libbrdf.LutFileError, lambda: libbrdf.Lut.open("/nonexistent/table.exr"), None),
    ("bake of a non-BRDF", V, lambda: libbrdf.bake("g", resolution=[4, 4, 4], **GOLD), None),
    ("bake resolution of 1 node", V, lambda: libbrdf.bake("mbk", resolution=[1, 4, 4], **GOLD), "resolution"),
    ("lookup channel out of range", V, lambda: small_lut(30, 30, 180, channel=1), "channel"),
    ("NaN lookup", V, lambda: small_lut(nan, 30, 180), "theta_i"),
    ("R_spec table channel out of range", V, lambda: small_lut.specular_reflectance(30, channel=-1), "channel"),
]
for label, kind, call, parameter in cases:
    check(raises(kind, call, parameter) is not None, f"{label}: {kind.__name__}" + (f" naming '{parameter}'" if parameter else ""))

# Every error message is one line that starts with the parameter.
e = raises(V, lambda: m(10, [10, 10, nan], 0), "theta_s")
check(e is not None and "\n" not in str(e) and "query 2" in str(e) and e.index == 2, f"the message and .index name the query: {e}")
e = raises(V, lambda: m(np.zeros((2, 3)), np.array([[10, 10, 10], [10, nan, 10]]), 0), "theta_s")
check(e is not None and e.index == 4, "a 2-D batch names the flat index of the bad query (4)")
e = raises(V, lambda: libbrdf.Model("mbk", material="Au", sigma_s=-1.0, lc=2.0), "sigma_s")
check(e is not None and e.index is None, "a bad model parameter has index None")
# --- a mistyped keyword: one line naming it and the accepted ones (not pybind11's overload dump) --
MODEL_KEYWORDS = ["name", "sigma_s", "lc", "wavelength", "n", "k", "material", "sigma_g", "rho_s", "rho_d", "g_term",
                  "k_mode", "sigma_g_mapping", "tolerance"]
for label, call, bad, accepted in [
        ("Model(sigma=)", lambda: libbrdf.Model("mbk", material="Au", sigma=0.05, lc=2.0), "sigma", MODEL_KEYWORDS),
        ("Model(wavelenght=)", lambda: libbrdf.Model("mbk", material="Au", sigma_s=0.05, lc=2.0, wavelenght=0.5), "wavelenght",
         MODEL_KEYWORDS),
        ("bake(resolutoin=)", lambda: libbrdf.bake("mbk", resolutoin=[8, 8, 8], **GOLD), "resolutoin",
         ["layout", "resolution", "target_error", "light", "view", "error_samples", "seed"] + MODEL_KEYWORDS)]:
    e = raises(TypeError, call)
    text = str(e) if e else ""
    listed = text.split("accepted: ")[-1].split(", ") if "accepted: " in text else []
    check(e is not None and "\n" not in text and f"'{bad}'" in text and set(accepted) <= set(listed) and len(text) < 400,
          f"{label}: one-line TypeError naming '{bad}' and the accepted keywords: {text!r}")
check("did you mean 'sigma_s'" in str(raises(TypeError, lambda: libbrdf.Model("mbk", sigma=0.05, lc=2.0, material="Au"))),
      "Model(sigma=) suggests sigma_s")
check(repr(libbrdf.Model("mbk", **GOLD)) == repr(m), "the keyword check leaves a correct call alone")

# --- repr: material (name, else n and k), roughness and wavelength; evaluating it rebuilds the model --
for model, expected in [
        (m, ["'mbk'", "material='Au'", "sigma_s=0.05", "lc=2.0", "wavelength=0.55"]),
        (libbrdf.Model("bk-modified", n=1.5, k=0.25, sigma_s=0.1, lc=1.2, wavelength=0.65),
         ["'bk-modified'", "n=1.5", "k=0.25", "sigma_s=0.1", "lc=1.2", "wavelength=0.65"]),
        (libbrdf.Model("microfacet", material="Al", sigma_s=0.1, lc=2.0, rho_s=0.5, rho_d=0.1),
         ["material='Al'", "sigma_s=0.1", "lc=2.0", "rho_s=0.5", "rho_d=0.1", "wavelength=0.55"])]:
    text = repr(model)
    rebuilt = eval(text, {"libbrdf": libbrdf})
    angles = (np.array([10.0, 30.0, 60.0]), np.array([20.0, 45.0, 70.0]), np.array([180.0, 90.0, 0.0]))
    check(all(part in text for part in expected) and np.array_equal(rebuilt(*angles), model(*angles)),
          f"repr {text} names {expected} and rebuilds the same values")

# --- Ctrl-C cancels a bake: KeyboardInterrupt, promptly (the whole bake takes ~25 s) ----------
import signal  # noqa: E402

signal.signal(signal.SIGINT, signal.default_int_handler)
threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
start = time.perf_counter()
try:
    libbrdf.bake("mbk", material="Au", sigma_s=0.1, lc=2.0, resolution=[256, 256, 256])
    interrupted = False
except KeyboardInterrupt:
    interrupted = True
took = time.perf_counter() - start
check(interrupted and took < 10.0, f"SIGINT during bake raised KeyboardInterrupt after {took:.1f} s")

# --- the README's example runs (matplotlib, Agg) and writes its plot --------------------------
import re  # noqa: E402
import subprocess  # noqa: E402
import tempfile  # noqa: E402

readme = open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "README.md")).read()
blocks = re.findall(r"```python\n(.*?)```", readme, re.S)
check(len(blocks) == 1 and len(blocks[0].splitlines()) <= 15, "the README has one Python example, at most 15 lines")
PACKAGE_PARENT = os.path.dirname(os.path.dirname(os.path.abspath(libbrdf.__file__)))  # build/python (libbrdf/__init__.py)
with tempfile.TemporaryDirectory() as tmp:
    run = subprocess.run([sys.executable, "-c", blocks[0]], cwd=tmp, capture_output=True, text=True,
                         env=dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=PACKAGE_PARENT), timeout=120)
    png = os.path.join(tmp, "in_plane.png")
    check(run.returncode == 0 and os.path.getsize(png) > 10000 if os.path.exists(png) else False,
          f"the README example ran and wrote in_plane.png: {run.stderr.strip()[-300:]}")

finish("ok: the Python module's array contract holds")
