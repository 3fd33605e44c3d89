#!/usr/bin/env python3
"""`brdf eval --model asf|mbk` per evaluation against a vectorised numpy series, one run.

The numpy reference is what a user would write: the MBK ASF (eq. 11, K = 1) summed over every
term m = 1 .. max(g) + 10 sqrt(max g) + 10 in log space, vectorised over the points, one thread.
mbk (K Qbar A, eq. 11 x Qbar) is also compared with a numpy mbk that computes the same quantity, timed
as a whole: Stover's Qbar in complex numpy (conventions.md; within 1.7e-15 of `brdf eval --model q`
at n = 1.5 + 1i, measured; a one-off check gave <= 9e-15 at 0.18 + 3.4i and 0.5 + 0i with theta_i,
theta_s in [80, 89.999] deg, 2e-14 at 0.5 near its critical angle, 30 deg, where w -> 0), K(theta_i)
by np.interp in a table of brdf's own K every 0.05 deg (`--model k` once per surface, untimed, as a
user would precompute eq. 13's integral; within 2.0e-6 of the direct K, measured), times the numpy A.
The CLI is timed on a query file; its CSV parsing and printing are cancelled out by subtracting
the CPU time of `--model g` (eq. 12, no series) on the same file. Each timing is the best CPU time of
--repeat runs (numpy runs on one thread: OPENBLAS/OMP threads play no part in elementwise numpy), and
the runs are interleaved (numpy, g, then every model and tolerance, --repeat times) so that a change of
load on the machine hits the I/O run and the model runs alike. Everything runs on one CPU (unless
--all-cpus): one thread per evaluation, as numpy.

  tools/bench/eval_vs_numpy.py --brdf build/cli/brdf [--points 1000000] [--repeat 5] [--tolerance 1e-6 1e-4] [--models asf mbk]
      [--methods auto series] [--surface NAME SIGMA_S LC WAVELENGTH ...]
--methods: `brdf eval --asf-method` values; each tolerance runs with `auto` (the default: the kernel table
where certified), `series` runs at 1e-6 only (the series in SIMD lanes, what 1e-6 ran before the table
was certified there).
Prints a CSV: surface,model,tolerance,method,numpy_ns,io_ns (the `--model g` run per query), cli_ns (I/O
cancelled), cli_spread_ns (max - min of that difference over the repeats: how far to trust cli_ns),
speedup (numpy / cli), cli_inproc_ns (the same difference from `brdf eval --timing`: the CPU time of the
batch call itself, best of the repeats, asf or mbk minus g: no CSV I/O to cancel, so ~1 ns precise where
cli_ns is only to within its spread), speedup_inproc (numpy / cli_inproc), speedup_inproc_paired (the
median over the rounds of that ratio within one round: numpy is timed in each round beside the brdf runs,
so that a machine whose speed drifts between phases -- other tenants, as on the two-core VMs this ran
on -- cannot pair a fast phase of one side with a slow phase of the other), max_rel_err (CLI asf against a converged reference series, the first 20000
points; mbk against brdf's own K and Qbar times that series), numpy_max_rel_err (the timed numpy script against the same reference), and, when the Python module imports
(PYTHONPATH=build/python), the same batch API without CSV I/O: module_cpu_ns (all threads),
module_wall_ns, module_speedup_cpu (numpy CPU / module CPU). All the columns above compare mbk with the
numpy ASF too, as before; mbk rows alone add the numpy mbk: numpy_mbk_ns (its best CPU time per point),
speedup_vs_numpy_mbk (numpy_mbk_ns / cli_ns), speedup_inproc_vs_numpy_mbk (numpy_mbk_ns / cli_inproc_ns),
numpy_mbk_max_rel_err (the timed numpy mbk against the same reference as max_rel_err), and its parts'
errors at the check points: numpy_k_interp_max_rel_err (the interpolated K against `--model k`) and
numpy_qbar_max_rel_err (against `--model q`); then module_speedup_cpu_vs_numpy_mbk (numpy mbk CPU /
module CPU); last, setup_ns (the model's --timing set-up CPU minus g's, per point: mbk's K by eq. 13's
quadrature), cli_inproc_with_setup_ns (evaluations plus set-up, best of the rounds, minus g's: what
one process pays for the model at this many points, CSV I/O excluded) and speedup_inproc_with_setup
(numpy / that). The in-process columns include each process's first touches of the kernel table
(its pages and cache lines): a cost per process, not per point, so larger per point at fewer points
(docs/performance.md, "Fast core").
`brdf eval` reads with std::from_chars and writes each number in its shortest exact digits
(std::to_chars): ~0.55 us of I/O per query (was ~2.4 us with strtod/printf, ~0.62 us with %.17g
digits, whose cost grew with the value's exponent), and the spread of the cancelled difference
30-200 ns at 1e6 points on a loaded two-core machine: trust cli_ns to about its cli_spread_ns
(a difference at or below 0, inside that noise, prints as nan with no ratio).
"""
import argparse, math, os, re, resource, statistics, subprocess, sys, tempfile, time
import numpy as np

