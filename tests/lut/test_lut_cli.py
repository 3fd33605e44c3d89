#!/usr/bin/python3
"""`brdf bake`, `brdf eval --lut` and `brdf bench` from the outside (env BRDF_EXE = brdf).

  brdf bake --model NAME [surface] [--wavelength a,b,c] --layout rusinkiewicz|merl|slice|kernel
            [--resolution A,B,C | --target-error REL] [--light-dir --view-dir] [--scene S] -o OUT
  brdf eval --lut FILE [--channel I] (--at ... | --queries ...)

The OpenEXR layout and the MERL binary are read here with the test's own code, written from the
documented layouts (libbrdf/lut.h, the EXR header, and the MERL reference reader's layout: three
int32 dims, then 3 x 90 x 90 x 180 doubles, red/green/blue, index = phi_d + 180 theta_d +
16200 theta_h, scales 1/1500, 1.15/1500, 1.66/1500), not with libbrdf's readers.
"""
import math
import os
import random
import re
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np
import OpenImageIO as oiio

BRDF = os.environ.get("BRDF_EXE")
GOLD = ["--model", "mbk", "--material", "Au", "--sigma-s", "0.1", "--lc", "2"]
WAVELENGTHS = [0.65, 0.55, 0.45]  # bake's default channels


def run(args, timeout=300):
    proc = subprocess.run([BRDF] + args, capture_output=True, text=True, timeout=timeout)
    return proc.returncode, proc.stdout, proc.stderr


def claimed_error(stdout):
    m = re.search(r"max relative ([0-9.eE+-]+), rms relative ([0-9.eE+-]+).*floor ([0-9.eE+-]+) 1/sr", stdout)
    assert m, stdout
    return float(m.group(1)), float(m.group(3))


def half_diff_to_angles(theta_h, theta_d, phi_d):
    """(theta_i, theta_s, phi_s) in degrees of a half/difference triple (phi_h = 0): the incident
    direction is R_y(theta_h) applied to the difference vector, the scattered one its mirror about h."""
    d = np.array([math.sin(theta_d) * math.cos(phi_d), math.sin(theta_d) * math.sin(phi_d), math.cos(theta_d)])
    c, s = math.cos(theta_h), math.sin(theta_h)
    wi = np.array([c * d[0] + s * d[2], d[1], -s * d[0] + c * d[2]])
    h = np.array([s, 0.0, c])
    wo = 2.0 * np.dot(wi, h) * h - wi
    ti = math.degrees(math.acos(min(1.0, wi[2])))
    ts = math.degrees(math.acos(min(1.0, wo[2])))
    ps = math.degrees(math.atan2(wo[1], wo[0]) - math.atan2(wi[1], wi[0]))
    return ti, ts, ps


def eval_model(angles, wavelength, extra=GOLD):
    text = "\n".join("%.17g,%.17g,%.17g" % a for a in angles) + "\n"
    with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
        f.write(text)
    try:
        rc, out, err = run(["eval"] + extra + ["--wavelength", str(wavelength), "--queries", f.name])
    finally:
        os.unlink(f.name)
    assert rc == 0, err
    return np.array([float(line.split(",")[3]) for line in out.splitlines()[1:]])


def eval_lut(path, angles, channel):
    text = "\n".join("%.17g,%.17g,%.17g" % a for a in angles) + "\n"
    with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
        f.write(text)
    try:
        rc, out, err = run(["eval", "--lut", path, "--channel", str(channel), "--queries", f.name])
    finally:
        os.unlink(f.name)
    assert rc == 0, err
    return np.array([float(line.split(",")[3]) for line in out.splitlines()[1:]])


def random_angles(count, limit_deg, seed):
    rng = random.Random(seed)
    out = []
    while len(out) < count:
        u = rng.random()
        ti, ts, ps = half_diff_to_angles(0.5 * math.pi * u * u, 0.5 * math.pi * rng.random(), math.pi * rng.random())
        if ti <= limit_deg and ts <= limit_deg:
            out.append((ti, ts, ps))
    return out


