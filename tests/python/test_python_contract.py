#!/usr/bin/python3
"""The Python module gives the same numbers as `brdf eval`, bit for bit (issue 12).

Every quantity `brdf eval --model` accepts, on several surfaces, at the same random points
(including one batch large enough for the batch API's threads), evaluated through
libbrdf.Model and through `brdf eval --queries` (CSV in shortest round-trip digits, exact for doubles): the
values must be equal, not close. Likewise a table baked by libbrdf.bake and by `brdf bake`, and
its lookups through Lut and `brdf eval --lut`.
Environment: BRDF_EXE (the brdf program), PYTHONPATH with the module's directory (build/python).
"""
import io
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import checks  # noqa: E402
import libbrdf  # noqa: E402

checks.print_passes = False
BRDF = os.environ["BRDF_EXE"]

# keyword -> brdf option; the same spelling with '-' for '_'.
def cli_options(params):
    args = []
    for key, value in params.items():
        args += ["--" + key.replace("_", "-"), f"{value:.17g}" if isinstance(value, float) else str(value)]
    return args


def cli_eval(args, queries):
    text = "\n".join(f"{a:.17g},{b:.17g},{c:.17g}" for a, b, c in queries)
    run = subprocess.run([BRDF, "eval", *args, "--queries", "-"], input=text, capture_output=True, text=True, timeout=300)
    if run.returncode != 0:
        raise RuntimeError(f"brdf eval {' '.join(args)}: {run.stderr.strip()}")
    table = np.loadtxt(io.StringIO(run.stdout), delimiter=",", skiprows=1, ndmin=2)
    return table[:, 3]


def report_mismatch(label, ours, theirs, queries):
    bad = np.flatnonzero(ours != theirs)
    if bad.size:
        k = bad[0]
        print(f"  {label}: {bad.size} of {ours.size} differ; first at {queries[k].tolist()}: "
              f"python {ours[k]!r} vs cli {theirs[k]!r}", flush=True)


rng = np.random.default_rng(12)
SURFACES = {
    "polished Au": dict(material="Au", sigma_s=0.005, lc=2.0, wavelength=0.55),
    "intermediate n,k": dict(n=1.5, k=0.5, sigma_s=0.05, lc=1.2, wavelength=0.633),
    "rough Au, K tis": dict(material="Au", sigma_s=0.5, lc=5.0, wavelength=0.45, k_mode="tis"),
    "BK7, series always": dict(material="BK7", sigma_s=0.1, lc=2.0, wavelength=0.55, tolerance=0.0),
    "microfacet given": dict(n=0.2, k=3.0, sigma_s=0.1, lc=2.0, sigma_g=0.2, rho_s=0.8, rho_d=0.1, g_term="vgroove"),
}
POINTS = 200
names = libbrdf.model_names()
# The CLI lists its quantities when given an unknown one: the module must know the same ones.
unknown = subprocess.run([BRDF, "eval", "--model", "no-such-model", "--at", "1,1,1"], capture_output=True, text=True).stderr
cli_names = unknown[unknown.find("(one of: ") + 9:unknown.rfind(")")].split(", ")
checks.check(len(names) >= 20 and names == cli_names, f"model_names() lists brdf eval's quantities: {names} vs {cli_names}")

compared = 0
unread = SURFACES["microfacet given"]
for name in ("mbk", "bk", "fresnel"):  # the same refusal through the module and the CLI
    try:
        libbrdf.Model(name, **unread)
        refused = False
    except libbrdf.InvalidArgument as e:
        refused = "applies only to --model" in str(e) and "microfacet" in str(e)
    cli = subprocess.run([BRDF, "eval", "--model", name, *cli_options(unread), "--at", "30,30,180"], capture_output=True, text=True)
    checks.check(refused and cli.returncode == 2 and "applies only to --model" in cli.stderr and "microfacet" in cli.stderr,
                 f"{name}: microfacet-only options refused by Model() and by brdf eval alike")
# The options only some models read (an error anywhere else, in both front ends): each model's row
# (model_info(name)["options"]); rho_s, rho_d for microfacet, sigma_g, g_term, sigma_g_mapping also
# for mbk-fg.
OPTIONAL = {"rho_s", "rho_d", "sigma_g", "g_term", "sigma_g_mapping"}
checks.check(set(libbrdf.model_info("microfacet")["options"]) == OPTIONAL and
             set(libbrdf.model_info("mbk-fg")["options"]) == {"sigma_g", "g_term", "sigma_g_mapping"} and
             libbrdf.model_info("mbk")["options"] == [], "model_info: the options microfacet, mbk-fg and mbk read")


def read_by(name, params):
    return {key: value for key, value in params.items() if key not in OPTIONAL or key in libbrdf.model_info(name)["options"]}


