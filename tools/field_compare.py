#!/usr/bin/env python3
"""Compare pile load-settlement curves with the loess field test (docs/validation/field_test.csv).

    tools/field_compare.py CURVE.csv[=LABEL] ... [--field docs/validation/field_test.csv]
                           [--png FILE.png] [--loads 30,45,60,75,90,105]

Each CURVE.csv has the columns load_kN,settlement_mm (curves/load_settlement.csv of a run, or a
Class-A record). Prints, per curve, the settlement at the chosen loads, its ratio to the mean of the
three test piles, and the hyperbolic fit P = s / (a + b s) of both (thesis eq. 5.3, P_ult = 1 / b),
fitted the same way: least squares of s / P against s over the recorded levels with P > 0 (the
Chin-Kondner straight line). A curve that ends before a load gives "beyond failure" there.

Exit code 0; a missing or malformed file is one line on stderr and exit code 1.
"""
import argparse
import csv
import os
import sys


# A run's curve in a scene with [units] (load_N, settlement_cm, ...) is converted to kN and mm,
# the units of the field test.
TO_KN = {"N": 1e-3, "kN": 1.0, "MN": 1e3}
TO_MM = {"mm": 1.0, "cm": 10.0, "m": 1e3}


def read_curve(path):
    """(loads in kN, settlements in mm) from a CSV with load_<force> and settlement_<length>
    columns, as stratum writes them (load_kN, settlement_mm by default; '#' lines skipped)."""
    with open(path, newline="") as f:
        rows = [r for r in f if r.strip() and not r.lstrip().startswith("#")]
    reader = csv.DictReader(rows)
    names = reader.fieldnames or []
    lk = next((n for n in names if n.startswith("load_") and n[5:] in TO_KN), None)
    sk = next((n for n in names if n.startswith("settlement_") and n[11:] in TO_MM), None)
    if not lk or not sk:
        raise ValueError(f"{path}:1: expected a header with load_kN and settlement_mm (or other units)")
    fl, fs = TO_KN[lk[5:]], TO_MM[sk[11:]]
    loads, settl = [], []
    for i, r in enumerate(reader, start=2):
        try:
            loads.append(fl * float(r[lk]))
            settl.append(fs * float(r[sk]))
        except (TypeError, ValueError, KeyError):
            raise ValueError(f"{path}:{i}: expected numbers in {lk} and {sk}")
    return loads, settl


def read_field(path):
    """(loads, mean settlement, [pile curves]) of the field test file."""
    with open(path, newline="") as f:
        rows = [r for r in f if r.strip() and not r.lstrip().startswith("#")]
    reader = csv.DictReader(rows)
    piles = [c for c in reader.fieldnames if c.startswith("pile")]
    if not piles:
        raise ValueError(f"{path}: no pileN_mm columns")
    loads, cols = [], [[] for _ in piles]
    for r in reader:
        loads.append(float(r["load_kN"]))
        for k, c in enumerate(piles):
            cols[k].append(float(r[c]))
    mean = [sum(c[i] for c in cols) / len(cols) for i in range(len(loads))]
    return loads, mean, cols


def hyperbolic_fit(loads, settlements):
    """(a, b) of P = s / (a + b s): least squares of s/P = a + b s over the points with P > 0.

    a is the inverse initial stiffness (mm/kN), 1/b the asymptotic load P_ult (kN)."""
    pts = [(s, s / p) for p, s in zip(loads, settlements) if p > 0 and s > 0]
    if len(pts) < 2:
        raise ValueError("a hyperbolic fit needs at least two points with P > 0 and s > 0")
    n = len(pts)
    sx = sum(x for x, _ in pts)
    sy = sum(y for _, y in pts)
    mx, my = sx / n, sy / n
    sxx = sum((x - mx) ** 2 for x, _ in pts)
    sxy = sum((x - mx) * (y - my) for x, y in pts)
    if sxx == 0.0:
        raise ValueError("a hyperbolic fit needs two different settlements")
    b = sxy / sxx
    a = my - b * mx
    return a, b


