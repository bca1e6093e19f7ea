"""Tests of tools/plot_pile.py, tools/plot_calibration.py and of the geometry of tools/plastic_zone_paraview.py (run by CTest
with /usr/bin/python3; plot_pile needs matplotlib, python3-matplotlib in tools/setup.sh). The
ParaView part of plastic_zone_paraview.py is not run here: it needs a ParaView (tools/README.md)."""
import contextlib
import io
import os
import sys
import tempfile
import unittest
from types import SimpleNamespace

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import plastic_zone_paraview as pzp  # noqa: E402
import plot_pile as pp  # noqa: E402
import plot_calibration as pc  # noqa: E402
import plot_sweep as ps  # noqa: E402

PNGS = ["load_settlement.png", "axial_force.png", "shaft_traction.png", "shaft_normal_traction.png",
        "shaft_slip.png"]


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def small_run(d, units=("kN", "mm", "m", "kPa"), diagnostics_last="1", log=None):
    """A pile run's output folder with three load levels (15, 30, 74.3066) and a toe level that
    has two different rows in shaft_traction.csv; returns its curves folder."""
    F, s, L, p = units
    curves = os.path.join(d, "curves")
    os.makedirs(curves)
    loads = [0.0, 15.0, 30.0, 74.3066]
    write(os.path.join(curves, "load_settlement.csv"),
          f"load_{F},settlement_{s}\n" + "".join(f"{P},{0.2 * P + 0.001 * P * P}\n" for P in loads))
    depths = [0.0, 1.0, 2.0, 3.0]
    write(os.path.join(curves, "axial_force.csv"), f"load_{F},depth_{L},axial_force_{F}\n" +
          "".join(f"{P},{z},{P * (1 - z / 6)}\n" for P in loads for z in depths))
    rows = []
    for P in loads:
        for z in depths:
            rows.append(f"{P},{z},{0.3 * P},{-10 - 20 * z},{0.01 * P},{'slip' if P > 50 and z < 1 else 'stick'}\n")
        rows.append(f"{P},3.0,{0.001 * P},{-1000.0},0,stick\n")  # the base's corner point at the toe
    write(os.path.join(curves, "shaft_traction.csv"),
          f"load_{F},depth_{L},shear_traction_{p},normal_traction_{p},slip_{s},status\n" + "".join(rows))
    write(os.path.join(d, "diagnostics.csv"),
          "stage,step,accepted,lambda_n,lambda,iterations,message\n"
          "4,1,1,0,0.1,3,\"\"\n"
          f"4,2,{diagnostics_last},0.1,0.105,8,\"Newton not converging: |R| = 0.4, above 0.5 x\"\n")
    if log is not None:
        write(os.path.join(d, "run.txt"), log)
    return curves


class Labels(unittest.TestCase):
    def test_loads_to_three_digits_without_exponent(self):
        for v, text in ((74.3066, "74.3"), (73.75, "73.8"), (15.0, "15"), (150.0, "150"), (15000.0, "15000"),
                        (0.625, "0.625"), (0.0, "0"), (1.5e-3, "0.0015")):
            self.assertEqual(pp.short(v), text)


class StopReason(unittest.TestCase):
    def test_from_the_printout(self):
        log = "done: 124 steps\nstopped: the settlement limit of the stage is exceeded\n"
        self.assertEqual(pp.reason_from_log(log), "the settlement limit of the stage is exceeded")
        self.assertEqual(pp.reason_from_log(
            "stopped: collapse: a load step found no equilibrium after its cut-backs, and the structure had lost"),
            "collapse: a load step found no equilibrium after its cut-backs")
        self.assertEqual(pp.reason_from_log(
            "stopped: numerical failure: a load step did not converge after its cut-backs although the structure"),
            "numerical failure: a load step did not converge after its cut-backs")
        self.assertEqual(pp.reason_from_log("done: 12 steps\n"), "full load reached")
        self.assertIsNone(pp.reason_from_log("progress: stage 1/4\n"))

    def test_from_diagnostics(self):
        self.assertEqual(pp.reason_from_diagnostics([{"accepted": 1.0, "lambda": 1.0, "message": ""}]),
                         "full load reached")
        self.assertIn("stop limit", pp.reason_from_diagnostics([{"accepted": 1.0, "lambda": 0.49, "message": ""}]))
        self.assertEqual(pp.reason_from_diagnostics([{"accepted": 1.0, "lambda": 0.5, "message": ""},
                                                     {"accepted": 0.0, "lambda": 0.51,
                                                      "message": "Newton not converging: |R| = 0.4"}]),
                         "a load step failed after its cut-backs (Newton not converging)")


