#!/usr/bin/python3
"""Hostile input (issue 11): the exact reproducers of the issue, each with the behaviour it must keep.

  no hang         extreme-but-valid surfaces finish in bounded time (timeouts below)
  no NaN / Inf    parameters beyond what a model can mean are range errors: exit 2, one line
                  naming the parameter and its range; nothing reaches stdout
  no silent guess an empty value, an empty list item, a trailing comma, an out-of-range whole
                  number, a CSV first row that is not the header "theta_i,theta_s,phi_s" are errors
  no orphan file  SIGINT / SIGTERM during a bake or an export: exit 130 / 143, no final file
                  changed, no temporary; a MERL binary and its sidecar are one unit (CRC-32)
  bounded         --error-samples, pixel counts claimed by an EXR header, CSV line length
  energy          `brdf albedo` (directional albedo, specular spike included)
env BRDF_EXE = the brdf executable.
"""
import math
import os
import random
import resource
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import unittest

BRDF = os.environ.get("BRDF_EXE")
GOLD = ["--material", "Au", "--wavelength", "0.55"]
ROUGH = GOLD + ["--sigma-s", "0.1", "--lc", "2"]


def run(args, timeout=30, stdin=None):
    start = time.monotonic()
    proc = subprocess.run([BRDF] + args, input=stdin, capture_output=True, timeout=timeout)
    return proc.returncode, proc.stdout.decode("latin-1"), proc.stderr.decode("latin-1"), time.monotonic() - start


def values(stdout):
    return [float(line.split(",")[-1]) for line in stdout.splitlines()[1:]]


class Case(unittest.TestCase):
    def assert_usage_error(self, args, names, timeout=30, stdin=None):
        """Exit 2, nothing on stdout, one short printable line on stderr containing every name."""
        rc, out, err, _ = run(args, timeout, stdin)
        self.assertEqual(rc, 2, f"{args}: rc {rc}, stderr {err[:300]!r}")
        self.assertEqual(out, "", args)
        self.assertEqual(err.count("\n"), 1, err[:300])
        self.assertLess(len(err), 400, err[:300])
        self.assertTrue(all(32 <= ord(c) < 127 for c in err.rstrip("\n")), repr(err[:300]))
        for name in names:
            self.assertIn(name, err, args)
        return err


class NoHang(Case):
    def test_sigma_over_lambda_10000_finishes_with_finite_values(self):
        # g >= 2^31 (sigma_s/lambda ~ 7400) never finished before; 3800 took 17 s.
        for model in ["mbk", "mbk-rough", "mbk-fg", "microfacet", "k"]:
            for sigma in ["5500", "3800"]:
                rc, out, err, took = run(["eval", "--model", model, "--sigma-s", sigma, "--lc", "2"] + GOLD +
                                         ["--at", "30,40,180"], timeout=60)
                self.assertEqual(rc, 0, f"{model} {sigma}: {err}")
                self.assertTrue(all(math.isfinite(v) and v >= 0 for v in values(out)), out)
                self.assertLess(took, 20, f"{model} sigma_s {sigma}: {took:.1f} s")

    def test_tiny_sigma_with_a_narrow_lobe_finishes(self):
        # g ~ 1e-317 (denormal): the K integral looped forever (sigma_s 1e-160) or took minutes.
        for model in ["mbk-rough", "k", "microfacet"]:
            rc, out, err, took = run(["eval", "--model", model, "--sigma-s", "1e-160", "--lc", "5.5e4", "--n", "1.5",
                                      "--wavelength", "0.55", "--at", "30,30,180", "--at", "89,89,0"], timeout=60)
            self.assertEqual(rc, 0, err)
            self.assertTrue(all(math.isfinite(v) for v in values(out)), out)
            self.assertLess(took, 20, f"{model}: {took:.1f} s")

    def test_sigma_or_lc_1e308_is_a_range_error(self):
        for model in ["mbk", "mbk-polished", "bk", "g", "microfacet", "k"]:
            self.assert_usage_error(["eval", "--model", model, "--sigma-s", "1e308", "--lc", "2"] + GOLD +
                                    ["--at", "30,40,180"], ["sigma_s", "1e+15"])
            self.assert_usage_error(["eval", "--model", model, "--sigma-s", "0.1", "--lc", "1e308"] + GOLD +
                                    ["--at", "30,40,180"], ["lc", "1e+06"])