def settlement_at(loads, settlements, p):
    """Settlement at load p by linear interpolation; None beyond the curve's last level."""
    if p > loads[-1] + 1e-9:
        return None
    for i in range(1, len(loads)):
        if loads[i] >= p - 1e-9:
            l0, l1 = loads[i - 1], loads[i]
            t = 0.0 if l1 == l0 else (p - l0) / (l1 - l0)
            return settlements[i - 1] + t * (settlements[i] - settlements[i - 1])
    return settlements[0] if loads and abs(loads[0] - p) < 1e-9 else None


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("curves", nargs="+", help="CURVE.csv or CURVE.csv=LABEL")
    ap.add_argument("--field", default="docs/validation/field_test.csv")
    ap.add_argument("--png", help="also draw the curves with the three piles and their mean")
    ap.add_argument("--loads", default="15,30,45,60,75,90,105,120")
    args = ap.parse_args(argv)
    if args.png:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            # Another Python first on PATH (pyenv, conda) lacks Debian's python3-matplotlib.
            if os.path.exists("/usr/bin/python3") and os.path.realpath(sys.executable) != "/usr/bin/python3":
                os.execv("/usr/bin/python3", ["/usr/bin/python3", os.path.abspath(__file__)] + argv)
            print("field_compare: --png needs matplotlib (Debian: python3-matplotlib)", file=sys.stderr)
            return 1
    try:
        fl, fm, piles = read_field(args.field)
        at = [float(x) for x in args.loads.split(",")]
        fa, fb = hyperbolic_fit(fl, fm)
        curves = []
        for spec in args.curves:
            path, _, label = spec.partition("=")
            curves.append((label or path, *read_curve(path)))
    except (OSError, ValueError) as e:
        print(f"field_compare: {e}", file=sys.stderr)
        return 1
    print(f"field test mean: hyperbolic fit a = {fa:.5g} mm/kN, P_ult = 1/b = {1 / fb:.1f} kN")
    head = "| curve | " + " | ".join(f"{p:g} kN" for p in at) + " | P_ult (kN) | P_ult / test |"
    print(head)
    print("|" + "---|" * (len(at) + 3))
    mean_row = "| test mean (mm) | " + " | ".join(
        f"{settlement_at(fl, fm, p):.2f}" if settlement_at(fl, fm, p) is not None else "-" for p in at)
    print(mean_row + f" | {1 / fb:.0f} | 1 |")
    for label, loads, settl in curves:
        cells = []
        for p in at:
            s, m = settlement_at(loads, settl, p), settlement_at(fl, fm, p)
            cells.append("beyond failure" if s is None else f"{s:.2f} ({s / m:.2f}x)" if m else f"{s:.2f}")
        try:
            a, b = hyperbolic_fit(loads, settl)
            pu = f"{1 / b:.0f} | {(1 / b) / (1 / fb):.2f}" if b > 0 else "- | -"
        except ValueError:
            pu = "- | -"
        print(f"| {label} (mm, ratio to test) | " + " | ".join(cells) + f" | {pu} |")
    if args.png:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(7, 5))
        for k, c in enumerate(piles):
            ax.plot(c, fl, "o", ms=4, color="0.55", label="field test, piles 1-3" if k == 0 else None)
        ax.plot(fm, fl, "k-", lw=2, label="field test, mean of three piles")
        for label, loads, settl in curves:
            ax.plot(settl, loads, "-", lw=1.5, label=label)
        ax.set_xlabel("head settlement (mm)")
        ax.set_ylabel("head load (kN)")
        ax.set_xlim(0, 30)
        ax.set_ylim(0, 150)
        ax.grid(alpha=0.3)
        ax.legend(loc="lower right", fontsize=8)
        ax.set_title("Loess pile (d = 0.27 m, L = 3 m): analyses against the field test")
        fig.tight_layout()
        tmp = args.png + ".tmp.png"
        fig.savefig(tmp, dpi=120)
        os.replace(tmp, args.png)
        print(f"figure: {args.png}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