class PlotPile(unittest.TestCase):
    def test_all_pngs_the_stop_mark_and_short_loads(self):
        with tempfile.TemporaryDirectory() as d:
            texts = pp.main([small_run(d, diagnostics_last="0")])
            self.assertEqual(sorted(texts), sorted(PNGS))
            for name in PNGS:
                self.assertGreater(os.path.getsize(os.path.join(d, "curves", name)), 5000, name)
            mark = [t for t in texts["load_settlement.png"] if t.startswith("last converged point")]
            self.assertEqual(len(mark), 1)
            s_last = 0.2 * 74.3066 + 0.001 * 74.3066 ** 2  # 20.38 mm
            self.assertIn(f"74.3 kN, {pp.short(s_last)} mm", mark[0])
            self.assertIn("run ended: a load step failed after its cut-backs (Newton not converging)", mark[0])
            for name in PNGS[1:]:
                self.assertIn("74.3 kN (last converged)", texts[name], name)
                self.assertIn("15 kN", texts[name], name)
                self.assertFalse(any("74.3066" in t for t in texts[name]), name)
            self.assertIn("interface slipping", texts["shaft_slip.png"])

    def test_the_printout_wins_and_units_come_from_the_headers(self):
        with tempfile.TemporaryDirectory() as d:
            curves = small_run(d, units=("N", "mm", "mm", "kN_per_m2"),
                               log="done: 3 steps\nstopped: the settlement limit of the stage is exceeded\n")
            texts = pp.main([curves])
            mark = [t for t in texts["load_settlement.png"] if t.startswith("last converged point")][0]
            self.assertIn("74.3 N", mark)
            self.assertIn("run ended: the settlement limit of the stage is exceeded", mark)

    def test_a_depth_with_two_different_rows_is_left_out(self):
        rows = [{"d": 2.0, "v": 1.0}, {"d": 2.0, "v": 1.0}, {"d": 3.0, "v": 2.0}, {"d": 3.0, "v": -1000.0}]
        kept, out = pp.split_ambiguous(rows, "v", "d")
        self.assertEqual(kept, rows[:2])  # equal repeats (a shared node) stay
        self.assertEqual(out, [3.0])