for label, params in SURFACES.items():
    queries = np.column_stack([rng.uniform(0, 89.9, POINTS), rng.uniform(0, 89.9, POINTS), rng.uniform(-360, 360, POINTS)])
    queries[:3] = [[0, 0, 0], [30, 30, 180], [89.5, 0.0, 90]]  # normal, specular, near grazing
    for name in names:
        params = read_by(name, SURFACES[label])
        model = libbrdf.Model(name, **params)
        ours = model(queries[:, 0], queries[:, 1], queries[:, 2])
        theirs = cli_eval(["--model", name, *cli_options(params)], queries)
        report_mismatch(f"{label} {name}", ours, theirs, queries)
        checks.check(np.array_equal(ours, theirs), f"{label}, {name}: {POINTS} values bit-identical with brdf eval")
        checks.check(np.all(np.isfinite(ours)), f"{label}, {name}: finite")
        compared += POINTS

# One batch above the batch API's parallel threshold (4096): threads must not change a bit.
big = np.column_stack([rng.uniform(0, 89.9, 6000), rng.uniform(0, 89.9, 6000), rng.uniform(0, 360, 6000)])
params = SURFACES["intermediate n,k"]
ours = libbrdf.Model("mbk", **params)(big[:, 0], big[:, 1], big[:, 2])
theirs = cli_eval(["--model", "mbk", *cli_options(params)], big)
report_mismatch("6000-point mbk", ours, theirs, big)
checks.check(np.array_equal(ours, theirs), "6000 points in one call (threaded): bit-identical with brdf eval")
compared += big.shape[0]

# A bake through both front ends, then lookups through both.
with tempfile.TemporaryDirectory() as tmp:
    params = dict(material="Au", sigma_s=0.1, lc=2.0)
    path = os.path.join(tmp, "cli.exr")
    run = subprocess.run([BRDF, "bake", "--model", "mbk", *cli_options(params), "--wavelength", "0.65,0.55",
                          "--resolution", "12,10,8", "--error-samples", "2000", "-o", path], capture_output=True, text=True)
    checks.check(run.returncode == 0, f"brdf bake ran: {run.stderr.strip()}")
    lut = libbrdf.bake("mbk", wavelength=[0.65, 0.55], resolution=[12, 10, 8], error_samples=2000, **params)
    from_file = libbrdf.Lut.open(path)
    checks.check(lut.values.shape == (2, 12, 10, 8) and np.array_equal(lut.values, from_file.values),
                 f"libbrdf.bake's table {lut.values.shape} equals brdf bake's, value for value")
    checks.check(lut.error == from_file.error and lut.error["max_relative"] > 0,
                 f"bake's measured error equals brdf bake's: {lut.error} vs {from_file.error}")
    saved = os.path.join(tmp, "py.exr")
    lut.save(saved)
    checks.check(np.array_equal(libbrdf.Lut.open(saved).values, lut.values), "Lut.save then Lut.open gives the same table")
    q = np.column_stack([rng.uniform(0, 89.9, 300), rng.uniform(0, 89.9, 300), rng.uniform(0, 360, 300)])
    for channel in (0, 1):
        ours = from_file(q[:, 0], q[:, 1], q[:, 2], channel=channel)
        theirs = cli_eval(["--lut", path, "--channel", str(channel)], q)
        report_mismatch(f"lut channel {channel}", ours, theirs, q)
        checks.check(np.array_equal(ours, theirs), f"Lut lookups, channel {channel}: bit-identical with brdf eval --lut")
        compared += q.shape[0]
    # LutSampler: every channel at once ([..., channel]), the same values; above the parallel
    # threshold too, and broadcast (a scalar theta_i against arrays).
    sampler = libbrdf.LutSampler(from_file)
    for queries in (q, big):
        both = sampler(queries[:, 0], queries[:, 1], queries[:, 2])
        checks.check(both.shape == (queries.shape[0], 2), f"LutSampler shape {both.shape}")
        for channel in (0, 1):
            one = from_file(queries[:, 0], queries[:, 1], queries[:, 2], channel=channel)
            checks.check(np.array_equal(both[:, channel], one), f"LutSampler channel {channel}, {queries.shape[0]} points: bit-identical with Lut")
        compared += 2 * queries.shape[0]
    grid = sampler(30.0, q[:5, 1], q[:5, 2])
    checks.check(grid.shape == (5, 2) and np.array_equal(grid[:, 1], from_file(30.0, q[:5, 1], q[:5, 2], channel=1)),
                 "LutSampler broadcasts a scalar theta_i")
    try:
        sampler(91.0, 10.0, 0.0)
        checks.check(False, "LutSampler refuses theta_i = 91 deg")
    except libbrdf.InvalidArgument as e:
        checks.check(e.parameter == "theta_i", f"LutSampler refuses theta_i = 91 deg: {e}")

checks.finish(f"ok: {compared} values through libbrdf and brdf, all bit-identical")
