"""Stratum from Python (docs/python.md).

    import stratum
    r = stratum.run("inputs/loess_pile/hypoelastic.toml", overrides={"materials.loess.K": [300, 250]})
    r.load_settlement            # (n, 2) array: head load (kN), settlement (mm)
    r.recorders["footing"]["ry"] # one column of a recorder, as an array
    r.summary["status"]          # "completed", "stopped" or "failed"

    folder = stratum.read_results("out/hypoelastic")   # what a run wrote, without parsing XML

Scenes run in this process with the GIL released; Ctrl-C ends a run at its next step with its
files written (as SIGINT does for `stratum run`) and raises KeyboardInterrupt. Input errors raise
stratum.Error, which carries .file, .line, .column and .message.
"""
import csv
import os
import tomllib
import xml.etree.ElementTree as ET

from ._stratum import Error, calibrate, check, plugins, scene_text
from ._stratum import sweep as _sweep
from ._stratum import point as _point
from ._stratum import run as _run

__all__ = ["Error", "Result", "Results", "calibrate", "check", "plugins", "point", "read_results", "run",
           "scene_text", "sweep"]


class Result:
    """What run() returns: arrays of the curves and recorders, the summary and the units."""

    def __init__(self, d):
        self.load_settlement = d["load_settlement"]
        self.settlement_components = d["settlement_components"]
        self.recorders = d["recorders"]
        self.summary = d["summary"]
        self.units = d["units"]
        self.title = d["title"]
        self.out_dir = d["summary"]["out_dir"]

    def __repr__(self):
        s = self.summary
        return "<stratum.Result %r: %s, %d steps, %d cut-backs, recorders %s>" % (
            self.title, s["status"], s["steps"], s["cutbacks"], ", ".join(self.recorders) or "none")


def run(path=None, *, text=None, overrides=None, out=None, write_output=True, progress=None):
    """Runs a scene (a file, or TOML text) with optional overrides {"table.key": value} and returns
    a Result. progress(step, steps, load_factor) is called after every accepted step."""
    return Result(_run(path=path, text=text, overrides=overrides or {}, out=out, write_output=write_output,
                       progress=progress))


def point(path=None, *, text=None, overrides=None):
    """Runs a point file (stratum point) with optional overrides and returns a dict: step, strain
    and stress as (n, 6) arrays (xx, yy, zz, xy, yz, zx; engineering shear strains; stresses
    tension positive in the file's units), status and message."""
    return _point(path=path, text=text, overrides=overrides or {})


def sweep(path, *, out=None, progress=None):
    """Runs a study file (stratum sweep) on this process, sample after sample, and returns its
    table as {column: numpy array} (text columns such as status and reason as lists), the rows of
    samples.csv under "csv". With out=DIR, samples.csv is written there (and per-sample output when
    the study asks for it). progress(done, total, status) after every sample; Ctrl-C stops
    between samples. For MPI and the journal use the command line (docs/sweep.md)."""
    import numpy as np

    d = _sweep(path, out=out, progress=progress)
    reader = csv.DictReader(d["csv"].splitlines())
    rows = list(reader)
    table = {}
    for c in reader.fieldnames:
        cells = [r[c] for r in rows]
        try:
            table[c] = np.array([float(v) if v != "" else float("nan") for v in cells])
        except ValueError:
            table[c] = cells
    table["csv"] = d["csv"]
    return table


def _numbers(rows, columns):
    """Columns of CSV rows as lists of floats (empty cells: nan)."""
    out = {}
    for c in columns:
        out[c] = [float(r[c]) if r[c] not in ("", None) else float("nan") for r in rows]
    return out


def _read_csv(path):
    with open(path, newline="") as f:
        lines = [line for line in f if not line.startswith("#")]
    reader = csv.DictReader(lines)
    rows = list(reader)
    return _numbers(rows, reader.fieldnames or [])


class Results:
    """A run's output folder, read: summary.toml as a dict, each CSV of curves/ and history/ as
    {column: numpy array} (column names as written, with their units where the file has them),
    and the VTK series of each .pvd as a list of (time, path) in time order."""

    def __init__(self, folder):
        import numpy as np

        self.folder = folder
        summary = os.path.join(folder, "summary.toml")
        if not os.path.isfile(summary):
            raise FileNotFoundError("%s has no summary.toml: not the output folder of a finished stratum run" % folder)
        with open(summary, "rb") as f:
            self.summary = tomllib.load(f)
        self.curves, self.recorders = {}, {}
        for sub, into in (("curves", self.curves), ("history", self.recorders)):
            d = os.path.join(folder, sub)
            if os.path.isdir(d):
                for name in sorted(os.listdir(d)):
                    if name.endswith(".csv"):
                        cols = _read_csv(os.path.join(d, name))
                        into[name[:-4]] = {k: np.array(v) for k, v in cols.items()}
        self.series = {}
        for name in sorted(os.listdir(folder)):
            if name.endswith(".pvd"):
                root = ET.parse(os.path.join(folder, name)).getroot()
                steps = [(float(e.get("timestep")), os.path.join(folder, e.get("file")))
                         for e in root.iter("DataSet")]
                self.series[name[:-4]] = sorted(steps)

    def __repr__(self):
        return "<stratum.Results %s: curves %s, recorders %s, series %s>" % (
            self.folder, ", ".join(self.curves) or "none", ", ".join(self.recorders) or "none",
            ", ".join(self.series) or "none")


def read_results(folder):
    """Reads a run's output folder (see Results)."""
    return Results(folder)
