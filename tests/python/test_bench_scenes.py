"""The scene texts that tools/benchmarks/bench_pile.py and bench_pile_family.py build from the
committed pile scenes are valid scenes: each variant kind goes through `stratum check`. The
benchmarks are not run by CI, so without this a scene edit (a table moved into an include, a
new solver parameter) would only show when tools/bench runs (it did: e45d59b). Needs the
stratum executable in STRATUM_EXE (set by CTest)."""
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tools", "benchmarks"))
import bench_pile  # noqa: E402
import bench_pile_family  # noqa: E402

EXE = os.environ.get("STRATUM_EXE", "")


def check(test, text):
    """`stratum check` of `text` written to a temporary folder (as the benchmarks run it)."""
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "scene.toml")
        with open(path, "w") as f:
            f.write(text)
        r = subprocess.run([EXE, "check", path], capture_output=True, text=True,
                           env=dict(os.environ, OMP_NUM_THREADS="1"))
        test.assertEqual(r.returncode, 0, (r.stderr or r.stdout).strip())
        test.assertIn(": ok (", r.stdout)


@unittest.skipUnless(EXE and os.path.exists(EXE), "STRATUM_EXE not set")
class BenchScenes(unittest.TestCase):
    def test_pile_work_precision_variants(self):
        # (scene, solver, update or integrator): the kinds bench_pile.py's work-precision runs.
        for name, solver, update in [("hypoelastic", "newton", "explicit"),
                                     ("hypoelastic", "newton", "incremental"),
                                     ("hypoelastic", "newton", "recovery"),
                                     ("hypoelastic", "modified_newton", "explicit"),
                                     ("hypoelastic", "kinsol", "explicit"),
                                     ("cap", "newton", None),
                                     ("cap", "newton", "sandler_rubin"),
                                     ("cap", "modified_newton", None),
                                     ("cap", "kinsol", None)]:
            with self.subTest(scene=name, solver=solver, update=update):
                text = bench_pile.scene_text(name, 4, bench_pile.QOI[name], solver, update, "1e-5", vtk=False)
                self.assertIn("steps = 4\n", text)
                check(self, text)

    def test_pile_profile_variant(self):
        check(self, bench_pile.scene_text("hypoelastic", 24, 60.0))

    def test_family_variants(self):
        for disp in (True, False):
            for kw in [{}, {"linear_solver": "umfpack"}, {"rtol": "7e-6"}, {"line_search": 1},
                       {"steps": 230}]:
                with self.subTest(displacement_test=disp, **kw):
                    text = bench_pile_family.variant(displacement_test=disp, **kw)
                    self.assertEqual("displacement_test = true" in text, disp)
                    check(self, text)


if __name__ == "__main__":
    unittest.main()
