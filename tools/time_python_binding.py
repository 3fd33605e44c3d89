#!/usr/bin/python3
"""Speed of the Python module (issue 12): model(...) on N points against `brdf eval --queries` on
the same points (one run each), and against the batch API alone in C++ (libbrdf_batch_timer), so
that the binding's overhead per point and per call shows. Also checks all three agree bit for bit.

  cmake --build build --target libbrdf_python brdf libbrdf_batch_timer
  PYTHONPATH=build/python /usr/bin/python3 tools/time_python_binding.py --build build [--points 1000000]

A measurement script, not a test: timings on a shared machine vary by tens of percent.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import libbrdf

SURFACE = dict(material="Au", sigma_s=0.1, lc=2.0, wavelength=0.55)  # intermediate gold
CLI = ["--material", "Au", "--sigma-s", "0.1", "--lc", "2", "--wavelength", "0.55"]


def best_of(n, f):
    best = float("inf")
    for _ in range(n):
        start = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - start)
    return best, out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build", help="build directory (cli/brdf, python/libbrdf_batch_timer)")
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--models", default="mbk,fresnel", help="comma-separated model names")
    args = parser.parse_args()
    brdf = os.path.join(args.build, "cli", "brdf")
    timer = os.path.join(args.build, "python", "libbrdf_batch_timer")
    rng = np.random.default_rng(1)
    n = args.points
    q = np.column_stack([rng.uniform(0, 89.9, n), rng.uniform(0, 89.9, n), rng.uniform(0, 360, n)])
    print(f"{n} random points, {os.cpu_count()} hardware threads; best of 3 except brdf eval (one run)")
    print("model,python_s,python_ns_per_point,cpp_batch_ns_per_point,binding_overhead_ns_per_point,"
          "brdf_eval_s,brdf_eval_ns_per_point,eval_over_python,bit_identical")
    with tempfile.TemporaryDirectory() as tmp:
        qfile, vfile, csv = (os.path.join(tmp, f) for f in ("q.f64", "v.f64", "q.csv"))
        q.astype(np.float64).tofile(qfile)
        np.savetxt(csv, q, fmt="%.17g", delimiter=",")
        for name in args.models.split(","):
            model = libbrdf.Model(name, **SURFACE)
            t_py, v_py = best_of(3, lambda: model(q[:, 0], q[:, 1], q[:, 2]))
            run = subprocess.run([timer, "--queries", qfile, "--values-out", vfile, "--repeat", "3", "--model", name, *CLI],
                                 capture_output=True, text=True, check=True)
            t_cpp = float(run.stdout.split(",")[1])
            v_cpp = np.fromfile(vfile)
            start = time.perf_counter()
            run = subprocess.run([brdf, "eval", "--model", name, *CLI, "--queries", csv], capture_output=True, text=True, check=True)
            t_cli = time.perf_counter() - start
            v_cli = np.loadtxt(run.stdout.splitlines()[1:], delimiter=",", usecols=3)
            same = np.array_equal(v_py, v_cpp) and np.array_equal(v_py, v_cli)
            print(f"{name},{t_py:.3f},{1e9 * t_py / n:.0f},{1e9 * t_cpp / n:.0f},{1e9 * (t_py - t_cpp) / n:.0f},"
                  f"{t_cli:.2f},{1e9 * t_cli / n:.0f},{t_cli / t_py:.1f},{same}", flush=True)
    # Per call: one point, many calls (argument checks, broadcasting, array allocation).
    model = libbrdf.Model("fresnel", **SURFACE)
    calls = 20000
    t_scalar, _ = best_of(3, lambda: [model(30.0, 40.0, 180.0) for _ in range(calls)])
    t_small, _ = best_of(3, lambda: [model(q[:8, 0], q[:8, 1], q[:8, 2]) for _ in range(calls)])
    print(f"per call (fresnel): scalar {1e6 * t_scalar / calls:.1f} us, 8-point arrays {1e6 * t_small / calls:.1f} us")


if __name__ == "__main__":
    sys.exit(main())