class ParaViewGeometry(unittest.TestCase):
    """The plain-Python part of plastic_zone_paraview.py: what is drawn and where."""

    def test_segment_clipping(self):
        xl, yl = (0.0, 1.0), (-2.0, 0.0)
        self.assertEqual(pzp.clip_segment((0.5, -1.0), (0.6, -1.5), xl, yl), ((0.5, -1.0), (0.6, -1.5)))
        self.assertIsNone(pzp.clip_segment((2.0, -1.0), (3.0, -1.0), xl, yl))
        (a, b) = pzp.clip_segment((-1.0, -1.0), (3.0, -1.0), xl, yl)
        self.assertEqual((a, b), ((0.0, -1.0), (1.0, -1.0)))
        (a, b) = pzp.clip_segment((0.5, 1.0), (0.5, -3.0), xl, yl)
        self.assertEqual((a, b), ((0.5, 0.0), (0.5, -2.0)))

    def test_polygon_clipping_and_edges_once(self):
        square = [(0.0, -3.0), (2.0, -3.0), (2.0, 0.0), (0.0, 0.0)]
        cut = pzp.clip_polygon(square, (0.0, 1.0), (-2.0, 0.0))
        xs, ys = [p[0] for p in cut], [p[1] for p in cut]
        self.assertEqual((min(xs), max(xs), min(ys), max(ys)), (0.0, 1.0, -2.0, 0.0))
        self.assertEqual(pzp.clip_polygon(square, (5.0, 6.0), (-2.0, 0.0)), [])
        # two cells sharing an edge: 7 edges, not 8; the window keeps the edges inside it
        polys = [([0, 1, 1, 0], [0, 0, 1, 1], 0), ([1, 2, 2, 1], [0, 0, 1, 1], 0)]
        self.assertEqual(len(pzp.mesh_edges(polys, (0, 2), (0, 1))), 7)
        edges = pzp.mesh_edges(polys, (0, 1.5), (0, 1))
        self.assertTrue(all(0 <= x <= 1.5 for e in edges for x, _ in e))

    def test_window_around_the_pile_and_overrides(self):
        a = SimpleNamespace(full=False, around=4.0, below=4.0, xlim=None, ylim=None)
        R, toe, top = 0.135, -3.0, 0.0
        xl, yl = pzp.window((0.0, 10.0, -12.0, 0.0), (R, toe, top), a)
        self.assertAlmostEqual(xl[1], R + 4 * 2 * R, places=12)
        self.assertAlmostEqual(yl[0], toe - 4 * 2 * R, places=12)
        self.assertAlmostEqual(yl[1], top + 0.15 * 2 * R, places=12)
        self.assertEqual(xl[0], 0.0)
        a.full = True
        self.assertEqual(pzp.window((0.0, 10.0, -12.0, 0.0), (R, toe, top), a), ((0.0, 10.0), (-12.0, 0.0)))
        a.xlim, a.ylim = [0.0, 2.0], [-5.0, 0.5]
        self.assertEqual(pzp.window((0.0, 10.0, -12.0, 0.0), (R, toe, top), a), ((0.0, 2.0), (-5.0, 0.5)))

    def test_points_in_view_and_their_legend(self):
        legend = [("elastic", "#c9d6e3", "elastic"), ("failed", "#d62728", "regime"), ("yield", "#ff7f0e", "regime"),
                  ("linear elastic (pile)", "#e6e6e6", "linear")]
        labels = ["elastic", "failed", "yield", "linear elastic (pile)", "failed"]
        xs, ys = [0.5, 0.6, 5.0, 0.05, 0.7], [-1.0, -1.0, -1.0, -1.0, -1.5]
        skip = [False, False, False, True, False]
        keep, shown, cat = pzp.in_view(labels, legend, xs, ys, (0.0, 1.0), (-2.0, 0.0), skip)
        self.assertEqual(keep, [0, 1, 4])  # "yield" is outside, the pile's point is the solid
        self.assertEqual(shown, [("elastic", "#c9d6e3", 1), ("failed", "#d62728", 2)])
        self.assertEqual(cat, [0, 1, 1])

    def test_layout_puts_the_window_left_of_the_legend(self):
        xl, yl = (0.0, 1.215), (-5.16, 0.0405)
        size, focal, scale, right = pzp.layout(xl, yl, height=1300, plot_height=1100, left=180, bottom=100,
                                               legend_width=560)
        ppm = 1100 / (yl[1] - yl[0])
        self.assertEqual(size[1], 1300)
        self.assertAlmostEqual(scale, 0.5 * size[1] / ppm, places=9)  # parallel scale: half the view height
        # the window's lower-left corner lands 180 px from the left and 100 px from the bottom
        self.assertAlmostEqual((xl[0] - (focal[0] - 0.5 * size[0] / ppm)) * ppm, 180.0, places=6)
        self.assertAlmostEqual((yl[0] - (focal[1] - scale)) * ppm, 100.0, places=6)
        self.assertAlmostEqual(right * size[0], 180 + (xl[1] - xl[0]) * ppm, places=6)
        self.assertGreaterEqual(size[0] - right * size[0], 560)  # room for the legend beside it


