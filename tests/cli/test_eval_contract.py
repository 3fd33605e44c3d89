#!/usr/bin/python3
"""The `brdf eval` contract other tools rely on (env BRDF_EXE = the brdf executable).

  brdf eval --model NAME [surface params] (--at TI,TS,PHIS ... | --queries FILE|-)

stdout: CSV with header `theta_i,theta_s,phi_s,value`, one row per query in input order, every
number in the fewest digits that read back as the same double. The README's `brdf eval` example is
run and its output compared with what it documents (values to 1e-12).
Bad input: exit status 2, nothing on stdout, exactly one line on stderr naming the parameter.
Values that can be checked independently (Fresnel at normal incidence, g, eta_r^2, S, R_spec)
are recomputed here from the paper's formulas.
"""
import math
import os
import re
import subprocess
import sys
import tempfile
import unittest

BRDF = os.environ.get("BRDF_EXE")

SURFACE = ["--sigma-s", "0.05", "--lc", "1.2", "--wavelength", "0.55", "--n", "1.5", "--k", "0.5"]
# Every model the conventions define (docs/conventions.md; models.h).
MODELS = ["fresnel", "q", "q-ss", "q-sp", "q-ps", "q-pp", "s", "rd", "g", "eta-r2", "asf", "k", "r-spec",
          "mbk", "mbk-polished", "mbk-rough", "mbk-fg", "bk", "bk-modified", "microfacet"]
HEADER = "theta_i,theta_s,phi_s,value"


def run(args, stdin=None):
    proc = subprocess.run([BRDF, "eval"] + args, input=stdin, capture_output=True, text=True, timeout=120)
    return proc.returncode, proc.stdout, proc.stderr


def parse_csv(text):
    lines = text.splitlines()
    rows = [[float(x) for x in line.split(",")] for line in lines[1:]]
    return lines, rows


README = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "README.md")