INDEX = dict(n=1.5, k=1.0)  # mbk's complex index (the ASF alone needs none)
INDEX_ARGS = ["--n", str(INDEX["n"]), "--k", str(INDEX["k"])]
INDEX_COMPLEX = complex(INDEX["n"], INDEX["k"])  # n + i kappa, for the numpy mbk
# The numpy mbk's K table: theta_i every 0.05 deg from 0 to 89.5 deg. Linear interpolation between
# them is within 2.0e-6 of brdf's direct K at the check points (rough surface, worst near 80 deg,
# where K bends); 0.1 deg gave 7.8e-6 and 0.5 deg (181 nodes) 1.9e-4.
K_NODES = np.radians(np.linspace(0.0, 89.5, 1791))  # np.interp holds K(89.5 deg) beyond; the queries stop at 85

SURFACES = {  # the surfaces: lambda = 0.5 um, l_c = 2 um
    "polished": dict(sigma_s=0.005, lc=2.0, wavelength=0.5),
    "intermediate": dict(sigma_s=0.1, lc=2.0, wavelength=0.5),
    "rough": dict(sigma_s=0.5, lc=2.0, wavelength=0.5),
}


def numpy_asf(ti, ts, ps, sigma_s, lc, wavelength, top=None):
    ci, cs = np.cos(ti), np.cos(ts)
    g = (2 * math.pi * sigma_s / wavelength) ** 2 * (ci + cs) ** 2
    eta2 = np.sin(ti) ** 2 + np.sin(ts) ** 2 + 2 * np.sin(ti) * np.sin(ts) * np.cos(ps)
    c = math.pi ** 2 * (lc / wavelength) ** 2 * eta2
    gmax = float(g.max())
    if top is None:
        top = int(gmax + 10 * math.sqrt(gmax) + 10)
    log_g = np.log(g)
    total = np.zeros_like(g)
    for m in range(1, top + 1):
        total += np.exp(-g + m * log_g - math.lgamma(m + 1) - math.log(m) - c / m)
    return math.pi * (lc / wavelength) ** 2 * total


def numpy_qbar(ti, ts, ps, index):
    """Stover's unpolarized factor Qbar = (Q_ss + Q_sp + Q_ps + Q_pp) / 2 (Rayleigh-Rice; conventions.md,
    "Fresnel and Stover's polarization factors"; the paper's Q / 2), for the complex index n + i kappa,
    with w = sqrt(eps - sin^2 theta) on numpy's principal branch and Stover's azimuth phi = phi_s - pi."""
    eps = index ** 2
    si, ss = np.sin(ti), np.sin(ts)
    ci, cs = np.cos(ti), np.cos(ts)
    wi, ws = np.sqrt(eps - si ** 2), np.sqrt(eps - ss ** 2)
    cos_phi, sin2_phi = -np.cos(ps), np.sin(ps) ** 2
    s_i, s_s, p_i, p_s = ci + wi, cs + ws, eps * ci + wi, eps * cs + ws
    q_ss = cos_phi ** 2 / np.abs(s_i * s_s) ** 2
    q_sp = np.abs(ws) ** 2 * sin2_phi / np.abs(s_i * p_s) ** 2
    q_ps = np.abs(wi) ** 2 * sin2_phi / np.abs(p_i * s_s) ** 2
    q_pp = np.abs(wi * ws * cos_phi - eps * si * ss) ** 2 / np.abs(p_i * p_s) ** 2
    return 0.5 * abs(eps - 1) ** 2 * (q_ss + q_sp + q_ps + q_pp)


