#!/usr/bin/python3
"""Kills bakes (OpenEXR and MERL) and exports (Blender, POV-Ray) at random moments and counts what
they leave behind (issue 11, "What it must show").

  /usr/bin/python3 tools/interrupt_sweep.py --brdf build/cli/brdf [--runs 60] [--concurrent 12] [--seed 1]

Per run: a command of a random kind writes over an existing complete output set (made by a first
clean run), and gets SIGINT, SIGTERM or SIGKILL after a random delay in [0, 1.2 x its measured
duration], so every phase is hit (model set-up, K table, node values, error measurement, writing,
renaming, after). Counted:
  orphans        temporaries (".NAME.tmp-PID-N") left in the output directory
  changed        SIGINT/SIGTERM runs that exited 130/143 with a final file different from the old
                 one, not saying the outputs were already complete
  unusable       output sets that `brdf eval --lut` (bakes) or a parse (exports) rejects
  mismatched     MERL binary + sidecar pairs whose sidecar CRC-32 does not match the binary
Then `--concurrent` rounds of two MERL bakes (different surfaces) to one path at once, one of
them sometimes killed, count mismatched pairs. SIGKILL cannot be handled: its orphans are listed
apart, and the next write to the same target removes them (stale temporaries of dead processes).
Prints a summary table; exits 1 if a SIGINT/SIGTERM run left an orphan or changed a file, or if
any MERL pair is mismatched.
"""
import argparse
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import zlib

SURFACE = ["--model", "mbk", "--material", "Au", "--lc", "2"]


def kinds(brdf, d):
    """name -> (command(sigma), final files)."""
    return {
        "bake-exr": (lambda s: [brdf, "bake"] + SURFACE + ["--sigma-s", s, "--resolution", "40,40,40",
                                                          "--error-samples", "2000", "-o", f"{d}/t.exr"],
                     ["t.exr"]),
        "bake-merl": (lambda s: [brdf, "bake"] + SURFACE + ["--sigma-s", s, "--error-samples", "2000",
                                                           "-o", f"{d}/t.binary"],
                      ["t.binary", "t.binary.json"]),
        "export-blender": (lambda s: [brdf, "export", "blender"] + SURFACE + ["--sigma-s", s, "--mode", "osl",
                                                                             "--resolution", "32,32,32",
                                                                             "--output", f"{d}/m.json"],
                           ["m.json", "m.exr", "m.osl"]),
        "export-povray": (lambda s: [brdf, "export", "povray"] + SURFACE + ["--sigma-s", s, "--light-dir", "0,1,1",
                                                                           "--view-dir", "0,1,-1", "--name", "P",
                                                                           "--resolution", "24", "-o", d],
                          ["P.inc"]),
    }


def default_signals():
    """In the child: SIGINT/SIGTERM back to their default (a background shell job ignores SIGINT,
    and brdf keeps an ignored signal ignored)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def snapshot(d, files):
    out = {}
    for f in files:
        try:
            with open(os.path.join(d, f), "rb") as h:
                out[f] = zlib.crc32(h.read())
        except FileNotFoundError:
            out[f] = None
    return out


def orphans(d):
    return sorted(f for f in os.listdir(d) if ".tmp-" in f)


def merl_pair_ok(path):
    """True if the sidecar's CRC-32 and size match the binary (write_merl_binary)."""
    try:
        with open(path, "rb") as f:
            data = f.read()
        with open(path + ".json") as f:
            side = json.load(f)
    except (FileNotFoundError, ValueError):
        return False
    return side.get("binary_crc32") == "%08x" % zlib.crc32(data) and side.get("binary_bytes") == len(data)