class NoNaN(Case):
    def test_index_beyond_1000_is_a_range_error(self):
        for model in ["fresnel", "q", "r-spec", "mbk", "microfacet"]:
            surface = ["--sigma-s", "0.1", "--lc", "2", "--at", "30,40,180"]
            self.assert_usage_error(["eval", "--model", model, "--n", "1e308"] + surface, ["n", "1000"])
            self.assert_usage_error(["eval", "--model", model, "--n", "1.5", "--k", "1e308"] + surface, ["k", "1000"])

    def test_microfacet_parameters_out_of_range(self):
        base = ["eval", "--model", "microfacet"] + ROUGH + ["--at", "30,30,180"]
        self.assert_usage_error(base + ["--sigma-g", "1e-320"], ["sigma_g", "1e-07"])
        self.assert_usage_error(base + ["--rho-s", "1e308"], ["rho_s", "1000"])
        self.assert_usage_error(base + ["--rho-d", "2"], ["rho_d", "[0, 1]"])

    def test_values_at_the_range_ends_are_finite(self):
        for model in ["mbk", "mbk-polished", "bk", "bk-modified", "microfacet", "fresnel", "r-spec", "g"]:
            for extra in [["--n", "1000", "--k", "1000", "--sigma-s", "0.1", "--lc", "2"],
                          ["--n", "0.001", "--sigma-s", "0.1", "--lc", "2"],
                          ["--n", "1.5", "--sigma-s", "5.5e14", "--lc", "2"],
                          ["--n", "1.5", "--sigma-s", "0.1", "--lc", "5.5e-7"]]:
                rc, out, err, _ = run(["eval", "--model", model, "--wavelength", "0.55"] + extra +
                                      ["--at", "30,40,180", "--at", "0,0,0", "--at", "89,89,180", "--at", "60,10,90"],
                                      timeout=60)
                self.assertEqual(rc, 0, f"{model} {extra}: {err}")
                self.assertTrue(all(math.isfinite(v) for v in values(out)), f"{model} {extra}: {out}")


