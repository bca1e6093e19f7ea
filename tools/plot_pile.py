#!/usr/bin/env python3
"""PNG plots of a pile run's curves: plot_pile.py OUT/curves [--log RUN.txt]

Reads load_settlement.csv (load_kN, settlement_mm), axial_force.csv (load_kN, depth_m,
axial_force_kN) and, if present, shaft_traction.csv (load_kN, depth_m, shear_traction_kPa,
normal_traction_kPa, slip_mm, status); writes beside them

  load_settlement.png         the curve, its last converged point marked with the load and why
                              the run ended there
  axial_force.png             N(depth) at the 15 kN levels and the last level
  shaft_traction.png          shear traction along the shaft (same levels)
  shaft_normal_traction.png   normal traction on the shaft (compression negative)
  shaft_slip.png              slip along the shaft; the points where the interface slips are
                              marked

The units come from the headers (a scene with [units] force = "N", length = "mm" writes load_N,
depth_mm, ...). Why the run ended: the "stopped:" line of the run's printout when it is given
(--log, or <run>/run.txt, which tools/run keeps), else what <run>/diagnostics.csv shows (the
last step rejected: it failed after its cut-backs; the stage short of its full load without a
failed step: a stop limit such as stop_settlement).
"""
import csv
import math
import os
import sys

from system_python import require

require(__file__, ["matplotlib"], "matplotlib (Debian: python3-matplotlib)")
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(v):
    try:
        return float(v)
    except (TypeError, ValueError):
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


def has_column(rows, name):
    return bool(rows) and any(k.startswith(name + "_") for k in rows[0].keys())


def short(v):
    """A load for a label: three significant digits, never an exponent, no trailing zeros
    (73.75 -> 73.8, 74.3066 -> 74.3, 15.0 -> 15, 150 -> 150, 15000 -> 15000, 0.625 -> 0.625)."""
    if v == 0 or not math.isfinite(v):
        return f"{v:g}"
    d = max(0, 2 - int(math.floor(math.log10(abs(v)))))
    s = f"{v:.{d}f}"
    return s.rstrip("0").rstrip(".") if "." in s else s


# The field test's load increments (15 kN) in each force unit.
STEP = {"N": 15e3, "kN": 15.0, "MN": 15e-3}


def reason_from_log(text):
    """Why the run ended, from stratum run's printout: its "stopped:" line up to the first
    explanation, "full load reached" after "done:" without one, else None."""
    stopped = [line[len("stopped: "):] for line in text.splitlines() if line.startswith("stopped: ")]
    if stopped:
        s = stopped[-1]
        for cut in (", and ", " although", " (", "; "):
            if cut in s:
                s = s[: s.index(cut)]
        return s.strip()
    if any(line.startswith("done:") for line in text.splitlines()):
        return "full load reached"
    return None


def reason_from_diagnostics(rows):
    """Why the run ended, from diagnostics.csv (stage, step, accepted, lambda_n, lambda, ...,
    message), or None."""
    if not rows:
        return None
    last = rows[-1]
    if int(last.get("accepted", 1)) == 0:
        msg = str(last.get("message", "") or "").strip().split(":")[0].strip()
        return "a load step failed after its cut-backs" + (f" ({msg})" if msg else "")
    lam = last.get("lambda")
    if isinstance(lam, float) and lam < 1.0 - 1e-9:
        return f"stage ended at load factor {lam:.3g} without a failed step (a stop limit, e.g. stop_settlement)"
    return "full load reached"


def stop_reason(folder, log=None):
    run = os.path.dirname(os.path.abspath(folder))
    for path in ([log] if log else []) + [os.path.join(run, "run.txt")]:
        if path and os.path.exists(path):
            with open(path, errors="replace") as f:
                r = reason_from_log(f.read())
            if r:
                return r
    diag = os.path.join(run, "diagnostics.csv")
    if os.path.exists(diag):
        return reason_from_diagnostics(read(diag))
    return None


def save(fig, path):
    """Writes the figure (temporary file, then rename); returns the texts of its legends."""
    texts = [t.get_text() for a in fig.axes if a.get_legend() for t in a.get_legend().get_texts()]
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    plt.close(fig)
    os.replace(tmp, path)
    return texts


def load_settlement(folder, reason):
    rows = read(os.path.join(folder, "load_settlement.csv"))
    lk, lu = column(rows, "load")
    sk, su = column(rows, "settlement")
    fig, ax = plt.subplots(figsize=(6, 4.5))
    P, s = [r[lk] for r in rows], [r[sk] for r in rows]
    ax.plot(P, s, "-", color="C0", lw=1.5, label="computed (each converged step)")
    if rows:
        text = f"last converged point: {short(P[-1])} {lu}, {short(s[-1])} {su}"
        ax.plot([P[-1]], [s[-1]], marker="X", ms=11, color="C3", ls="", zorder=5,
                label=text + (f"\nrun ended: {reason}" if reason else ""))
        ax.annotate(f"{short(P[-1])} {lu}", (P[-1], s[-1]), textcoords="offset points", xytext=(-8, -4),
                    ha="right", va="bottom", fontsize=9, color="C3")
    ax.set_xlabel(f"head load ({lu})")
    ax.set_ylabel(f"head settlement ({su})")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.invert_yaxis()
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7.5, loc="lower left")
    ax.set_title("Pile head: load against settlement", fontsize=10)
    fig.tight_layout()
    return "load_settlement.png", save(fig, os.path.join(folder, "load_settlement.png"))


