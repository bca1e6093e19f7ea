#!/usr/bin/env python3
"""PNG plots of a `stratum calibrate` result folder (docs/calibrate.md).

  plot_calibration.py DIR [-o FILE.png] [--x-label TEXT] [--y-label TEXT]

One panel per data set of DIR/residuals.csv: the measured points, the computed curve at the best
values (DIR/fitted_<data>.csv) and, below, the weighted residuals at the measured abscissae.
The title carries the best values and their 95 % intervals from DIR/parameters.csv. Written to
DIR/calibration.png unless -o says otherwise."""
import argparse
import csv
import math
import os
import sys

from system_python import require

require(__file__, ["matplotlib"], "matplotlib (Debian: python3-matplotlib)")
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(cell):
    return float(cell) if cell not in ("", None) else math.nan


def data_sets(residuals):
    """The residuals.csv rows grouped by data set, in file order."""
    sets = {}
    for r in residuals:
        sets.setdefault(r["data"], []).append(r)
    return sets


def title(parameters):
    """'c = 9.645 (6.8 to 13.68), phi = 29.96 (27.01 to 32.91)'; 'not determined' where so."""
    parts = []
    for p in parameters:
        v = "%s = %.4g" % (p["name"], number(p["value"]))
        if p["determined"] == "true":
            v += " (%.4g to %.4g)" % (number(p["ci95_low"]), number(p["ci95_high"]))
        else:
            v += " (not determined)"
        parts.append(v)
    return ", ".join(parts)


def plot(folder, out, x_label=None, y_label=None):
    residuals = read(os.path.join(folder, "residuals.csv"))
    parameters = read(os.path.join(folder, "parameters.csv"))
    sets = data_sets(residuals)
    fig, axes = plt.subplots(2, len(sets), figsize=(6.0 * len(sets), 6.0), squeeze=False,
                             gridspec_kw={"height_ratios": [3, 1]}, sharex="col")
    for j, (name, rows) in enumerate(sets.items()):
        fitted = read(os.path.join(folder, "fitted_%s.csv" % name))
        xcol, ycol = list(fitted[0].keys())[:2] if fitted else ("x", "y")
        top, bottom = axes[0][j], axes[1][j]
        top.plot([number(r[xcol]) for r in fitted], [number(r[ycol]) for r in fitted], "-", color="C0",
                 label="computed at the best values")
        top.plot([number(r["x"]) for r in rows], [number(r["measured"]) for r in rows], "o", color="C3",
                 label="measured")
        top.set_ylabel(y_label or ycol)
        top.set_title(name)
        top.grid(True, alpha=0.3)
        top.legend()
        bottom.axhline(0.0, color="0.5", lw=0.8)
        bottom.plot([number(r["x"]) for r in rows], [number(r["residual"]) for r in rows], "o", color="C3")
        bottom.set_ylabel("weighted residual")
        bottom.set_xlabel(x_label or xcol)
        bottom.grid(True, alpha=0.3)
    fig.suptitle(title(parameters), fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folder")
    ap.add_argument("-o", "--output")
    ap.add_argument("--x-label")
    ap.add_argument("--y-label")
    a = ap.parse_args(argv)
    for f in ("residuals.csv", "parameters.csv"):
        if not os.path.isfile(os.path.join(a.folder, f)):
            sys.exit("plot_calibration.py: %s has no %s (is it the --out folder of stratum calibrate?)" % (a.folder, f))
    out = plot(a.folder, a.output or os.path.join(a.folder, "calibration.png"), a.x_label, a.y_label)
    print("wrote", out)


if __name__ == "__main__":
    main()