class EvalOutput(unittest.TestCase):
    def test_readme_example_output_is_what_eval_prints(self):
        with open(README) as f:
            text = f.read()
        match = re.search(r"```\n\$ brdf eval ([^\n]*)\n(.*?)```", text, re.S)
        self.assertIsNotNone(match, "the README's `$ brdf eval` example")
        rc, out, err = run(match.group(1).split())
        self.assertEqual(rc, 0, err)
        printed, documented = out.splitlines(), match.group(2).splitlines()
        self.assertEqual(printed[0], documented[0])
        self.assertEqual(len(printed), len(documented))
        # Angles as written; values to 1e-12 relative, so that another SIMD target's last bits
        # (Highway picks one at run time) do not fail the documentation.
        for got, want in zip(printed[1:], documented[1:]):
            got, want = got.split(","), want.split(",")
            self.assertEqual(got[:3], want[:3])
            self.assertLessEqual(abs(float(got[3]) - float(want[3])), 1e-12 * abs(float(want[3])), (got, want))


    def test_header_and_one_row_per_repeated_at_in_order(self):
        queries = ["30,30,180", "10,20,0", "45,60,90", "0,0,0"]
        args = ["--model", "mbk"] + SURFACE
        for q in queries:
            args += ["--at", q]
        rc, out, err = run(args)
        self.assertEqual(rc, 0, err)
        lines, rows = parse_csv(out)
        self.assertEqual(lines[0], HEADER)
        self.assertEqual(len(rows), len(queries))
        for q, row in zip(queries, rows):
            self.assertEqual(row[:3], [float(x) for x in q.split(",")])
            self.assertTrue(math.isfinite(row[3]) and row[3] >= 0.0, row)

    def test_every_number_is_its_shortest_round_trip(self):
        rc, out, err = run(["--model", "mbk"] + SURFACE + ["--at", "33.3,21.7,171.1", "--at", "10,10,180", "--at", "0.1,85,0"])
        self.assertEqual(rc, 0, err)
        lines, _ = parse_csv(out)
        self.assertEqual(lines[1].split(",")[:3], ["33.3", "21.7", "171.1"])  # the angles as given
        for line in lines[1:]:
            for field in line.split(","):
                x = float(field)
                # Its significant digits (no sign, point, exponent or padding zeros) read back as x,
                # and one digit fewer does not: the shortest exact form.
                digits = re.sub(r"e.*$", "", field).replace(".", "").replace("-", "").strip("0") or "0"
                n = len(digits)
                self.assertEqual(float("%.*e" % (n - 1, x)), x, field)
                if n > 1:
                    self.assertNotEqual(float("%.*e" % (n - 2, x)), x, field)

    def test_queries_file_with_header_equals_at(self):
        queries = ["30,30,180", "10,20,0", "45,60,90"]
        rc, reference, err = run(["--model", "bk-modified"] + SURFACE + sum((["--at", q] for q in queries), []))
        self.assertEqual(rc, 0, err)
        with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
            f.write("theta_i,theta_s,phi_s\n" + "\n".join(queries) + "\n")
            path = f.name
        try:
            rc, out, err = run(["--model", "bk-modified"] + SURFACE + ["--queries", path])
            self.assertEqual(rc, 0, err)
            self.assertEqual(out, reference)
        finally:
            os.unlink(path)
        # From stdin, with and without the header line.
        for text in ["theta_i,theta_s,phi_s\n" + "\n".join(queries) + "\n", "\n".join(queries) + "\n"]:
            rc, out, err = run(["--model", "bk-modified"] + SURFACE + ["--queries", "-"], stdin=text)
            self.assertEqual(rc, 0, err)
            self.assertEqual(out, reference)

    def test_csv_utf8_from_a_spreadsheet_byte_order_mark_and_crlf(self):
        """"CSV UTF-8" as spreadsheets save it: a UTF-8 byte-order mark, CRLF line ends; with and
        without the header line, the same rows as --at."""
        queries = ["30,30,180", "10,20,0", "45,60,90"]
        rc, reference, err = run(["--model", "bk-modified"] + SURFACE + sum((["--at", q] for q in queries), []))
        self.assertEqual(rc, 0, err)
        for header in [b"theta_i,theta_s,phi_s\r\n", b""]:
            data = b"\xef\xbb\xbf" + header + b"\r\n".join(q.encode() for q in queries) + b"\r\n"
            with tempfile.TemporaryDirectory() as d:
                path = os.path.join(d, "queries.csv")
                with open(path, "wb") as f:
                    f.write(data)
                rc, out, err = run(["--model", "bk-modified"] + SURFACE + ["--queries", path])
            self.assertEqual(rc, 0, f"{data!r}: {err}")
            self.assertEqual(out, reference, data)

    def test_every_model_name_is_accepted(self):
        # The list the CLI reports for an unknown name holds every documented one (and the models
        # added to the registry since: each is evaluated here too).
        rc, _, err = run(["--model", "no-such-model", "--at", "10,10,180"])
        self.assertEqual(rc, 2)
        listed = re.search(r"one of: ([^)]*)\)", err).group(1).split(", ")
        self.assertLessEqual(set(MODELS), set(listed))
        self.assertEqual(len(listed), len(set(listed)))
        for model in listed:
            rc, out, err = run(["--model", model] + SURFACE + ["--at", "30,30,180", "--at", "20,50,90", "--at", "80,89.5,0"])
            self.assertEqual(rc, 0, model + ": " + err)
            _, rows = parse_csv(out)
            self.assertEqual(len(rows), 3, model)
            for row in rows:
                self.assertTrue(math.isfinite(row[3]) and row[3] >= 0.0, (model, row))