def numpy_mbk(ti, ts, ps, k_nodes, k_values, sigma_s, lc, wavelength):
    """mbk = K(theta_i) Qbar A (eq. 11 x Qbar, K of eq. 13), as a user would write it: Qbar and A
    in numpy, K interpolated linearly (np.interp) in brdf's own K at the nodes k_nodes (radians),
    a table computed once beforehand (eq. 13's integral is not a user's one-liner)."""
    return (np.interp(ti, k_nodes, k_values) * numpy_qbar(ti, ts, ps, INDEX_COMPLEX)
            * numpy_asf(ti, ts, ps, sigma_s, lc, wavelength))


def reference_asf(ti, ts, ps, sigma_s, lc, wavelength, terms=600):
    """The accuracy reference: the same series summed over m = 1 .. `terms` (every term the sum can
    feel in double precision for these surfaces: the terms fall off like g^m / m! beyond the mode).
    The timed numpy script stops at g + 10 sqrt(g) + 10 (the issue's rule), which misses terms where
    c is large and g small: measured 5.4e-6 relative on the polished surface (forward scatter at
    theta ~ 67 deg, value 6.6e-55)."""
    return numpy_asf(ti, ts, ps, sigma_s, lc, wavelength, top=terms)


def best_cpu(compute, repeat):
    """The best CPU time of `repeat` calls of compute() (numpy: one thread) and its last result."""
    best = math.inf
    for _ in range(repeat):
        t0 = time.process_time()
        result = compute()
        best = min(best, time.process_time() - t0)
    return best, result


def max_rel_err(values, ref):
    return float(np.max(np.abs(values - ref) / ref))


def brdf_values(brdf, args, path):
    """The value column of `brdf eval ARGS --queries PATH` (untimed)."""
    out = subprocess.run([brdf, "eval", *args, "--queries", path], check=True, stdout=subprocess.PIPE, text=True).stdout
    return csv_values(out)


def csv_values(out):
    return np.loadtxt(out.splitlines()[1:], delimiter=",")[:, 3]