class NoSilentGuess(Case):
    def test_an_option_the_model_does_not_read_is_an_error(self):
        surface = ["--n", "1.5", "--sigma-s", "0.1", "--lc", "2", "--at", "30,30,180"]
        for model, option, value in [("mbk", "--rho-d", "0.3"), ("mbk", "--rho-s", "1"), ("bk", "--g-term", "vgroove"),
                                     ("asf", "--sigma-g", "0.2"), ("bk-modified", "--sigma-g-mapping", "rough")]:
            self.assert_usage_error(["eval", "--model", model] + surface + [option, value],
                                    [option[2:], "applies only to --model", "microfacet", model])
        self.assert_usage_error(["bake", "--model", "mbk"] + ROUGH + ["--rho-d", "0.5", "-o", "/tmp/never.exr"],
                                ["rho-d", "microfacet"])
        self.assertFalse(os.path.exists("/tmp/never.exr"))
        for model, option, value in [("microfacet", "--rho-d", "0.3"), ("mbk-fg", "--g-term", "vgroove"),
                                     ("mbk-fg", "--sigma-g", "0.2")]:  # the models that read them
            rc, out, err, _ = run(["eval", "--model", model] + surface + [option, value])
            self.assertEqual(rc, 0, f"{model} {option}: {err}")

    def test_empty_values_are_errors(self):
        for option in ["--k", "--tolerance", "--sigma-g", "--rho-s", "--rho-d", "--lc"]:
            self.assert_usage_error(["eval", "--model", "mbk", "--n", "1.5", "--sigma-s", "0.1", "--lc", "2",
                                     option, "", "--at", "30,30,180"], [option, "empty"])
        self.assert_usage_error(["eval", "--lut", "x.exr", "--channel", "", "--at", "30,30,180"], ["--channel", "empty"])
        for option in ["--resolution", "--target-error", "--layout"]:
            self.assert_usage_error(["bake", "--model", "mbk"] + ROUGH + [option, "", "-o", "/tmp/never.exr"],
                                    [option, "empty"])

    def test_empty_list_item_and_trailing_comma(self):
        self.assert_usage_error(["bake", "--model", "mbk", "--material", "Au", "--sigma-s", "0.1", "--lc", "2",
                                 "--wavelength", "0.65,,0.45", "-o", "/tmp/never.exr"], ["wavelength", "empty item"])
        self.assert_usage_error(["eval", "--model", "mbk"] + ROUGH + ["--at", "30,40,180,"], ["at", "30,40,180,"])
        self.assert_usage_error(["eval", "--model", "mbk"] + ROUGH + ["--at", ",30,40,180"], ["at"])

    def test_out_of_range_whole_numbers(self):
        base = ["bake", "--model", "mbk"] + ROUGH + ["-o", "/tmp/never.exr"]
        self.assert_usage_error(base + ["--seed", "-1"], ["seed", "18446744073709551615"])
        self.assert_usage_error(base + ["--seed", "18446744073709551616"], ["seed"])
        self.assert_usage_error(base + ["--error-samples", "2147483647"], ["error-samples", "1000000"])
        self.assert_usage_error(base + ["--error-samples", "1e3"], ["error-samples"])

    def test_first_csv_row_with_letters_is_data_not_a_header(self):
        for row in ["30,40,nan", "inf,40,180", "theta,40,180"]:
            self.assert_usage_error(["eval", "--model", "mbk"] + ROUGH + ["--queries", "-"], ["queries", "line 1"],
                                    stdin=(row + "\n10,10,180\n").encode())
        rc, out, err, _ = run(["eval", "--model", "mbk"] + ROUGH + ["--queries", "-"],
                              stdin=b" theta_i, theta_s, phi_s\n10,10,180\n")
        self.assertEqual((rc, len(values(out))), (0, 1), err)


class UnclearErrors(Case):
    def test_unknown_command_is_named(self):
        self.assert_usage_error(["frobnicate"], ["frobnicate", "eval"])
        self.assert_usage_error(["export", "frobnicate"], ["frobnicate", "blender"])

    def test_queries_from_dev_zero_a_directory_and_a_50_mb_line(self):
        rc, out, err, took = run(["eval", "--model", "mbk"] + ROUGH + ["--queries", "/dev/zero"], timeout=20)
        self.assertEqual(rc, 2, err)
        self.assertIn("longer than 4096", err)
        self.assertLess(took, 5)
        self.assert_usage_error(["eval", "--model", "mbk"] + ROUGH + ["--queries", tempfile.gettempdir()],
                                ["queries", "is a directory"])
        self.assert_usage_error(["eval", "--model", "mbk"] + ROUGH + ["--queries", "-"], ["queries", "line 2"],
                                stdin=b"10,10,180\n" + b"9" * (50 << 20) + b"\n")
        self.assert_usage_error(["eval", "--model", "mbk"] + ROUGH + ["--queries", "-"], ["queries", "\\x1b"],
                                stdin=b"30,\x1b[31m40\x07,180\n")

    def test_missing_output_directory_is_found_before_the_bake(self):
        rc, out, err, took = run(["bake", "--model", "mbk"] + ROUGH + ["-o", "/nonexistent-dir/x.exr"])
        self.assertEqual(rc, 2, err)
        self.assertIn("does not exist", err)
        self.assertLess(took, 2.0)

    def test_control_character_in_output_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            self.assert_usage_error(["export", "blender", "--model", "mbk"] + ROUGH +
                                    ["--mode", "osl", "--output", os.path.join(d, "a\nb.json")], ["--output", "control"])
            self.assertEqual(os.listdir(d), [])


