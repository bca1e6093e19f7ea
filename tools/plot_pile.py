#!/usr/bin/env python3
"""PNG plots of a pile run's curves: plot_pile.py OUT/curves

Reads load_settlement.csv (load_kN, settlement_mm), axial_force.csv (load_kN, depth_m,
axial_force_kN) and, if present, shaft_traction.csv; writes the PNGs beside them."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(v):
    try:
        return float(v)
    except ValueError:
        return v


def read(path):
    with open(path, newline="") as f:
        return [{k: number(v) for k, v in row.items()} for row in csv.DictReader(f)]


def main(folder):
    rows = read(os.path.join(folder, "load_settlement.csv"))
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.plot([r["load_kN"] for r in rows], [r["settlement_mm"] for r in rows], "o-")
    ax.set_xlabel("head load (kN)")
    ax.set_ylabel("head settlement (mm)")
    ax.invert_yaxis()
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "load_settlement.png"), dpi=120)
    for name, key, label in (("axial_force", "axial_force_kN", "axial force (kN)"),
                             ("shaft_traction", "shear_traction_kPa", "shaft shear traction (kPa)")):
        path = os.path.join(folder, name + ".csv")
        if not os.path.exists(path):
            continue
        data = read(path)
        fig, ax = plt.subplots(figsize=(5, 4))
        loads = sorted({r["load_kN"] for r in data})
        # the field's 15 kN increments and the last level: a line per converged step would bury them
        shown = [p for p in loads if p > 0 and abs(p / 15.0 - round(p / 15.0)) < 1e-6] + loads[-1:]
        for load in sorted(set(shown)) if len(set(shown)) >= 2 else loads:
            pts = [r for r in data if r["load_kN"] == load]
            ax.plot([r[key] for r in pts], [r["depth_m"] for r in pts], label=f"{load:g} kN")
        ax.set_xlabel(label)
        ax.set_ylabel("depth (m)")
        ax.invert_yaxis()
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6)
        fig.tight_layout()
        fig.savefig(os.path.join(folder, name + ".png"), dpi=120)
    print("plots:", folder)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/hypoelastic/curves")