class SweepTables(unittest.TestCase):
    """plot_sweep.py --table: the Markdown tables of docs/validation/loess_pile.md."""

    def test_tornado_table_ranks_by_the_largest_swing_and_says_stopped(self):
        rows = [
            {"index": "0", "varied": "base", "status": "stopped", "a": "1", "b": "2", "s30": "3.0", "P": "80"},
            {"index": "1", "varied": "a:low", "status": "stopped", "a": "0.5", "b": "2", "s30": "3.1", "P": ""},
            {"index": "2", "varied": "a:high", "status": "stopped", "a": "1.5", "b": "2", "s30": "2.95", "P": "81"},
            {"index": "3", "varied": "b:low", "status": "stopped", "a": "1", "b": "1", "s30": "5.0", "P": "70"},
            {"index": "4", "varied": "b:high", "status": "failed", "a": "1", "b": "3", "s30": "", "P": ""},
        ]
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "t.png")
            buf = io.StringIO()
            with contextlib.redirect_stdout(buf):
                ps.tornado(rows, "s30", out, table=["s30", "P"])
            self.assertTrue(os.path.exists(out))
        lines = [l for l in buf.getvalue().splitlines() if l.startswith("|")]
        self.assertEqual(lines[0], "| parameter (low / high) | s30: low / high | P: low / high |")
        self.assertEqual(lines[2], "| base run | 3.00 | 80.00 |")
        # b failed on one side: an infinite swing, so it ranks first
        self.assertEqual(lines[3], "| b (1 / 3) | 5.00 / failed | 70.00 / failed |")
        self.assertEqual(lines[4], "| a (0.5 / 1.5) | 3.10 / 2.95 | stopped before / 81.00 |")

    def test_band_table_quantiles(self):
        rows = [{"status": "stopped", "s@1": str(v), "P": "" if v > 9 else str(10 * v)} for v in range(1, 12)]
        t = ps.band_table(rows, ["s@1", "P"]).splitlines()
        self.assertEqual(t[0], "| quantile | s@1 | P |")
        # type-7 quantiles of 1..11: 1.5, 6, 10.5; P reaches only 9 of 11 samples: no 95 % value
        self.assertEqual(t[2], "| 5 % | 1.50 | 15.00 |")
        self.assertEqual(t[3], "| 50 % | 6.00 | 60.00 |")
        self.assertEqual(t[4], "| 95 % | 10.50 | stopped |")


class PlotCalibration(unittest.TestCase):
    """plot_calibration.py: one panel per data set, the title from parameters.csv."""

    def folder(self, d):
        write(os.path.join(d, "parameters.csv"),
              "name,start,lower,upper,log,value,standard_error,relative_standard_error,ci95_low,ci95_high,"
              "determined,at_bound\n"
              "A,2,0.1,10,true,0.5,inf,inf,-inf,inf,false,false\n"
              "E,6e4,2e3,2e5,true,25118.4,141.3,0.0056,24786.6,25454.7,true,false\n")
        write(os.path.join(d, "residuals.csv"),
              "data,line,x,measured,computed,weight,residual\n"
              "head,5,15,0.27,0.26,1,-0.01\nhead,6,30,0.52,0.51,1,-0.01\n"
              "base,4,15,0.1,0.11,2,0.02\n")
        write(os.path.join(d, "fitted_head.csv"), "load,settlement\n0,0\n15,0.26\n30,0.51\n")
        write(os.path.join(d, "fitted_base.csv"), "load,base_settlement\n0,0\n15,0.11\n")

    def test_title_gives_intervals_and_says_not_determined(self):
        rows = [{"name": "A", "value": "0.5", "determined": "false", "ci95_low": "-inf", "ci95_high": "inf"},
                {"name": "E", "value": "25118.4", "determined": "true", "ci95_low": "24786.6",
                 "ci95_high": "25454.7"}]
        self.assertEqual(pc.title(rows), "A = 0.5 (not determined), E = 2.512e+04 (2.479e+04 to 2.545e+04)")

    def test_one_png_with_a_panel_per_data_set(self):
        with tempfile.TemporaryDirectory() as d:
            self.folder(d)
            self.assertEqual(list(pc.data_sets(pc.read(os.path.join(d, "residuals.csv")))), ["head", "base"])
            with contextlib.redirect_stdout(io.StringIO()):
                pc.main([d])
            self.assertGreater(os.path.getsize(os.path.join(d, "calibration.png")), 10000)

    def test_a_folder_without_results_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            with self.assertRaises(SystemExit) as e:
                pc.main([d])
            self.assertIn("has no residuals.csv", str(e.exception))


if __name__ == "__main__":
    unittest.main()
