#!/usr/bin/env python3
"""PNG plots of a pile run's curves: plot_pile.py OUT/curves

Reads load_settlement.csv (load_kN, settlement_mm), axial_force.csv (load_kN, depth_m,
axial_force_kN) and, if present, shaft_traction.csv; writes the PNGs beside them. The units come
from the headers (a scene with [units] force = "N", length = "mm" writes load_N, depth_mm, ...)."""
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


def column(rows, name):
    """(key, unit) of the column `name`_<unit> (the unit as stratum writes it: kN, mm, kN_per_cm2)."""
    for key in (rows[0].keys() if rows else []):
        if key.startswith(name + "_"):
            return key, key[len(name) + 1:].replace("_per_", "/")
    sys.exit(f"no column {name}_<unit> in {list(rows[0].keys()) if rows else 'an empty file'}")


# The field test's load increments (15 kN) in each force unit.
STEP = {"N": 15e3, "kN": 15.0, "MN": 15e-3}


def main(folder):
    rows = read(os.path.join(folder, "load_settlement.csv"))
    lk, lu = column(rows, "load")
    sk, su = column(rows, "settlement")
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.plot([r[lk] for r in rows], [r[sk] for r in rows], "o-")
    ax.set_xlabel(f"head load ({lu})")
    ax.set_ylabel(f"head settlement ({su})")
    ax.invert_yaxis()
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "load_settlement.png"), dpi=120)
    for name, quantity, label in (("axial_force", "axial_force", "axial force"),
                                  ("shaft_traction", "shear_traction", "shaft shear traction")):
        path = os.path.join(folder, name + ".csv")
        if not os.path.exists(path):
            continue
        data = read(path)
        key, unit = column(data, quantity)
        lk, lu = column(data, "load")
        dk, du = column(data, "depth")
        fig, ax = plt.subplots(figsize=(5, 4))
        loads = sorted({r[lk] for r in data})
        # the field's 15 kN increments and the last level: a line per converged step would bury them
        step = STEP.get(lu, 15.0)
        shown = [p for p in loads if p > 0 and abs(p / step - round(p / step)) < 1e-6] + loads[-1:]
        for load in sorted(set(shown)) if len(set(shown)) >= 2 else loads:
            pts = [r for r in data if r[lk] == load]
            ax.plot([r[key] for r in pts], [r[dk] for r in pts], label=f"{load:g} {lu}")
        ax.set_xlabel(f"{label} ({unit})")
        ax.set_ylabel(f"depth ({du})")
        ax.invert_yaxis()
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6)
        fig.tight_layout()
        fig.savefig(os.path.join(folder, name + ".png"), dpi=120)
    print("plots:", folder)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/hypoelastic/curves")
