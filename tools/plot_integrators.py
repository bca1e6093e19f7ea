#!/usr/bin/env python3
"""Plots of bench_integrators: Krieg & Krieg iso-error maps and the MCC error-vs-cost plot.

Reads docs/figures/iso_error_<scheme>.csv and docs/figures/mcc_error_cost.csv (written by
build/release/bin/bench_integrators) and writes docs/figures/iso_error_<scheme>.png and
docs/figures/mcc_error_cost.png. Usage: python3 tools/plot_integrators.py [--root DIR]
"""
import argparse
import csv
import math
import os
import sys

SCHEMES = ["forward_euler", "modified_euler", "trapezoidal", "midpoint", "cutting_plane", "closest_point"]


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def iso_map(plt, np, figures, scheme):
    rows = read_csv(os.path.join(figures, f"iso_error_{scheme}.csv"))
    xs = sorted({float(r["de_n_over_eps_y"]) for r in rows})
    ys = sorted({float(r["de_t_over_eps_y"]) for r in rows})
    z = np.full((len(ys), len(xs)), np.nan)
    for r in rows:
        i = ys.index(float(r["de_t_over_eps_y"]))
        j = xs.index(float(r["de_n_over_eps_y"]))
        z[i, j] = float(r["error_pct"])
    fig, ax = plt.subplots(figsize=(5, 4.3))
    finite = z[np.isfinite(z)]
    zmax = float(finite.max()) if finite.size else 0.0
    if zmax > 0.0:
        levels = [lv for lv in (0.01, 0.1, 0.5, 1, 2, 5, 10, 15, 20, 30, 50, 100, 200, 500, 1000) if lv <= zmax]
        if len(levels) < 2:
            levels = list(np.linspace(0.0, zmax, 6)[1:])
        cf = ax.contourf(xs, ys, z, levels=[0.0] + levels + [max(zmax, levels[-1]) * 1.0001], cmap="viridis")
        cs = ax.contour(xs, ys, z, levels=levels, colors="k", linewidths=0.6)
        ax.clabel(cs, fmt="%g", fontsize=7)
        fig.colorbar(cf, ax=ax, label="error %")
    else:
        ax.text(5, 5, "error = 0 everywhere", ha="center")
    ax.set_xlabel(r"$\Delta\varepsilon_n / \varepsilon_y$")
    ax.set_ylabel(r"$\Delta\varepsilon_t / \varepsilon_y$")
    ax.set_title(f"Krieg & Krieg one-step error: {scheme} (max {zmax:.3g} %)", fontsize=9)
    ax.set_aspect("equal")
    out = os.path.join(figures, f"iso_error_{scheme}.png")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def error_cost(plt, figures):
    rows = read_csv(os.path.join(figures, "mcc_error_cost.csv"))
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    for scheme in SCHEMES:
        pts = [r for r in rows if r["scheme"] == scheme and r["ok"] == "1"]
        pts = [(float(r["time_s"]), int(r["yield_evaluations"]), float(r["err_p_ref"])) for r in pts]
        pts = [(t, y, max(e, 1e-16)) for t, y, e in pts if math.isfinite(e)]
        if not pts:
            continue
        axes[0].loglog([p[1] for p in pts], [p[2] for p in pts], "o-", ms=3, label=scheme)
        axes[1].loglog([p[0] * 1e3 for p in pts], [p[2] for p in pts], "o-", ms=3, label=scheme)
    axes[0].set_xlabel("yield evaluations")
    axes[1].set_xlabel("time (ms, median of 3)")
    for ax in axes:
        ax.set_ylabel("relative error of end p vs reference")
        ax.grid(True, which="both", lw=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("MCC undrained triaxial, 10 % axial strain in 1 ... 1000 steps", fontsize=10)
    fig.tight_layout()
    out = os.path.join(figures, "mcc_error_cost.png")
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--root", default=os.path.dirname(here), help="source tree (default: the repository)")
    args = parser.parse_args()
    figures = os.path.join(args.root, "docs", "figures")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy as np
    except ImportError:
        print("matplotlib/numpy not available: no plots written (apt-get install python3-matplotlib)")
        return 1
    for scheme in SCHEMES:
        print("wrote", iso_map(plt, np, figures, scheme))
    print("wrote", error_cost(plt, figures))
    return 0


if __name__ == "__main__":
    sys.exit(main())