def small_bake(path, extra=(), sigma="0.1", error_samples=2000):
    return [BRDF, "bake", "--model", "mbk", "--material", "Au", "--sigma-s", sigma, "--lc", "2",
            "--error-samples", str(error_samples), "-o", path] + list(extra)


class LutFiles(Case):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp()
        cls.exr = os.path.join(cls.dir, "t.exr")
        cls.merl = os.path.join(cls.dir, "t.binary")
        for path, extra in [(cls.exr, ["--resolution", "16,16,16"]), (cls.merl, [])]:
            proc = subprocess.run(small_bake(path, extra), capture_output=True, text=True, timeout=120)
            assert proc.returncode == 0, proc.stderr

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_negative_value_in_a_merl_binary_is_refused(self):
        bad = os.path.join(self.dir, "neg.binary")
        with open(self.merl, "rb") as f:
            data = bytearray(f.read())
        data[12 + 8 * 1000:12 + 8 * 1001] = struct.pack("<d", -1.0)
        with open(bad, "wb") as f:
            f.write(data)
        self.assert_usage_error(["eval", "--lut", bad, "--at", "30,30,180"], ["lut", "negative"])

    def test_mismatched_merl_pair_is_refused(self):
        other = os.path.join(self.dir, "other.binary")
        proc = subprocess.run(small_bake(other, sigma="0.3"), capture_output=True, text=True, timeout=120)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        shutil.copy(self.merl + ".json", other + ".json")  # the sidecar of another bake
        self.assert_usage_error(["eval", "--lut", other, "--at", "30,30,180"], ["CRC-32 mismatch"])

    def test_exr_header_claiming_20000_squared_pixels_is_refused_early(self):
        with open(self.exr, "rb") as f:
            data = bytearray(f.read())
        key = b"dataWindow\x00box2i\x00" + struct.pack("<i", 16)
        at = data.find(key)
        self.assertGreater(at, 0)
        data[at + len(key) + 8:at + len(key) + 16] = struct.pack("<ii", 19999, 19999)
        bad = os.path.join(self.dir, "huge.exr")
        with open(bad, "wb") as f:
            f.write(data)
        before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
        err = self.assert_usage_error(["eval", "--lut", bad, "--at", "30,30,180"], ["lut"])
        self.assertIn("refused", err)
        self.assertLess(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, max(before, 300_000), "peak RSS (KB)")