def usable(brdf, kind, d):
    if kind.startswith("bake"):
        path = f"{d}/t.exr" if kind == "bake-exr" else f"{d}/t.binary"
        proc = subprocess.run([brdf, "eval", "--lut", path, "--at", "30,30,180"], capture_output=True, timeout=60)
        return proc.returncode == 0
    if kind == "export-blender":
        try:
            with open(f"{d}/m.json") as f:
                json.load(f)
            return os.path.getsize(f"{d}/m.exr") > 0 and os.path.getsize(f"{d}/m.osl") > 0
        except (OSError, ValueError):
            return False
    with open(f"{d}/P.inc") as f:
        text = f.read()
    return text.rstrip().endswith("#end")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--brdf", required=True)
    parser.add_argument("--runs", type=int, default=60)
    parser.add_argument("--concurrent", type=int, default=12)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    root = tempfile.mkdtemp(prefix="brdf-sweep-")
    table = {}  # (kind, signal) -> counters
    failures = []
    try:
        durations = {}
        dirs = {}
        for kind in kinds(args.brdf, "").keys():
            d = os.path.join(root, kind)
            os.mkdir(d)
            dirs[kind] = d
            command, _ = kinds(args.brdf, d)[kind]
            start = time.monotonic()
            subprocess.run(command("0.1"), check=True, capture_output=True, timeout=300)
            durations[kind] = time.monotonic() - start
        for run in range(args.runs):
            kind = rng.choice(sorted(dirs))
            signum = rng.choice([signal.SIGINT, signal.SIGTERM, signal.SIGKILL])
            d = dirs[kind]
            command, files = kinds(args.brdf, d)[kind]
            before = snapshot(d, files)
            proc = subprocess.Popen(command(rng.choice(["0.05", "0.1", "0.2"])), stdout=subprocess.DEVNULL,
                                    stderr=subprocess.PIPE, preexec_fn=default_signals)
            time.sleep(rng.uniform(0.0, 1.2 * durations[kind]))
            proc.send_signal(signum)
            _, err = proc.communicate(timeout=300)
            err = err.decode(errors="replace")
            name = signal.Signals(signum).name
            c = table.setdefault((kind, name), {"runs": 0, "killed": 0, "finished": 0, "orphans": 0, "changed": 0,
                                                "unusable": 0, "mismatched": 0})
            c["runs"] += 1
            left = orphans(d)
            c["orphans"] += len(left)
            after = snapshot(d, files)
            if proc.returncode == 0:
                c["finished"] += 1
            else:
                c["killed"] += 1
                # -signum: killed before brdf's main() took the signals (process start-up, nothing
                # written yet; a shell reports it as 128 + signum all the same).
                expected = {signal.SIGINT: 130, signal.SIGTERM: 143, signal.SIGKILL: -9}[signum]
                if proc.returncode not in (expected, -signum):
                    failures.append(f"run {run} {kind} {name}: exit {proc.returncode}, expected {expected}: {err.strip()}")
                if signum != signal.SIGKILL and after != before and "already complete" not in err:
                    c["changed"] += 1
            if signum != signal.SIGKILL and left:
                failures.append(f"run {run} {kind} {name}: orphans {left}")
            if kind == "bake-merl" and not merl_pair_ok(f"{d}/t.binary"):
                c["mismatched"] += 1
            if not usable(args.brdf, kind, d):
                c["unusable"] += 1
            if signum == signal.SIGKILL and left:
                # The next complete write to the same target removes a dead process's temporaries.
                subprocess.run(command("0.1"), check=True, capture_output=True, timeout=300)
                if orphans(d):
                    failures.append(f"run {run} {kind}: stale temporaries not removed by the next write: {orphans(d)}")

        # Concurrent MERL bakes to one path (different surfaces), one sometimes killed.
        d = os.path.join(root, "concurrent")
        os.mkdir(d)
        concurrent = {"rounds": 0, "killed": 0, "mismatched": 0, "unusable": 0, "orphans": 0}
        for _ in range(args.concurrent):
            path = f"{d}/c.binary"
            procs = [subprocess.Popen([args.brdf, "bake"] + SURFACE + ["--sigma-s", s, "--error-samples", "2000",
                                                                       "-o", path],
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                      preexec_fn=default_signals) for s in ["0.05", "0.2"]]
            if rng.random() < 0.5:
                time.sleep(rng.uniform(0.0, 1.2 * durations["bake-merl"]))
                victim = rng.choice(procs)
                victim.send_signal(rng.choice([signal.SIGINT, signal.SIGTERM, signal.SIGKILL]))
                concurrent["killed"] += 1
            for p in procs:
                p.wait(timeout=300)
            concurrent["rounds"] += 1
            concurrent["orphans"] += len(orphans(d))
            for f in orphans(d):  # only a SIGKILL can leave them; clear for the next round
                os.unlink(os.path.join(d, f))
            if os.path.exists(path):
                concurrent["mismatched"] += 0 if merl_pair_ok(path) else 1
                proc = subprocess.run([args.brdf, "eval", "--lut", path, "--at", "30,30,180"], capture_output=True,
                                      timeout=60)
                concurrent["unusable"] += proc.returncode != 0
    finally:
        shutil.rmtree(root, ignore_errors=True)

    print("kind,signal,runs,killed,finished_first,orphan_temporaries,final_changed,unusable_after,mismatched_merl_pairs")
    for (kind, name), c in sorted(table.items()):
        print(f"{kind},{name},{c['runs']},{c['killed']},{c['finished']},{c['orphans']},{c['changed']},{c['unusable']},"
              f"{c['mismatched']}")
    print(f"concurrent-merl,mixed,{concurrent['rounds']},{concurrent['killed']},,{concurrent['orphans']},,"
          f"{concurrent['unusable']},{concurrent['mismatched']}")
    graceful_bad = sum(c["orphans"] + c["changed"] for (k, n), c in table.items() if n != "SIGKILL")
    mismatched = sum(c["mismatched"] for (k, n), c in table.items() if n != "SIGKILL") + concurrent["mismatched"]
    for f in failures:
        print("FAIL:", f, file=sys.stderr)
    return 1 if graceful_bad or mismatched or failures else 0


if __name__ == "__main__":
    sys.exit(main())
