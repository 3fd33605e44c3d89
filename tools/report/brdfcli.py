"""The report scripts' (and the render checks') one way to libbrdf's numbers.

Every number comes from libbrdf's batch API (no physics is re-implemented here), through the
Python module `libbrdf` built beside the given `brdf` program (build/cli/brdf -> build/python/):
numpy arrays in and out, no process start-up, no text. The module gives values bit-identical to
`brdf eval` (tests/python/test_python_contract.py). Without the module (a `brdf` built alone,
e.g. `run.sh --no-build` with $BRDF_EXE) queries go to `brdf eval --queries -` as CSV instead.
"""
import glob
import importlib.util
import io
import json
import os
import shutil
import subprocess
import sys

import numpy as np

REPORT_DIR = os.path.dirname(os.path.abspath(__file__))
MATERIALS_FILE = os.path.join(REPORT_DIR, "materials.json")

# Python keyword -> `brdf eval` option.
_OPTIONS = {
    "material": "--material", "n": "--n", "k": "--k", "sigma_s": "--sigma-s", "lc": "--lc",
    "wavelength": "--wavelength", "sigma_g": "--sigma-g", "rho_s": "--rho-s", "rho_d": "--rho-d",
    "g_term": "--g-term", "k_mode": "--k-mode", "sigma_g_mapping": "--sigma-g-mapping",
    "tolerance": "--tolerance",
}


class BrdfError(RuntimeError):
    pass


def progress(message):
    """One line of sub-progress on stderr (run.sh shows the latest one beside the stage)."""
    print(message, file=sys.stderr, flush=True)


def cli_options(**params):
    args = []
    for key, value in params.items():
        if value is None:
            continue
        if key not in _OPTIONS:
            raise KeyError(f"unknown brdf option {key!r}")
        args += [_OPTIONS[key], f"{value:.17g}" if isinstance(value, float) else str(value)]
    return args


_modules = {}


def module_for(brdf):
    """The `libbrdf` Python package of the build that holds `brdf` (BUILD/cli/brdf -> BUILD/python/
    libbrdf/), or None when that build has none. Loaded from that directory, not from sys.path, so
    that the numbers always come from the same build as the program. (Builds before the package
    layout held a single module BUILD/python/libbrdf*.so; it is loaded the same way.)"""
    exe = shutil.which(brdf) or brdf
    directory = os.path.join(os.path.dirname(os.path.dirname(os.path.realpath(exe))), "python")
    if directory not in _modules:
        package = os.path.join(directory, "libbrdf", "__init__.py")
        single = sorted(glob.glob(os.path.join(directory, "libbrdf*.so")))
        module = None
        if os.path.exists(package) or single:
            # In sys.modules before it runs: the package's relative import of _core looks it up there.
            if os.path.exists(package):
                spec = importlib.util.spec_from_file_location("libbrdf", package, submodule_search_locations=[os.path.dirname(package)])
            else:
                spec = importlib.util.spec_from_file_location("libbrdf", single[0])
            module = importlib.util.module_from_spec(spec)
            sys.modules[spec.name] = module
            spec.loader.exec_module(module)
        _modules[directory] = module
    return _modules[directory]


def evaluate(brdf, model, theta_i, theta_s, phi_s, **params):
    """Evaluates `model` at the broadcast arrays of angles (degrees); returns values of that shape.

    Raises BrdfError (naming the parameter, as brdf would) for bad input or a non-finite value.
    """
    module = module_for(brdf)
    if module is not None:
        params = {key: value for key, value in params.items() if value is not None}
        try:
            values = np.asarray(module.Model(model, **params)(theta_i, theta_s, phi_s), dtype=float)
        except (ValueError, TypeError) as e:
            raise BrdfError(f"libbrdf.Model({model!r}, {params}): {e}") from None
        if not np.all(np.isfinite(values)):  # the module's contract; checked as for brdf eval
            raise BrdfError(f"libbrdf.Model({model!r}, {params}): non-finite value")
        return values
    return evaluate_cli(brdf, model, theta_i, theta_s, phi_s, **params)


def evaluate_cli(brdf, model, theta_i, theta_s, phi_s, **params):
    """evaluate() through `brdf eval --queries -` (CSV both ways)."""
    ti, ts, ps = np.broadcast_arrays(np.asarray(theta_i, float), np.asarray(theta_s, float), np.asarray(phi_s, float))
    shape = ti.shape
    queries = np.column_stack([ti.ravel(), ts.ravel(), ps.ravel()])
    buffer = io.StringIO()
    np.savetxt(buffer, queries, fmt="%.17g", delimiter=",")
    command = [brdf, "eval", "--model", model, *cli_options(**params), "--queries", "-"]
    run = subprocess.run(command, input=buffer.getvalue(), capture_output=True, text=True)
    if run.returncode != 0:
        raise BrdfError(f"{' '.join(command)} failed ({run.returncode}): {run.stderr.strip()}")
    table = np.loadtxt(io.StringIO(run.stdout), delimiter=",", skiprows=1, ndmin=2)
    if table.shape != (queries.shape[0], 4):
        raise BrdfError(f"{' '.join(command)}: expected {queries.shape[0]} rows of 4 columns, got {table.shape}")
    if not np.allclose(table[:, :3], queries, rtol=0, atol=1e-9):
        raise BrdfError(f"{' '.join(command)}: rows came back out of order")
    values = table[:, 3]
    if not np.all(np.isfinite(values)):
        bad = queries[~np.isfinite(values)][0]
        raise BrdfError(f"{' '.join(command)}: non-finite value at theta_i,theta_s,phi_s = {bad.tolist()}")
    return values.reshape(shape)


def load_materials(path=MATERIALS_FILE):
    """The default material set; adds sigma_s_um = sigma_over_lambda x design wavelength."""
    with open(path) as f:
        config = json.load(f)
    lam = config["design_wavelength_um"]
    for s in config["surfaces"]:
        s["sigma_s_um"] = s["sigma_over_lambda"] * lam
    return config


def surface_params(surface, wavelength):
    return dict(material=surface["material"], sigma_s=surface["sigma_s_um"], lc=surface["lc_um"],
                wavelength=wavelength)


# The paper's regime thresholds on g (Krywonos, quoted in section 2.2 of the paper).
G_POLISHED = 0.025
G_VERY_ROUGH = 800.0


def regime(g):
    if g < G_POLISHED:
        return "polished"
    if g > G_VERY_ROUGH:
        return "very rough"
    return "intermediate"