class EvalValues(unittest.TestCase):
    """Values recomputed here from the paper's formulas (degrees in, radians inside)."""

    def values(self, model, queries, extra=()):
        args = ["--model", model] + SURFACE + list(extra)
        for q in queries:
            args += ["--at", "%r,%r,%r" % q]
        rc, out, err = run(args)
        self.assertEqual(rc, 0, err)
        return [row[3] for row in parse_csv(out)[1]]

    def test_fresnel_at_normal_incidence(self):
        n, k = 1.5, 0.5
        expected = ((n - 1) ** 2 + k ** 2) / ((n + 1) ** 2 + k ** 2)
        self.assertAlmostEqual(self.values("fresnel", [(0, 0, 180)])[0], expected, delta=1e-14)
        # Qbar = F at specular (conventions.md).
        self.assertAlmostEqual(self.values("q", [(0, 0, 180)])[0], expected, delta=1e-14)

    def test_g_eta_and_s_follow_eqs_10_12_22(self):
        ti, ts, ps = 35.0, 62.0, 140.0
        r = math.radians
        ci, cs = math.cos(r(ti)), math.cos(r(ts))
        g = (2 * math.pi * 0.05 / 0.55) ** 2 * (ci + cs) ** 2
        eta2 = math.sin(r(ti)) ** 2 + math.sin(r(ts)) ** 2 + 2 * math.sin(r(ti)) * math.sin(r(ts)) * math.cos(r(ps))
        cos2d = ci * cs + math.sin(r(ti)) * math.sin(r(ts)) * math.cos(r(ps))
        ch2 = (ci + cs) ** 2 / (2 * (1 + cos2d))
        s = 4 * ci * cs * ch2 ** 2 / (ci + cs) ** 2
        self.assertAlmostEqual(self.values("g", [(ti, ts, ps)])[0] / g, 1.0, delta=1e-13)
        self.assertAlmostEqual(self.values("eta-r2", [(ti, ts, ps)])[0] / eta2, 1.0, delta=1e-13)
        self.assertAlmostEqual(self.values("s", [(ti, ts, ps)])[0] / s, 1.0, delta=1e-13)

    def test_specular_spike_is_fresnel_times_exp_minus_g(self):
        ti = 40.0
        ci = math.cos(math.radians(ti))
        g = (4 * math.pi * 0.05 / 0.55 * ci) ** 2
        expected = self.values("fresnel", [(ti, ti, 180)])[0] * math.exp(-g)
        self.assertAlmostEqual(self.values("r-spec", [(ti, 10, 0)])[0] / expected, 1.0, delta=1e-13)

    def test_bk_modified_is_reciprocal_and_bk_is_not(self):
        a, b = self.values("bk-modified", [(10, 60, 180), (60, 10, 180)])
        self.assertAlmostEqual(a / b, 1.0, delta=1e-12)
        a, b = self.values("bk", [(10, 60, 180), (60, 10, 180)])
        self.assertAlmostEqual(a / b, (math.cos(math.radians(60)) / math.cos(math.radians(10))) ** 2, delta=1e-12)

    def test_k_is_at_least_one_in_plane_mode(self):
        for k in self.values("k", [(0.0, 0, 0), (45.0, 0, 0), (85.0, 0, 0)]):
            self.assertGreaterEqual(k, 1.0)

    def test_asf_methods_agree_within_the_tolerance(self):
        # auto (the kernel table, certified 1e-6) and the series alone: both within 1e-6 of the
        # converged series, so within 2e-6 of each other; and they are different methods.
        points = [(10, 12, 180), (30, 50, 20), (60, 70, 170), (80, 5, 90), (45, 45, 0)]
        auto = self.values("asf", points)
        series = self.values("asf", points, extra=["--asf-method", "series"])
        for a, b in zip(auto, series):
            self.assertAlmostEqual(a / b, 1.0, delta=2e-6)
        self.assertTrue(any(a != b for a, b in zip(auto, series)), "--asf-method series must not use the table")

    def test_timing_goes_to_stderr_and_leaves_stdout_alone(self):
        args = ["--model", "mbk"] + SURFACE + ["--at", "10,12,180", "--at", "30,50,20"]
        rc, timed, err = run(args + ["--timing"])
        self.assertEqual(rc, 0, err)
        self.assertEqual(timed, run(args)[1])
        self.assertRegex(err, r"^brdf eval: set-up [0-9.e+-]+ s CPU; 2 evaluations [0-9.e+-]+ s CPU \([0-9.e+-]+ ns each\)\n$")