class Bake(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)

    def path(self, name):
        return os.path.join(self.dir.name, name)

    def test_eval_lut_agrees_with_eval_model_within_the_claimed_error(self):
        out_path = self.path("gold.exr")
        rc, out, err = run(["bake"] + GOLD + ["--resolution", "48,48,32", "-o", out_path])
        self.assertEqual(rc, 0, err)
        self.assertEqual(err, "", "no progress bar when stderr is not a terminal")
        claimed, floor = claimed_error(out)
        self.assertLess(claimed, 0.5)
        angles = random_angles(400, 85.0, 1)
        model = eval_model(angles, 0.55)
        table = eval_lut(out_path, angles, 1)
        keep = model >= floor
        self.assertGreater(keep.sum(), 100)
        worst = np.max(np.abs(table[keep] - model[keep]) / model[keep])
        self.assertLessEqual(worst, 1.25 * claimed, "claimed %g" % claimed)

    def check_kernel_table(self, surface, angular, tag, limit=1e-3):
        """Bakes `surface` in the kernel layout with --kernel-angular `angular`; asserts its claimed
        error and, from outside, `eval --lut` against `eval --model` at independent random points
        (theta <= 85 deg, values >= 1e-3 of the largest) within `limit`, and <= 2 MB of nodes for 3
        channels. Returns the worst error seen."""
        out_path = self.path("kernel_%s_%s.exr" % (tag, angular))
        rc, out, err = run(["bake"] + surface + ["--layout", "kernel", "--kernel-angular", angular, "-o", out_path])
        self.assertEqual(rc, 0, err)
        claimed, _ = claimed_error(out)
        self.assertLess(claimed, limit, out)
        spec = oiio.ImageInput.open(out_path).spec()
        self.assertLessEqual(spec.width * spec.height * spec.nchannels * 4, 2_000_000)
        self.assertEqual(spec.getattribute("libbrdf:kernel_angular"), angular)
        angles = random_angles(600, 85.0, 7)
        worst = 0.0
        for channel, wavelength in enumerate(WAVELENGTHS):
            model = eval_model(angles, wavelength, surface)
            table = eval_lut(out_path, angles, channel)
            keep = model >= 1e-3 * model.max()
            self.assertGreater(keep.sum(), 100)
            worst = max(worst, float(np.max(np.abs(table[keep] - model[keep]) / model[keep])))
        self.assertLess(worst, limit, "%s %s" % (tag, angular))
        return worst

    def test_kernel_layout_table_form_is_small_and_accurate_from_polished_to_rough(self):
        """--layout kernel --kernel-angular table (issue 9; what the Blender atlas holds): K F P~ Sigma
        with P~ = Qbar / F on 54^3 nodes, for the renderer issue's surfaces, n = 1.5 + 1i, and a rough
        gold-like metal (n = 0.18 + 3.4i): within 1e-3 (measured <= 1.4e-4 for the first three, 3.7e-4
        for the metal, with the cubic P~ reader), <= 2 MB for 3 channels."""
        for sigma, lc, n, k in [("0.02", "2", "1.5", "1"), ("0.2", "2", "1.5", "1"), ("1.0", "5", "1.5", "1"),
                                ("0.5", "3", "0.18", "3.4")]:
            surface = ["--model", "mbk", "--n", n, "--k", k, "--sigma-s", sigma, "--lc", lc]
            self.check_kernel_table(surface, "table", "%s_%s" % (sigma, n))

    def test_kernel_layout_closed_form_holds_where_the_table_form_cannot(self):
        """--layout kernel (default --kernel-angular closed-form): all of P in closed form at lookup
        (mbk: Stover's Qbar), only K (1D) and Sigma interpolated. Checked on the hard cases of the
        table form: a dielectric with n < 1 (Qbar and F(theta_d) have square-root kinks at the
        critical angle; the table form's error there is ~0.8: asserted to stay above 1e-2, so that this
        test shows why the closed form exists), aluminium (large kappa) at short l_c (table form:
        4.5e-3 at grazing), and polished to rough n = 1.5 + 1i; bk-modified too; mbk-fg (F G/S at
        lookup with the file's sigma_g and G term) polished to rough and a metal with Smith's G, the
        V-groove G and none (its table form: 5.7e-3 polished with Smith's G, steep near grazing,
        asserted to stay above 1e-3; 2e-2-1e-1 with the V-groove G or none). Measured <= 7.5e-5."""
        hard = ["--model", "mbk", "--n", "0.5", "--k", "0", "--sigma-s", "0.1", "--lc", "2"]
        out_path = self.path("kernel_n05_table.exr")
        rc, out, err = run(["bake"] + hard + ["--layout", "kernel", "--kernel-angular", "table", "-o", out_path])
        self.assertEqual(rc, 0, err)
        self.assertGreater(claimed_error(out)[0], 1e-2, "the table form cannot hold the kink at the critical angle")
        fg_polished = ["--model", "mbk-fg", "--n", "1.5", "--k", "1", "--sigma-s", "0.02", "--lc", "2"]
        out_path = self.path("kernel_fg_table.exr")
        rc, out, err = run(["bake"] + fg_polished + ["--layout", "kernel", "--kernel-angular", "table", "-o", out_path])
        self.assertEqual(rc, 0, err)
        self.assertGreater(claimed_error(out)[0], 1e-3, "the table form of mbk-fg misses issue 9's 1e-3 near grazing")
        cases = [(hard, "n0.5"), (["--model", "mbk", "--material", "Al", "--sigma-s", "0.05", "--lc", "1"], "Al"),
                 (["--model", "mbk", "--n", "1.5", "--k", "1", "--sigma-s", "0.02", "--lc", "2"], "polished"),
                 (["--model", "mbk", "--n", "1.5", "--k", "1", "--sigma-s", "1.0", "--lc", "5"], "rough"),
                 (["--model", "bk-modified", "--material", "BK7", "--sigma-s", "0.3", "--lc", "2"], "bk-modified"),
                 (fg_polished, "fg-polished"),
                 (["--model", "mbk-fg", "--n", "1.5", "--k", "1", "--sigma-s", "1.0", "--lc", "5"], "fg-rough"),
                 (["--model", "mbk-fg", "--n", "0.18", "--k", "3.4", "--sigma-s", "0.5", "--lc", "3"], "fg-metal"),
                 (fg_polished + ["--g-term", "vgroove"], "fg-vgroove"),
                 (["--model", "mbk-fg", "--material", "Al", "--sigma-s", "0.05", "--lc", "1", "--g-term", "none"], "fg-none-Al")]
        for surface, tag in cases:
            worst = self.check_kernel_table(surface, "closed-form", tag, limit=1e-4)
            print("kernel closed-form %s: max relative error %.3g" % (tag, worst))

    def test_exr_layout_as_documented(self):
        out_path = self.path("layout.exr")
        n0, n1, n2 = 20, 18, 16
        rc, out, err = run(["bake"] + GOLD + ["--resolution", "%d,%d,%d" % (n0, n1, n2), "-o", out_path])
        self.assertEqual(rc, 0, err)
        inp = oiio.ImageInput.open(out_path)
        spec = inp.spec()
        self.assertEqual((spec.width, spec.height, spec.nchannels), (n2, n0 * n1, 3))
        for key in ["model", "parameters", "wavelengths_um", "layout", "shape", "axes", "texel_convention",
                    "max_relative_error", "rms_relative_error", "error_floor", "version", "storage"]:
            self.assertTrue(spec.getattribute("libbrdf:" + key), key)
        self.assertEqual(spec.getattribute("libbrdf:layout"), "rusinkiewicz")
        self.assertEqual(spec.getattribute("libbrdf:shape"), "%d,%d,%d" % (n0, n1, n2))
        pixels = inp.read_image(0, 0, 0, 3, "float")
        self.assertTrue(inp.seek_subimage(1, 0))
        self.assertEqual((inp.spec().height, inp.spec().nchannels), (2, 3))
        side = inp.read_image(1, 0, 0, 3, "float")
        inp.close()
        # Nodes: theta_h = (pi/2)(i/(N0-1))^2, theta_d = (pi/2) j/(N1-1), phi_d = pi k/(N2-1); pixel (x=k, y=i*N1+j).
        rng = random.Random(4)
        nodes, angles = [], []
        while len(nodes) < 40:
            i, j, k = rng.randrange(n0), rng.randrange(n1), rng.randrange(n2)
            a = half_diff_to_angles(0.5 * math.pi * (i / (n0 - 1)) ** 2, 0.5 * math.pi * j / (n1 - 1), math.pi * k / (n2 - 1))
            if a[0] < 85 and a[1] < 85:
                nodes.append((i, j, k))
                angles.append(a)
        for channel, wavelength in enumerate(WAVELENGTHS):
            model = eval_model(angles, wavelength)
            stored = np.array([pixels[i * n1 + j, k, channel] for i, j, k in nodes])
            np.testing.assert_allclose(stored, model, rtol=1e-6, atol=1e-30)
        # Side tables: row 0 R_spec, row 1 K at theta_i = 90 deg m/(W-1).
        width = side.shape[1]
        m = width // 3
        theta = 90.0 * m / (width - 1)
        r_spec = eval_model([(theta, theta, 180.0)], 0.65, ["--model", "r-spec", "--material", "Au", "--sigma-s", "0.1", "--lc", "2"])
        self.assertAlmostEqual(side[0, m, 0] / r_spec[0], 1.0, places=6)
        k_direct = eval_model([(theta, theta, 180.0)], 0.65, ["--model", "k", "--material", "Au", "--sigma-s", "0.1", "--lc", "2"])
        self.assertAlmostEqual(side[1, m, 0] / k_direct[0], 1.0, places=5)

    def test_merl_binary_read_by_an_independent_reader(self):
        out_path = self.path("gold.binary")
        rc, out, err = run(["bake"] + GOLD + ["--layout", "merl", "-o", out_path])
        self.assertEqual(rc, 0, err)
        with open(out_path, "rb") as f:
            raw = f.read()
        dims = np.frombuffer(raw[:12], dtype="<i4")
        self.assertEqual(list(dims), [90, 90, 180])
        n = 90 * 90 * 180
        self.assertEqual(len(raw), 12 + 3 * n * 8)
        data = np.frombuffer(raw[12:], dtype="<f8").reshape(3, 90, 90, 180)
        scales = [1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0]
        self.assertTrue(np.all(np.isfinite(data)) and np.all(data >= 0.0))
        rng = random.Random(2)
        nodes, angles = [], []
        while len(nodes) < 40:
            i, j, k = rng.randrange(90), rng.randrange(90), rng.randrange(180)
            th, td, pd = 0.5 * math.pi * (i / 90.0) ** 2, 0.5 * math.pi * j / 90.0, math.pi * k / 180.0
            a = half_diff_to_angles(th, td, pd)
            if a[0] < 85 and a[1] < 85:
                # The reference reader floors these angles (plus a hair) back to the same indices.
                self.assertEqual(int(math.sqrt((th + 1e-12) / (0.5 * math.pi) * 90 * 90)), i)
                self.assertEqual(int((td + 1e-12) / (0.5 * math.pi) * 90), j)
                self.assertEqual(int((pd + 1e-12) / math.pi * 180), k)
                nodes.append((i, j, k))
                angles.append(a)
        for channel, wavelength in enumerate(WAVELENGTHS):
            model = eval_model(angles, wavelength)
            stored = np.array([data[channel, i, j, k] * scales[channel] for i, j, k in nodes])
            np.testing.assert_allclose(stored, model, rtol=1e-6, atol=1e-30)
        # Metadata sidecar and eval --lut on the binary.
        self.assertTrue(os.path.exists(out_path + ".json"))
        table = eval_lut(out_path, angles[:5], 0)
        np.testing.assert_allclose(table, [data[0, i, j, k] * scales[0] for i, j, k in nodes[:5]], rtol=1e-5)

    def test_target_error_is_met_and_the_tighter_table_is_larger(self):
        sizes = []
        for target in [1e-2, 1e-3]:
            out_path = self.path("t%g.exr" % target)
            rc, out, err = run(["bake"] + GOLD + ["--wavelength", "0.55", "--layout", "slice", "--light-dir", "0.3,0,1",
                                                  "--view-dir", "-0.5,0.2,1", "--target-error", str(target), "-o", out_path])
            self.assertEqual(rc, 0, err)
            claimed, _ = claimed_error(out)
            self.assertLessEqual(claimed, target)
            self.assertIn("target-error:", err)  # each table of the search is reported
            spec = oiio.ImageInput.open(out_path).spec()
            self.assertLessEqual(float(spec.getattribute("libbrdf:max_relative_error")), target)
            sizes.append(spec.width * spec.height)
        self.assertGreater(sizes[1], sizes[0])

    def test_scene_picks_the_layout(self):
        scene = self.path("scene.json")
        with open(scene, "w") as f:
            f.write('{"lights": [{"type": "sun", "direction": [0.3, 0, 1]}],'
                    ' "camera": {"type": "orthographic", "direction": [-0.5, 0.2, 1]}, "wavelengths_um": [0.55]}')
        out_path = self.path("scene.exr")
        rc, out, err = run(["bake"] + GOLD + ["--scene", scene, "--resolution", "64,32", "-o", out_path])
        self.assertEqual(rc, 0, err)
        self.assertIn("scene: slice", err)
        spec = oiio.ImageInput.open(out_path).spec()
        self.assertEqual(spec.getattribute("libbrdf:layout"), "slice")
        self.assertEqual(spec.nchannels, 1)
        # The slice answers geometries of its scene (cos 2 theta_d = L.V) and refuses others.
        l = np.array([0.3, 0, 1]) / math.sqrt(1.09)
        v = np.array([-0.5, 0.2, 1]) / math.sqrt(1.29)
        n = (l + v) / np.linalg.norm(l + v)
        ti, ts = math.degrees(math.acos(np.dot(n, l))), math.degrees(math.acos(np.dot(n, v)))
        rc, out, err = run(["eval", "--lut", out_path, "--at", "%.17g,%.17g,180" % (ti, ts)])
        self.assertEqual(rc, 0, err)
        rc, out, err = run(["eval", "--lut", out_path, "--at", "10,10,180"])
        self.assertEqual(rc, 2)
        self.assertIn("phi_s", err)
        with open(scene, "w") as f:
            f.write('{"lights": [{"type": "sun", "direction": [0.3, 0, 1]}], "camera": {"type": "perspective", "position": [0, 0, 5]}}')
        rc, out, err = run(["bake"] + GOLD + ["--scene", scene, "--resolution", "8,8,8", "-o", out_path])
        self.assertEqual(rc, 0, err)
        self.assertIn("scene: rusinkiewicz", err)

    def test_sigint_leaves_no_file(self):
        out_path = self.path("big.exr")
        proc = subprocess.Popen([BRDF, "bake"] + GOLD + ["--resolution", "220,220,220", "-o", out_path],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        time.sleep(1.5)
        self.assertIsNone(proc.poll(), "the bake finished before the signal; make it larger")
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=60)
        self.assertEqual(proc.returncode, 130, err)
        self.assertIn("interrupted", err)
        self.assertEqual(os.listdir(self.dir.name), [], "no output and no temporary left")

    def test_bad_input_exits_2_with_one_line_naming_the_parameter(self):
        out_path = self.path("x.exr")
        cases = [
            (["--resolution", "1,8,8"], "resolution"),
            (["--resolution", "8,8"], "resolution"),
            (["--layout", "cube"], "layout"),
            (["--layout", "slice"], "light-dir"),
            (["--layout", "slice", "--light-dir", "0,0,1", "--view-dir", "0,0,0"], "view-dir"),
            (["--target-error", "2"], "target-error"),
            (["--target-error", "1e-2", "--resolution", "8,8,8"], "target-error"),
            (["--layout", "merl", "--target-error", "0.1"], "target-error"),
            (["--tolerance", "2"], "tolerance"),
            (["--wavelength", "0.5,-1"], "wavelength"),
        ]
        for extra, parameter in cases:
            args = ["bake"] + GOLD + extra + ["-o", out_path]
            rc, out, err = run(args)
            self.assertEqual(rc, 2, (extra, err))
            self.assertEqual(len(err.strip().splitlines()), 1, err)
            self.assertIn(parameter, err)
        rc, out, err = run(["bake"] + GOLD + ["-o", self.path("x.png")])
        self.assertEqual(rc, 2)
        self.assertIn("output", err)
        rc, out, err = run(["bake", "--model", "fresnel", "--n", "1.5", "-o", out_path])
        self.assertEqual(rc, 2)
        self.assertIn("model", err)
        rc, out, err = run(["bake"] + GOLD + ["--resolution", "8,8,8", "-o", self.path("x.binary")])
        self.assertEqual(rc, 2)
        self.assertEqual(os.listdir(self.dir.name), [])

    def test_corrupt_truncated_and_foreign_files(self):
        good = self.path("good.exr")
        rc, out, err = run(["bake"] + GOLD + ["--resolution", "16,16,16", "-o", good])
        self.assertEqual(rc, 0, err)
        with open(good, "rb") as f:
            data = f.read()
        files = {"empty.exr": b"", "text.exr": b"not an image\n", "cut10.exr": data[: len(data) // 10],
                 "cut90.exr": data[: len(data) * 9 // 10], "cut.binary": b"\x5a\0\0\0\x5a\0\0\0\xb4\0\0\0" + b"\0" * 800}
        rng = random.Random(9)
        for t in range(6):
            damaged = bytearray(data)
            for _ in range(16):
                damaged[rng.randrange(len(damaged))] ^= 0xA5
            files["damaged%d.exr" % t] = bytes(damaged)
        for name, content in files.items():
            with open(self.path(name), "wb") as f:
                f.write(content)
        foreign = self.path("foreign.exr")
        out = oiio.ImageOutput.create(foreign)
        out.open(foreign, oiio.ImageSpec(4, 4, 3, "float"))
        out.write_image(np.zeros((4, 4, 3), dtype=np.float32))
        out.close()
        names = list(files) + ["foreign.exr", "missing.exr"]
        failures = 0
        for name in names:
            rc, out, err = run(["eval", "--lut", self.path(name), "--at", "10,20,170"])
            if name.startswith("damaged") and rc == 0:
                continue  # damage that OpenEXR's checks do not see and that leaves a finite table
            failures += 1
            self.assertEqual(rc, 2, (name, err))
            self.assertEqual(out, "")
            self.assertEqual(len(err.strip().splitlines()), 1, err)
            self.assertTrue(err.startswith("brdf: error: lut: " + self.path(name)), err)
        self.assertGreaterEqual(failures, len(names) - 6)


class Bench(unittest.TestCase):
    def test_quick_bench_writes_csv_and_plot(self):
        with tempfile.TemporaryDirectory() as d:
            t0 = time.time()
            rc, out, err = run(["bench", "--quick", "--out", d], timeout=240)
            self.assertEqual(rc, 0, err)
            elapsed = time.time() - t0
            self.assertLess(elapsed, 120, "bench --quick took %.0f s" % elapsed)
            with open(os.path.join(d, "bench.csv")) as f:
                lines = f.read().splitlines()
            header = lines[0].split(",")
            rows = [dict(zip(header, line.split(","))) for line in lines[1:]]
            for column in ["kind", "model", "surface", "variant", "evals_per_s", "speed_ratio", "max_rel_error", "rms_rel_error"]:
                self.assertIn(column, header)
            kinds = {r["kind"] for r in rows}
            self.assertTrue({"model", "fast_path", "lut"} <= kinds, kinds)
            for model in ["mbk", "mbk-polished", "mbk-rough", "mbk-fg", "bk", "bk-modified", "microfacet"]:
                self.assertTrue(any(r["model"] == model for r in rows), model)
            for r in rows:
                self.assertTrue(math.isfinite(float(r["evals_per_s"])) and float(r["evals_per_s"]) > 0, r)
                self.assertTrue(math.isfinite(float(r["max_rel_error"])), r)
                if r["variant"] == "reference":
                    self.assertEqual(float(r["max_rel_error"]), 0.0, r)
                    self.assertEqual(float(r["speed_ratio"]), 1.0, r)
            # An interpolated table (one trilinear lookup) is faster than the reference series it
            # replaces (same-run ratio). Not the kernel layout: it still evaluates K, F or Qbar and
            # Sigma per query, about the cost of the polished surface's few-term series.
            lut_ratios = [float(r["speed_ratio"]) for r in rows
                          if r["kind"] == "lut" and r["model"] == "mbk" and r["layout"] != "kernel"]
            self.assertTrue(lut_ratios and min(lut_ratios) > 1.0, lut_ratios)
            png = os.path.join(d, "bench.png")
            self.assertGreater(os.path.getsize(png), 10000)


if __name__ == "__main__":
    if not BRDF:
        sys.exit("BRDF_EXE is not set")
    unittest.main()
