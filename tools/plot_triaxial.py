#!/usr/bin/env python3
"""Triaxial plots from point-driver CSVs: q vs eps_axial and eps_vol vs eps_axial.

Reads any number of CSV files written by `stratum point FILE --out CSV` (columns eps_axial,
eps_vol, q_kPa: compression positive; q_MPa etc. from a point file with [units]) and writes two PNGs:
    <out>_q.png     deviator q (kPa) against axial strain (%)
    <out>_ev.png    volumetric strain (%) against axial strain (%)

Usage:
    python3 tools/plot_triaxial.py --out docs/figures/loess_duncan_chang \
        --title "Loess, Duncan-Chang" a.csv "sigma_3 = 25 kPa" b.csv "sigma_3 = 40 kPa" ...
Each CSV is followed by its label. With --reference CSV LABEL pairs (same columns), those
curves are drawn dashed, e.g. for measured data or another model.
"""
import argparse
import csv
import os
import sys


def read_curve(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    # q_<stress unit>: q_kPa, or q_MPa from a point file with [units] force = "N", length = "mm"
    qcol = next((k for k in (rows[0].keys() if rows else []) if k.startswith("q_")), "q_kPa")
    for col in ("eps_axial", "eps_vol", qcol):
        if rows and col not in rows[0]:
            sys.exit(f"{path}: no column '{col}' (is this a `stratum point` CSV?)")
    ea = [100.0 * float(r["eps_axial"]) for r in rows]
    ev = [100.0 * float(r["eps_vol"]) for r in rows]
    q = [float(r[qcol]) for r in rows]
    return ea, ev, q, qcol[2:].replace("_per_", "/")


def pairs(items, what):
    if len(items) % 2:
        sys.exit(f"{what}: give CSV files and labels in pairs (CSV LABEL CSV LABEL ...)")
    return [(items[i], items[i + 1]) for i in range(0, len(items), 2)]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True, help="output path without extension; _q.png and _ev.png are added")
    ap.add_argument("--title", default="", help="figure title")
    ap.add_argument("--reference", nargs="*", default=[], help="CSV LABEL pairs drawn dashed")
    ap.add_argument("curves", nargs="+", help="CSV LABEL pairs")
    args = ap.parse_args()

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    curves = [(p, l, read_curve(p)) for p, l in pairs(args.curves, "curves")]
    refs = [(p, l, read_curve(p)) for p, l in pairs(args.reference, "--reference")]
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    unit = curves[0][2][3] if curves else "kPa"
    for key, ylabel, idx in (("q", f"deviator q = sigma_1 - sigma_3 ({unit})", 2),
                             ("ev", "volumetric strain eps_vol (%), compression +", 1)):
        fig, ax = plt.subplots(figsize=(6.4, 4.6))
        for i, (_, label, c) in enumerate(curves):
            ax.plot(c[0], c[idx], "-", color=f"C{i % 10}", label=label)
        for i, (_, label, c) in enumerate(refs):
            ax.plot(c[0], c[idx], "--", color=f"C{i % 10}", label=label)
        ax.set_xlabel("axial strain eps_axial (%), compression +")
        ax.set_ylabel(ylabel)
        if args.title:
            ax.set_title(args.title)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        path = f"{args.out}_{key}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        print(path)


if __name__ == "__main__":
    main()
