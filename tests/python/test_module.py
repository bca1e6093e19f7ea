"""Tests of `import stratum` (python/, docs/python.md), run by CTest (python.module) with Debian's
/usr/bin/python3 and pytest, PYTHONPATH at the build tree's python/ folder and STRATUM_EXE the
program: the arrays equal what the program writes, errors carry their place, a run stops on
KeyboardInterrupt with its files written, overrides act as in a study, the point driver and a
calibration give what the command line gives."""
import csv
import os
import signal
import subprocess

import numpy as np
import pytest

import stratum

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
EXE = os.environ.get("STRATUM_EXE", os.path.join(ROOT, "build", "release", "bin", "stratum"))
PILE = os.path.join(ROOT, "inputs", "examples", "elastic_pile.toml")
FOOTING = os.path.join(ROOT, "tests", "scenes", "sweep", "elastic_footing.toml")


def csv_columns(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return {k: [r[k] for r in rows] for k in rows[0]}


def test_the_pile_curve_equals_its_csv_to_the_last_digit(tmp_path):
    r = stratum.run(PILE, out=str(tmp_path / "pile"))
    assert r.summary["status"] == "completed" and r.summary["steps"] == 8
    cols = csv_columns(tmp_path / "pile" / "curves" / "load_settlement.csv")
    assert r.load_settlement.shape == (9, 2)
    # The CSV writes 10 significant digits: the array, printed so, is the same text.
    assert ["%.10g" % v for v in r.load_settlement[:, 0]] == cols["load_kN"]
    assert ["%.10g" % v for v in r.load_settlement[:, 1]] == cols["settlement_mm"]
    res = stratum.read_results(str(tmp_path / "pile"))
    assert np.array_equal(res.curves["load_settlement"]["settlement_mm"],
                          np.array([float(c) for c in cols["settlement_mm"]]))
    assert res.summary["ended"] == "completed"


def test_recorders_equal_their_csv_and_the_series_is_listed(tmp_path):
    r = stratum.run(FOOTING, out=str(tmp_path / "f"))
    cols = csv_columns(tmp_path / "f" / "history" / "footing.csv")
    # The CSV names each column with its unit (plane strain: a reaction per metre of the strip).
    for c, written in (("lambda", "lambda"), ("uy", "uy_m"), ("ry", "ry_kN_per_m")):
        assert ["%.12g" % v for v in r.recorders["footing"][c]] == cols[written]
    # Linear elasticity: the reaction is proportional to the settlement.
    ry, uy = r.recorders["footing"]["ry"][1:], r.recorders["footing"]["uy"][1:]
    assert np.allclose(ry / uy, ry[-1] / uy[-1], rtol=1e-9)
    res = stratum.read_results(str(tmp_path / "f"))
    (name, steps), = [(k, v) for k, v in res.series.items() if not k.endswith("_ip")]
    assert [t for t, _ in steps] == list(r.recorders["footing"]["lambda"])  # one file per step, at its load factor
    assert all(os.path.isfile(p) for _, p in steps)


def test_an_error_in_a_scene_raises_stratum_error_with_line_and_column(tmp_path):
    text = open(PILE).read().replace("nu = 0.3", "nu = 0.7")
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    line = next(i for i, s in enumerate(text.splitlines(), 1) if s.startswith("nu = 0.7"))
    with pytest.raises(stratum.Error) as e:
        stratum.run(str(bad))
    assert (e.value.file, e.value.line, e.value.column) == (str(bad), line, 6)
    assert "nu = 0.7 is outside (-1, 0.5)" in e.value.message
    assert isinstance(e.value, ValueError)
    with pytest.raises(stratum.Error, match="no key 'sol' in \\[materials\\]"):
        stratum.run(PILE, overrides={"materials.sol.E": 1.0})


def test_overrides_act_as_in_a_study():
    base = stratum.run(PILE, write_output=False)
    stiff = stratum.run(PILE, write_output=False,
                        overrides={"materials.soil.E": 40000.0, "materials.concrete.E": 63.0e6})
    # Every modulus doubled: every settlement halves (linear elasticity).
    assert np.allclose(stiff.load_settlement[:, 1], base.load_settlement[:, 1] / 2, rtol=1e-9)
    assert "E = 40000.0" in stratum.scene_text(PILE, overrides={"materials.soil.E": 40000.0})


def test_keyboard_interrupt_stops_the_run_with_its_files_written(tmp_path):
    # The elastic pile in 4000 steps: seconds for the command line to be interrupted in its stage.
    long_pile = {"stages[0].steps": 4000}
    seen = []

    def progress(step, steps, lam):
        seen.append(step)
        if step == 3:
            os.kill(os.getpid(), signal.SIGINT)  # what Ctrl-C does

    with pytest.raises(KeyboardInterrupt):
        stratum.run(PILE, overrides=long_pile, out=str(tmp_path / "py"), progress=progress)
    assert seen == [1, 2, 3]
    res = stratum.read_results(str(tmp_path / "py"))
    assert res.summary["ended"] == "stopped" and res.summary["stop_reason"] == "interrupted"
    assert len(res.curves["load_settlement"]["load_kN"]) == 4  # the start and three steps
    # `stratum run` of the same scene, SIGINT after 1 s: the same files (its curve longer).
    scene = tmp_path / "long_pile.toml"
    scene.write_text(stratum.scene_text(PILE, overrides=long_pile))
    cli = subprocess.run(["timeout", "--preserve-status", "-s", "INT", "1", EXE, "run", str(scene), "--out",
                          str(tmp_path / "cli"), "--quiet"], capture_output=True, text=True)
    assert cli.returncode == 130, cli.stderr
    assert "interrupted by SIGINT" in cli.stderr
    assert sorted(os.listdir(tmp_path / "py")) == sorted(os.listdir(tmp_path / "cli"))
    assert stratum.read_results(str(tmp_path / "cli")).summary["stop_reason"] == "interrupted"


def test_the_point_driver_gives_the_cli_csv(tmp_path):
    path = os.path.join(ROOT, "inputs", "point", "elastic_paths.toml")
    p = stratum.point(path)
    out = tmp_path / "p.csv"
    subprocess.run([EXE, "point", path, "--out", str(out)], check=True, capture_output=True)
    cols = csv_columns(out)
    first_stress = [k for k in cols if k.startswith("sig_xx")][0]
    assert len(cols[first_stress]) == p["stress"].shape[0]
    assert np.allclose(p["stress"][:, 0], [float(v) for v in cols[first_stress]], rtol=1e-9, atol=1e-9)


def test_calibrate_from_python_equals_the_command_line(tmp_path):
    study = os.path.join(ROOT, "tests", "calibrate", "elastic_pile_E.toml")
    r = stratum.calibrate(study, out=str(tmp_path / "py"))
    subprocess.run([EXE, "calibrate", study, "--out", str(tmp_path / "cli")], check=True, capture_output=True)
    with open(tmp_path / "cli" / "parameters.csv") as f:
        row = next(csv.DictReader(f))
    assert "%.10g" % r["parameters"]["E_soil"]["value"] == row["value"]
    assert r["parameters"]["E_soil"]["determined"]
    assert (tmp_path / "py" / "parameters.csv").read_text() == (tmp_path / "cli" / "parameters.csv").read_text()


def test_a_sweep_from_python_gives_the_command_line_samples(tmp_path):
    study = os.path.join(ROOT, "tests", "sweep", "lhs.toml")
    t = stratum.sweep(study, out=str(tmp_path / "py"))
    subprocess.run([EXE, "sweep", study, "--out", str(tmp_path / "cli")], check=True, capture_output=True,
                   env=dict(os.environ, STRATUM_PLUGIN_PATH=""))
    assert (tmp_path / "py" / "samples.csv").read_text() == (tmp_path / "cli" / "samples.csv").read_text()
    assert list(t["index"]) == list(range(10))
    assert t["status"].count("failed") == 3  # the study's three samples with nu = 0.5


def test_plugins_lists_the_kinds():
    p = stratum.plugins()
    assert "linear_elastic" in p["material"] and "newton" in p["solver"]