class Interrupts(Case):
    def test_sigint_and_sigterm_leave_the_old_file_and_no_temporary(self):
        killed = 0
        with tempfile.TemporaryDirectory() as d:
            for layout, name in [("rusinkiewicz", "t.exr"), ("merl", "t.binary")]:
                target = os.path.join(d, name)
                rng = random.Random(11)
                for signum in [signal.SIGINT, signal.SIGTERM, signal.SIGINT, signal.SIGTERM]:
                    with open(target, "wb") as f:  # an earlier run may have finished and replaced it
                        f.write(b"old")
                    extra = ["--resolution", "48,48,48"] if layout == "rusinkiewicz" else []
                    # Default dispositions in the child: under a background shell SIGINT arrives ignored,
                    # and brdf rightly keeps an ignored signal ignored.
                    # 1e6 error samples (the maximum) keep each run ~1 s long (the nodes alone take ~0.2 s since the
                    # span path), so that signals sent 0.05-1 s in land mid-run: in the bake or the
                    # error measurement, both before the rename.
                    proc = subprocess.Popen(small_bake(target, extra, error_samples=1_000_000), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
                    time.sleep(rng.uniform(0.05, 1.0))
                    proc.send_signal(signum)
                    _, err = proc.communicate(timeout=30)
                    leftovers = [f for f in os.listdir(d) if ".tmp-" in f]
                    self.assertEqual(leftovers, [], f"{signum}: {err!r}")
                    if proc.returncode == 0:
                        continue  # finished before the signal
                    killed += 1
                    self.assertEqual(proc.returncode, 128 + signum, err)
                    with open(target, "rb") as f:
                        content = f.read()
                    if b"already complete" not in err:
                        self.assertEqual(content, b"old", f"{layout} {signum}: final file changed")
        self.assertGreaterEqual(killed, 3, "too few runs were interrupted to test anything")

    def test_blender_export_creates_a_missing_output_directory(self):
        """`export blender --output bl/x.json` creates bl/ (and its parents), as `export povray -o` does."""
        with tempfile.TemporaryDirectory() as d:
            output = os.path.join(d, "bl", "nested", "x.json")
            rc, out, err, _ = run(["export", "blender", "--model", "mbk"] + ROUGH +
                                  ["--mode", "lut", "--resolution", "8,8,8", "--output", output], 120)
            self.assertEqual(rc, 0, err)
            self.assertTrue(os.path.isfile(output), err)
            self.assertTrue(os.path.isfile(os.path.join(d, "bl", "nested", "x.exr")), os.listdir(os.path.dirname(output)))
            # A directory that cannot be created (a file is in the way) is a one-line error naming --output.
            with open(os.path.join(d, "file"), "w"):
                pass
            self.assert_usage_error(["export", "blender", "--model", "mbk"] + ROUGH +
                                    ["--mode", "lut", "--resolution", "8,8,8", "--output", os.path.join(d, "file", "x.json")],
                                    ["output", "directory"])

    def test_failed_blender_export_leaves_no_file(self):
        with tempfile.TemporaryDirectory() as d:
            os.mkdir(os.path.join(d, "m.osl"))  # the OSL cannot replace a directory: the export fails
            rc, out, err, _ = run(["export", "blender", "--model", "mbk"] + ROUGH +
                                  ["--mode", "osl", "--resolution", "8,8,8", "--output", os.path.join(d, "m.json")], 120)
            self.assertNotEqual(rc, 0, err)
            self.assertEqual(sorted(os.listdir(d)), ["m.osl"], err)


class Energy(Case):
    def albedo(self, args):
        rc, out, err, _ = run(["albedo"] + args, timeout=60)
        self.assertEqual(rc, 0, err)
        rows = [list(map(float, line.split(","))) for line in out.splitlines()[1:]]
        return {row[0]: row for row in rows}

    def test_issue_numbers_at_80_degrees(self):
        surface = GOLD + ["--sigma-s", "0.5", "--lc", "2", "--theta-i", "80"]
        self.assertAlmostEqual(self.albedo(["--model", "mbk"] + surface)[80][1], 1.09, delta=0.01)
        self.assertAlmostEqual(self.albedo(["--model", "bk"] + surface)[80][1], 3.83, delta=0.02)

    def test_white_lambertian_and_mirror(self):
        white = self.albedo(["--model", "microfacet"] + ROUGH + ["--rho-s", "0", "--rho-d", "1", "--theta-i", "0,45,85"])
        for row in white.values():
            self.assertAlmostEqual(row[1], 1.0, delta=1e-6)
        mirror = self.albedo(["--model", "mbk", "--material", "Au", "--wavelength", "0.55", "--sigma-s", "0",
                              "--lc", "2", "--theta-i", "45"])[45]
        rc, out, err, _ = run(["eval", "--model", "fresnel"] + GOLD + ["--at", "45,45,180"])
        self.assertAlmostEqual(mirror[1], values(out)[0], delta=1e-12)


if __name__ == "__main__":
    if not BRDF:
        sys.exit("BRDF_EXE is not set")
    unittest.main(verbosity=2)
