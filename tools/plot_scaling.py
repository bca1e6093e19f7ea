#!/usr/bin/env python3
"""Plot of bench_scaling: time per Newton iteration versus free DOF, per component.

Reads docs/figures/bench_scaling.csv (written by build/release/bin/bench_scaling) and writes
docs/figures/bench_scaling.png: log-log, one panel per problem (elastic, elastoplastic), the
assembly, stress update, solve and total per iteration, each with its least-squares exponent,
and reference slopes 1 and 1.3 (the target). Non-positive values (the linear-elastic update,
at the timer's resolution) leave their component out.
Usage: /usr/bin/python3 tools/plot_scaling.py [--root DIR]
"""
import argparse
import csv
import math
import os
import sys

COMPONENTS = [
    ("assembly_s", "assembly", "o-"),
    ("stress_update_s", "stress update", "s-"),
    ("solve_s", "solve (factorize + solve)", "^-"),
    ("per_iteration_s", "total per iteration", "D-"),
]
PROBLEMS = [("elastic", "Elastic (Lamé cylinder)"), ("elastoplastic", "Elastoplastic (Hill cylinder, von Mises)")]


def exponent(xs, ys):
    """Least-squares slope of log y against log x (None for fewer than two points)."""
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x > 0 and y > 0]
    if len(pts) < 2:
        return None
    n = len(pts)
    sx = sum(p[0] for p in pts)
    sy = sum(p[1] for p in pts)
    sxx = sum(p[0] * p[0] for p in pts)
    sxy = sum(p[0] * p[1] for p in pts)
    d = n * sxx - sx * sx
    return (n * sxy - sx * sy) / d if d > 0 else None


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--root", default=os.path.dirname(here), help="repository root (default: this checkout)")
    args = parser.parse_args()
    figures = os.path.join(args.root, "docs", "figures")
    src = os.path.join(figures, "bench_scaling.csv")
    with open(src, newline="") as f:
        rows = list(csv.DictReader(f))
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not available: no plot written (apt-get install python3-matplotlib)")
        return 1

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6), sharey=True)
    for ax, (key, title) in zip(axes, PROBLEMS):
        sel = [r for r in rows if r["problem"] == key]
        if not sel:
            ax.set_title(title + ": not run")
            continue
        dof = [float(r["free_dof"]) for r in sel]
        for col, label, style in COMPONENTS:
            ys = [float(r[col]) for r in sel]
            if min(ys) <= 0:
                # The linear-elastic update: at the timer's resolution, no meaningful curve.
                ax.plot([], [], style, label=f"{label}: at the timer's resolution, not shown")
                continue
            xs = dof
            k = exponent(xs, ys)
            text = f"{label} (slope {k:.2f})" if k is not None else label
            ax.loglog(xs, ys, style, label=text, lw=2.2 if col == "per_iteration_s" else 1.2, ms=5)
        cpu = [(x, float(r["per_iteration_cpu_s"])) for x, r in zip(dof, sel) if "per_iteration_cpu_s" in r]
        if cpu and min(y for _, y in cpu) > 0:
            xs, ys = zip(*cpu)
            k = exponent(xs, ys)
            ax.loglog(xs, ys, "D--", color="0.45", ms=4, lw=1.2, label=f"total per iteration, CPU time (slope {k:.2f})")
        # Reference slopes through the first total.
        x0 = dof[0]
        y0 = float(sel[0]["per_iteration_s"])
        xr = [min(dof), max(dof)]
        for s, ls in ((1.0, ":"), (1.3, "--")):
            ax.loglog(xr, [y0 * (x / x0) ** s for x in xr], "k" + ls, lw=0.8, label=f"slope {s:g}")
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("free DOF")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7.5, loc="lower right")
    axes[0].set_ylabel("time per Newton iteration (s)")
    fig.suptitle("bench_scaling: axisymmetric quad8, CHOLMOD, OPENBLAS_NUM_THREADS=1", fontsize=10)
    fig.tight_layout()
    out = os.path.join(figures, "bench_scaling.png")
    fig.savefig(out, dpi=110)
    print("wrote " + out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
