"""Tests of tools/field_compare.py (run by CTest with the system python3)."""
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import field_compare as fc  # noqa: E402


class HyperbolicFit(unittest.TestCase):
    def test_exact_hyperbola_recovered(self):
        # P = s / (a + b s) sampled at uneven settlements: the fit returns a and b to 1e-10.
        a, b = 0.0123, 1.0 / 127.0
        s = [0.1, 0.37, 0.9, 2.5, 4.4, 9.6, 21.0]
        p = [x / (a + b * x) for x in s]
        fa, fb = fc.hyperbolic_fit([0.0] + p, [0.0] + s)  # the origin is skipped
        self.assertLess(abs(fa - a) / a, 1e-10)
        self.assertLess(abs(fb - b) / b, 1e-10)

    def test_needs_two_points(self):
        with self.assertRaises(ValueError):
            fc.hyperbolic_fit([0.0, 10.0], [0.0, 1.0])

    def test_interpolation_and_end_of_curve(self):
        loads, s = [0.0, 15.0, 30.0], [0.0, 1.0, 3.0]
        self.assertAlmostEqual(fc.settlement_at(loads, s, 22.5), 2.0, places=14)
        self.assertIsNone(fc.settlement_at(loads, s, 45.0))


class Cli(unittest.TestCase):
    def test_field_file_against_itself(self):
        field = os.path.join(ROOT, "docs", "validation", "field_test.csv")
        loads, mean, _ = fc.read_field(field)
        with tempfile.TemporaryDirectory() as d:
            curve = os.path.join(d, "c.csv")
            with open(curve, "w") as f:
                f.write("load_kN,settlement_mm\n")
                for p, s in zip(loads, mean):
                    f.write(f"{p},{s / 2}\n")  # twice as stiff as the test everywhere
            out = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "field_compare.py"), curve + "=half",
                                  "--field", field], capture_output=True, text=True, check=True).stdout
        self.assertIn("(0.50x)", out)
        # Halving s: (s/2)/P = a/2 + b (s/2), so b and P_ult = 1/b are unchanged.
        self.assertIn("| 1.00 |", out)

    def test_bad_file_is_one_line(self):
        r = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "field_compare.py"), "/nonexistent.csv"],
                           capture_output=True, text=True)
        self.assertEqual(r.returncode, 1)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1)


if __name__ == "__main__":
    unittest.main()