def cpu_children():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def time_cli(brdf, args, path, keep_output=False):
    """CPU time (user + system, all threads) of one `brdf eval --timing` run: CPU time, not wall
    time, so that other load on the machine does not count and a threaded batch is not credited
    with its second core. Also returns the evaluations' own CPU seconds as --timing reports them
    (the batch call alone, no CSV reading or writing) and the output."""
    t0 = cpu_children()
    done = subprocess.run([brdf, "eval", "--timing", *args, "--queries", path], check=True,
                          stdout=subprocess.PIPE if keep_output else subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    inproc = float(re.search(r"evaluations ([0-9.e+-]+) s CPU", done.stderr).group(1))
    setup = float(re.search(r"set-up ([0-9.e+-]+) s CPU", done.stderr).group(1))
    return cpu_children() - t0, done.stdout, inproc, setup


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--brdf", required=True)
    ap.add_argument("--points", type=int, default=1000000)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--tolerance", nargs="*", default=["1e-6", "1e-4"])
    ap.add_argument("--models", nargs="*", default=["asf", "mbk"])
    ap.add_argument("--methods", nargs="*", default=["auto", "series"])
    ap.add_argument("--surface", nargs=4, action="append", metavar=("NAME", "SIGMA_S", "LC", "WAVELENGTH"),
                    help="a surface to time instead of the issue's three (um; repeatable), e.g. --surface wide 0.005 20 0.5")
    ap.add_argument("--all-cpus", action="store_true",
                    help="let brdf and the module use every CPU (default: this process and its children on one CPU, "
                         "so that oneTBB runs one thread and its idle workers add no CPU time)")
    a = ap.parse_args()
    surfaces = SURFACES if not a.surface else {
        name: dict(sigma_s=float(sigma_s), lc=float(lc), wavelength=float(wavelength)) for name, sigma_s, lc, wavelength in a.surface}
    if not a.all_cpus:
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})  # inherited by the brdf runs
    rng = np.random.default_rng(1)
    deg = np.column_stack([rng.uniform(0, 85, a.points), rng.uniform(0, 85, a.points), rng.uniform(0, 360, a.points)])
    ti, ts, ps = np.radians(deg.T)
    try:  # the same batch API without CSV I/O: the Python module (PYTHONPATH=build/python)
        import libbrdf
    except ImportError:
        libbrdf = None
    print("surface,model,tolerance,method,numpy_ns,io_ns,cli_ns,cli_spread_ns,speedup,cli_inproc_ns,speedup_inproc,speedup_inproc_paired,max_rel_err,numpy_max_rel_err,module_cpu_ns,module_wall_ns,module_speedup_cpu,"
          "numpy_mbk_ns,speedup_vs_numpy_mbk,speedup_inproc_vs_numpy_mbk,numpy_mbk_max_rel_err,numpy_k_interp_max_rel_err,"
          "numpy_qbar_max_rel_err,module_speedup_cpu_vs_numpy_mbk,setup_ns,cli_inproc_with_setup_ns,speedup_inproc_with_setup")
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "q.csv")
        np.savetxt(path, deg, delimiter=",", fmt="%.17g")
        check = slice(0, min(a.points, 20000))  # the converged reference on the first points
        check_path = os.path.join(tmp, "check.csv")  # those points alone, for mbk's K and Qbar
        np.savetxt(check_path, deg[check], delimiter=",", fmt="%.17g")
        nodes_path = os.path.join(tmp, "k_nodes.csv")  # theta_i = the K table's nodes (theta_s, phi_s play no part)
        np.savetxt(nodes_path, np.column_stack([np.degrees(K_NODES), np.zeros((len(K_NODES), 2))]),
                   delimiter=",", fmt="%.17g")
        configs = [(m, t, "auto") for m in a.models for t in a.tolerance if "auto" in a.methods]
        configs += [(m, "1e-6", "series") for m in a.models if "series" in a.methods]
        for name, s in surfaces.items():
            surface = ["--sigma-s", str(s["sigma_s"]), "--lc", str(s["lc"]), "--wavelength", str(s["wavelength"])]
            exact = reference_asf(ti[check], ts[check], ps[check], **s)
            keep = exact > 1e-300
            # mbk = K Qbar A (eq. 11 x Qbar): its reference multiplies the converged A by brdf's own K and
            # Qbar (`--model k`, `--model q` at the same points), so that the ASF is what is checked.
            mbk_exact, numpy_mbk_columns = None, ""
            if "mbk" in a.models:
                k_direct, q_brdf = (brdf_values(a.brdf, ["--model", factor, *surface, *INDEX_ARGS], check_path)
                                    for factor in ("k", "q"))
                mbk_exact = k_direct * q_brdf * exact
                # The numpy mbk: its K table from brdf once, untimed; then Qbar, K, A and products, timed.
                k_table = brdf_values(a.brdf, ["--model", "k", *surface], nodes_path)
                best_np_mbk, mbk = best_cpu(lambda: numpy_mbk(ti, ts, ps, K_NODES, k_table, **s), a.repeat)
                per_np_mbk = best_np_mbk / a.points * 1e9
                at_check = (ti[check], ts[check], ps[check])
                numpy_mbk_columns = (f"{max_rel_err(mbk[check][keep], mbk_exact[keep]):.2e},"
                                     f"{max_rel_err(np.interp(ti[check], K_NODES, k_table), k_direct):.2e},"
                                     f"{max_rel_err(numpy_qbar(*at_check, INDEX_COMPLEX), q_brdf):.2e}")
            def args(model, tol, method):
                extra = INDEX_ARGS if model != "asf" else []
                return ["--model", model, *surface, *extra, "--tolerance", tol, "--asf-method", method]
            io_runs, io_inproc, runs, inproc, outputs = [], [], {c: [] for c in configs}, {c: [] for c in configs}, {}
            io_setup, setup = [], {c: [] for c in configs}
            numpy_runs = []
            for r in range(a.repeat):  # interleaved: numpy, the I/O run, then every configuration
                numpy_time, numpy_values = best_cpu(lambda: numpy_asf(ti, ts, ps, **s), 1)  # the same values every round
                numpy_runs.append(numpy_time)
                t, _, t_in, t_setup = time_cli(a.brdf, ["--model", "g", *surface], path)
                io_runs.append(t)
                io_inproc.append(t_in)
                io_setup.append(t_setup)
                for config in configs:
                    t, out, t_in, t_setup = time_cli(a.brdf, args(*config), path, keep_output=(r == 0))
                    runs[config].append(t)
                    inproc[config].append(t_in)
                    setup[config].append(t_setup)
                    if r == 0:
                        outputs[config] = out
            io, best_np = min(io_runs), min(numpy_runs)
            numpy_error = max_rel_err(numpy_values[check][keep], exact[keep])
            for model, tol, method in configs:
                config = (model, tol, method)
                vals = csv_values(outputs[config])[check]
                ref = exact if model == "asf" else mbk_exact
                diff = max_rel_err(vals[keep], ref[keep])
                differences = [t - i for t, i in zip(runs[config], io_runs)]
                per_np, per_io = best_np / a.points * 1e9, io / a.points * 1e9
                # A difference at or below 0 is below the noise: no ratio (nan), not a huge one.
                per_cli = (min(runs[config]) - io) / a.points * 1e9
                per_cli = per_cli if per_cli > 0 else math.nan
                spread = (max(differences) - min(differences)) / a.points * 1e9
                per_inproc = (min(inproc[config]) - min(io_inproc)) / a.points * 1e9
                per_inproc = per_inproc if per_inproc > 0 else math.nan
                # The same ratio round by round (numpy and brdf timed within one round), its median: on a
                # machine whose speed drifts between phases (other tenants), a best-of-rounds ratio can pair
                # a fast phase of one side with a slow phase of the other; paired rounds cannot.
                paired = [n / (b - i) for n, b, i in zip(numpy_runs, inproc[config], io_inproc) if b > i]
                per_paired = statistics.median(paired) if paired else math.nan
                # What the process pays for the model beyond g, CSV I/O excluded but set-up included (mbk's
                # K by eq. 13's quadrature): the per-process cost a run of this many points sees.
                per_setup = (min(setup[config]) - min(io_setup)) / a.points * 1e9
                per_with_setup = (min(b + u for b, u in zip(inproc[config], setup[config]))
                                  - min(i + v for i, v in zip(io_inproc, io_setup))) / a.points * 1e9
                setup_columns = f"{per_setup:.1f},{per_with_setup:.1f},{per_np / per_with_setup if per_with_setup > 0 else math.nan:.2f}"
                module, module_vs_mbk = ",,", ""
                if libbrdf is not None and method == "auto":  # the module has no asf-method keyword
                    kwargs = dict(sigma_s=s["sigma_s"], lc=s["lc"], wavelength=s["wavelength"], tolerance=float(tol))
                    if model != "asf":
                        kwargs.update(INDEX)
                    m = libbrdf.Model(model, **kwargs)
                    m(deg[:10, 0], deg[:10, 1], deg[:10, 2])  # one-time set-up (kernel table) outside the timing
                    cpu = wall = math.inf
                    for _ in range(a.repeat):
                        c0, w0 = time.process_time(), time.perf_counter()
                        m(deg[:, 0], deg[:, 1], deg[:, 2])
                        cpu, wall = min(cpu, time.process_time() - c0), min(wall, time.perf_counter() - w0)
                    per_cpu, per_wall = cpu / a.points * 1e9, wall / a.points * 1e9
                    module = f"{per_cpu:.1f},{per_wall:.1f},{per_np / per_cpu:.2f}"
                    if model == "mbk":
                        module_vs_mbk = f"{per_np_mbk / per_cpu:.2f}"
                vs_mbk = ",,,,,"  # the numpy mbk columns: mbk rows only
                if model == "mbk":
                    vs_mbk = f"{per_np_mbk:.1f},{per_np_mbk / per_cli:.2f},{per_np_mbk / per_inproc:.2f},{numpy_mbk_columns}"
                print(f"{name},{model},{tol},{method},{per_np:.1f},{per_io:.1f},{per_cli:.1f},{spread:.1f},{per_np / per_cli:.2f},"
                      f"{per_inproc:.1f},{per_np / per_inproc:.2f},{per_paired:.2f},{diff:.2e},"
                      f"{numpy_error:.2e},{module},{vs_mbk},{module_vs_mbk},{setup_columns}")
                sys.stdout.flush()


if __name__ == "__main__":
    main()