def split_ambiguous(rows, key, dk):
    """(rows to draw, depths left out): the rows of one load at a depth where the file has
    different values of `key` are left out (shaft_traction.csv takes every interface point at the
    largest radius of an interface domain, so where one domain holds the shaft and the base, the
    toe has the shaft's last point and the base's corner point; which is which the file does not
    say). Repeated equal rows (a node shared by two interface cells) are kept."""
    by_depth = {}
    for r in rows:
        by_depth.setdefault(r[dk], set()).add(r[key])
    out = {d for d, v in by_depth.items() if len(v) > 1}
    return [r for r in rows if r[dk] not in out], sorted(out)


def depth_plot(folder, data, quantity, label, name, title, zero_line=False, mark_slip=False):
    key, unit = column(data, quantity)
    lk, lu = column(data, "load")
    dk, du = column(data, "depth")
    left_out = set()
    fig, ax = plt.subplots(figsize=(7.2, 4.5))
    loads = sorted({r[lk] for r in data})
    # the field's 15 kN increments and the last level: a line per converged step would bury them
    step = STEP.get(lu, 15.0)
    shown = [p for p in loads if p > 0 and abs(p / step - round(p / step)) < 1e-6] + loads[-1:]
    levels = sorted(set(shown)) if len(set(shown)) >= 2 else loads
    colours = plt.get_cmap("viridis")
    slipping = False
    for n, load in enumerate(levels):
        pts, out = split_ambiguous([r for r in data if r[lk] == load], key, dk)
        left_out.update(out)
        last = load == loads[-1]
        c = "C3" if last else colours(n / max(len(levels) - 1, 1))
        ax.plot([r[key] for r in pts], [r[dk] for r in pts], color=c, lw=2.0 if last else 1.2,
                ls="--" if last else "-", label=f"{short(load)} {lu}" + (" (last converged)" if last else ""))
        if mark_slip and "status" in pts[0]:
            sl = [r for r in pts if str(r["status"]) == "slip"]
            if sl:
                slipping = True
                ax.plot([r[key] for r in sl], [r[dk] for r in sl], "o", mfc="none", mec=c, ms=5)
    if slipping:
        ax.plot([], [], "o", mfc="none", mec="black", ms=5, label="interface slipping")
    if zero_line:
        ax.axvline(0.0, color="black", lw=0.6)
    if left_out:
        deepest = max(r[dk] for r in data)
        where = ", ".join(short(d) for d in sorted(left_out)) + f" {du}"
        fig.text(0.01, 0.01, f"not drawn: depth {where}, where the file has two different rows"
                 + (" (the toe: the shaft's last point and the base's corner)" if max(left_out) == deepest else ""),
                 fontsize=7, color="0.3", ha="left", va="bottom")
    ax.set_xlabel(f"{label} ({unit})")
    ax.set_ylabel(f"depth ({du})")
    ax.invert_yaxis()
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7.5, title=f"head load ({lu})", title_fontsize=7.5, loc="upper left",
              bbox_to_anchor=(1.02, 1.0), frameon=False)  # beside the axes: never on the curves
    ax.set_title(title, fontsize=10)
    fig.tight_layout(rect=(0, 0.03 if left_out else 0, 1, 1))
    return name + ".png", save(fig, os.path.join(folder, name + ".png"))


def main(argv):
    args = [a for a in argv if not a.startswith("--log")]
    log = None
    for i, a in enumerate(argv):
        if a == "--log" and i + 1 < len(argv):
            log = argv[i + 1]
            args.remove(argv[i + 1])
        elif a.startswith("--log="):
            log = a[len("--log="):]
    folder = args[0] if args else "out/hypoelastic/curves"
    reason = stop_reason(folder, log)
    written = dict([load_settlement(folder, reason)])
    plots = (("axial_force.csv", "axial_force", "axial force", "axial_force", "Axial force in the pile", {}),
             ("shaft_traction.csv", "shear_traction", "shear traction on the shaft", "shaft_traction",
              "Shaft shear traction (soil on pile)", {"zero_line": True}),
             ("shaft_traction.csv", "normal_traction", "normal traction on the shaft, compression < 0",
              "shaft_normal_traction", "Normal traction on the shaft", {"zero_line": True}),
             ("shaft_traction.csv", "slip", "slip (tangential jump of the interface)", "shaft_slip",
              "Slip of the pile against the soil", {"mark_slip": True}))
    cache = {}
    for csv_name, quantity, label, name, title, opts in plots:
        path = os.path.join(folder, csv_name)
        if not os.path.exists(path):
            continue
        data = cache.setdefault(path, read(path))
        if not has_column(data, quantity):
            continue
        written.update([depth_plot(folder, data, quantity, label, name, title, **opts)])
    print("plots:", folder, "(" + ", ".join(written) + ")" + (f"; run ended: {reason}" if reason else ""))
    return written  # {PNG: its legend's texts}


if __name__ == "__main__":
    main(sys.argv[1:])
