#!/usr/bin/env python3
"""Are two `brdf` executables bit-identical on every model? (issue 35: the model registry)

For every model both executables know (`brdf eval --model` lists them when given an unknown name),
on each surface below: `brdf eval` at --points seeded random queries (theta_i, theta_s uniform in
[0, 89.9] deg, phi_s in [0, 360)), and for every BRDF small baked tables (rusinkiewicz 12x12x12;
for the models the kernel layout accepts, its closed-form and table forms) and their lookups at the
same queries (`brdf eval --lut`); the md5 of each output (CSV; the .exr file and the lookups),
or the error message where both refuse (a refusal worded otherwise is listed, not a failure).
Prints one line per run and a summary; exit 1 when any output differs.

  tools/audit/model_identity.py --reference /work/main/build/cli/brdf --candidate build/cli/brdf
"""
import argparse
import hashlib
import os
import random
import subprocess
import sys
import tempfile

SURFACES = {
    "dielectric-ish n,k": ["--sigma-s", "0.05", "--lc", "1.2", "--wavelength", "0.55", "--n", "1.5", "--k", "0.5"],
    "polished Au": ["--material", "Au", "--sigma-s", "0.005", "--lc", "2", "--wavelength", "0.55"],
    "rough Au, K tis": ["--material", "Au", "--sigma-s", "0.5", "--lc", "5", "--wavelength", "0.45", "--k-mode", "tis"],
    # Options only the facet models read (the others refuse them: the refusal is compared too).
    "facet options": ["--n", "0.2", "--k", "3", "--sigma-s", "0.1", "--lc", "2", "--wavelength", "0.633",
                      "--sigma-g", "0.2", "--rho-s", "0.8", "--rho-d", "0.1", "--g-term", "vgroove"],
    "slope options": ["--material", "Ag", "--sigma-s", "0.2", "--lc", "3", "--wavelength", "0.5",
                      "--sigma-g", "0.1", "--g-term", "none"],
    "polished mapping": ["--material", "Cu", "--sigma-s", "0.02", "--lc", "4", "--wavelength", "0.7",
                         "--sigma-g-mapping", "polished", "--rho-d", "0.05"],
}
# Surfaces that only the facet models accept are evaluated, not baked.
EVAL_ONLY = ("facet options", "slope options", "polished mapping")


def model_names(brdf):
    err = subprocess.run([brdf, "eval", "--model", "no-such-model", "--at", "1,1,1"], capture_output=True, text=True).stderr
    return err[err.find("(one of: ") + 9:err.rfind(")")].split(", ")


def digest(brdf, args):
    """(True, md5 of stdout) when it ran, else (False, its one-line error message)."""
    proc = subprocess.run([brdf] + args, capture_output=True, timeout=600)
    if proc.returncode == 0:
        return True, hashlib.md5(proc.stdout).hexdigest()
    return False, proc.stderr.decode(errors="replace").strip()


def bake_digest(brdf, args, directory, query_file):
    """md5 of the baked file and of `brdf eval --lut` (channel 0) at the queries."""
    path = os.path.join(directory, "table.exr")
    if os.path.exists(path):
        os.unlink(path)
    ok, text = digest(brdf, ["bake"] + args + ["-o", path])
    if not ok:
        return False, text
    ok, lookups = digest(brdf, ["eval", "--lut", path, "--queries", query_file])
    with open(path, "rb") as f:
        return True, hashlib.md5(f.read()).hexdigest()[:16] + "+" + (lookups[:15] if ok else "lookup refused")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reference", required=True)
    parser.add_argument("--candidate", required=True)
    parser.add_argument("--points", type=int, default=10000)
    parser.add_argument("--seed", type=int, default=35)
    parser.add_argument("--no-bake", action="store_true")
    a = parser.parse_args()

    reference, candidate = model_names(a.reference), model_names(a.candidate)
    common = [m for m in reference if m in candidate]
    only_new = [m for m in candidate if m not in reference]
    missing = [m for m in reference if m not in candidate]
    rng = random.Random(a.seed)
    queries = ["%.17g,%.17g,%.17g" % (rng.uniform(0, 89.9), rng.uniform(0, 89.9), rng.uniform(0, 360))
               for _ in range(a.points)]
    runs = equal = evaluated = reworded = baked = 0
    with tempfile.TemporaryDirectory() as d:
        query_file = os.path.join(d, "queries.csv")
        with open(query_file, "w") as f:
            f.write("\n".join(queries) + "\n")
        # Which models bake: those the reference bakes on the first surface.
        for surface, params in SURFACES.items():
            for model in common:
                jobs = [("eval", ["eval", "--model", model] + params + ["--queries", query_file], False)]
                if not a.no_bake and surface not in EVAL_ONLY:
                    jobs.append(("bake rusinkiewicz", ["--model", model] + params +
                                 ["--resolution", "12,12,12", "--error-samples", "2000"], True))
                    jobs.append(("bake kernel closed", ["--model", model] + params +
                                 ["--layout", "kernel", "--resolution", "8,8,8", "--error-samples", "1000"], True))
                    jobs.append(("bake kernel table", ["--model", model] + params +
                                 ["--layout", "kernel", "--kernel-angular", "table", "--resolution", "8,8,8",
                                  "--error-samples", "1000"], True))
                for label, args, is_bake in jobs:
                    if is_bake:
                        (ok_r, h_r), (ok_c, h_c) = (bake_digest(a.reference, args, d, query_file),
                                                    bake_digest(a.candidate, args, d, query_file))
                    else:
                        (ok_r, h_r), (ok_c, h_c) = digest(a.reference, args), digest(a.candidate, args)
                    same = ok_r == ok_c and h_r == h_c
                    # Both refused, in other words: the same outcome (no values), reported apart.
                    words = not same and not ok_r and not ok_c
                    runs += 1
                    equal += same
                    reworded += words
                    evaluated += ok_r and not is_bake
                    baked += ok_r and is_bake
                    status = "same" if same else "WORDS" if words else "DIFF"
                    print("%-5s %-14s %-18s %-20s %s%s" % (status, model, label, surface,
                                                         h_r if ok_r else "refused: " + h_r,
                                                         "" if same else " | candidate: " + (h_c if ok_c else "refused: " + h_c)))
                    sys.stdout.flush()
    print("models compared: %d (%s); only in candidate: %s; missing from candidate: %s" %
          (len(common), ", ".join(common), ", ".join(only_new) or "none", ", ".join(missing) or "none"))
    print("runs: %d, md5-equal: %d, refused by both in other words: %d, different: %d; evaluations that ran: %d x %d points; "
          "tables baked: %d" % (runs, equal, reworded, runs - equal - reworded, evaluated, a.points, baked))
    return 0 if equal + reworded == runs and not missing else 1


if __name__ == "__main__":
    sys.exit(main())