class EvalErrors(unittest.TestCase):
    """Exit status 2, empty stdout, one stderr line naming the parameter."""

    def expect_error(self, args, parameter_pattern, stdin=None):
        rc, out, err = run(args, stdin=stdin)
        self.assertEqual(rc, 2, "exit status for %s: %d (stderr %r)" % (args, rc, err))
        self.assertEqual(out, "", "partial output on error: %r" % out)
        lines = err.strip("\n").split("\n")
        self.assertEqual(len(lines), 1, "stderr must be one line: %r" % err)
        self.assertRegex(lines[0], parameter_pattern)
        return lines[0]

    def test_unknown_model(self):
        self.expect_error(["--model", "mbk-smooth"] + SURFACE + ["--at", "10,10,180"], r"\bmodel\b.*mbk-smooth")

    def test_missing_parameters(self):
        self.expect_error(["--model", "mbk", "--lc", "1", "--n", "1.5", "--at", "10,10,180"], r"sigma[_-]s")
        self.expect_error(["--model", "mbk", "--sigma-s", "0.1", "--n", "1.5", "--at", "10,10,180"], r"\blc\b")
        self.expect_error(["--model", "bk", "--sigma-s", "0.1", "--lc", "1", "--at", "10,10,180"], r"\bn\b")
        self.expect_error(["--model", "mbk"] + SURFACE, r"\bat\b|queries")  # no queries at all

    def test_angles_at_or_beyond_90_degrees(self):
        self.expect_error(["--model", "mbk"] + SURFACE + ["--at", "90,10,180"], r"theta_i.*90")
        self.expect_error(["--model", "mbk"] + SURFACE + ["--at", "10,95,180"], r"theta_s.*90")
        self.expect_error(["--model", "fresnel", "--n", "1.5", "--at", "10,10,180", "--at", "89.99999,90,0"], r"theta_s")

    def test_negative_and_nan_values(self):
        base = ["--model", "mbk", "--at", "10,10,180"]
        self.expect_error(base + ["--sigma-s", "-0.1", "--lc", "1", "--n", "1.5"], r"sigma[_-]s")
        self.expect_error(base + ["--sigma-s", "0.1", "--lc", "-1", "--n", "1.5"], r"\blc\b")
        self.expect_error(base + ["--sigma-s", "0.1", "--lc", "0", "--n", "1.5"], r"\blc\b")
        self.expect_error(base + ["--sigma-s", "0.1", "--lc", "1", "--n", "1.5", "--wavelength", "-0.5"], r"wavelength")
        self.expect_error(base + ["--sigma-s", "0.1", "--lc", "1", "--n", "1.5", "--k", "-1"], r"\bk\b")
        self.expect_error(base + ["--sigma-s", "nan", "--lc", "1", "--n", "1.5"], r"sigma[_-]s")
        self.expect_error(base + ["--sigma-s", "0.1", "--lc", "nan", "--n", "1.5"], r"\blc\b")
        self.expect_error(["--model", "mbk"] + SURFACE + ["--at", "nan,10,180"], r"\bat\b")

    def test_malformed_csv_line_names_the_line(self):
        text = "theta_i,theta_s,phi_s\n10,10,180\n20,20,180\n10,x,180\n"
        line = self.expect_error(["--model", "mbk"] + SURFACE + ["--queries", "-"], r"queries", stdin=text)
        self.assertRegex(line, r"line 4\b")
        line = self.expect_error(["--model", "mbk"] + SURFACE + ["--queries", "-"], r"queries", stdin="10,10\n")
        self.assertRegex(line, r"line 1\b")
        # An angle out of range inside a file is reported with its line too.
        line = self.expect_error(["--model", "mbk"] + SURFACE + ["--queries", "-"], r"theta_s", stdin="10,10,180\n10,91,0\n")
        self.assertRegex(line, r"line 2\b")

    def test_byte_order_mark_after_line_1_is_an_error_naming_its_line(self):
        for data, line_number in [(b"10,10,180\r\n\xef\xbb\xbf20,20,180\r\n", 2),
                                  (b"\xef\xbb\xbf\xef\xbb\xbf10,10,180\n", 1),  # a second mark on line 1
                                  (b"theta_i,theta_s,phi_s\n10,10,180\n20,20,180\xef\xbb\xbf\n", 3)]:
            with tempfile.TemporaryDirectory() as d:
                path = os.path.join(d, "queries.csv")
                with open(path, "wb") as f:
                    f.write(data)
                line = self.expect_error(["--model", "mbk"] + SURFACE + ["--queries", path], r"queries")
            self.assertRegex(line, r"line %d\b" % line_number, data)

    def test_unknown_asf_method(self):
        self.expect_error(["--model", "asf"] + SURFACE + ["--asf-method", "table", "--at", "10,10,180"], r"asf-method.*auto\|series")

    def test_unreadable_queries_file(self):
        self.expect_error(["--model", "mbk"] + SURFACE + ["--queries", "/nonexistent/q.csv"], r"queries")


if __name__ == "__main__":
    if not BRDF or not os.access(BRDF, os.X_OK):
        sys.exit("BRDF_EXE must name the brdf executable (got %r)" % BRDF)
    unittest.main(verbosity=2)
