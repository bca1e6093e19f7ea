#!/usr/bin/env python3
"""PNG plots of a `stratum sweep` study (docs/sweep.md).

  plot_sweep.py tornado SAMPLES.csv QUANTITY [-o FILE.png]
      one-at-a-time study: one bar per parameter from the base run's value of QUANTITY to its
      values at the parameter's low and high setting, the widest swing on top.
  plot_sweep.py band SAMPLES.csv NAME [-o FILE.png] [--x-label ...] [--y-label ...] [--invert-y]
      sampled study: the 5 / 50 / 95 % quantiles of the curve recorded as the columns NAME@x
      (a quantity of type "curve" with at = [x1, x2, ...]), with every sample's curve in grey.
  --table Q1,Q2,...   also print the study's table in Markdown (the tables of
      docs/validation/loess_pile.md): tornado: the base row and one row per parameter, low / high
      of each quantity Qi, ranked like the bars; band: the 5 / 50 / 95 % rows of the columns Qi
      (NAME@x or any other quantity).

Rows with status "failed" (the scene could not run) are left out and counted. An empty cell of
a run that did not reach the abscissa (it stopped: the pile failed first) counts as beyond every
finite value, so a quantile is drawn only where at least that share of the samples reached x."""
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


def value(cell):
    return float(cell) if cell not in ("", None) else math.inf


def quantile(values, q):
    """Linear interpolation between order statistics (the usual 'type 7'); None where that
    needs a sample that did not reach the abscissa (inf)."""
    v = sorted(values)
    h = (len(v) - 1) * q
    lo, hi = math.floor(h), math.ceil(h)
    if math.isinf(v[hi]):
        return None
    return v[lo] + (h - lo) * (v[hi] - v[lo])


def tornado(rows, quantity, out, title=None, table=None):
    if "varied" not in rows[0]:
        sys.exit("plot_sweep: tornado needs a one_at_a_time study (a 'varied' column)")
    if quantity not in rows[0]:
        sys.exit(f"plot_sweep: no column '{quantity}'; columns: {', '.join(rows[0])}")
    by = {r["varied"]: r for r in rows}
    base = by.get("base")
    if base is None or base["status"] == "failed" or base[quantity] == "":
        sys.exit("plot_sweep: the base run has no value of " + quantity)
    b = float(base[quantity])
    params = [k for k in rows[0] if k not in ("index", "varied", "status", "reason")]
    bars = []
    lo = hi = None
    for name in dict.fromkeys(r["varied"].rsplit(":", 1)[0] for r in rows if r["varied"] != "base"):
        lo, hi = by.get(name + ":low"), by.get(name + ":high")
        vals = []
        for r in (lo, hi):
            ok = r is not None and r["status"] != "failed" and r[quantity] != ""
            vals.append(float(r[quantity]) if ok else None)
        # A setting whose run never reached the quantity (it stopped first) is the largest effect.
        swing = math.inf if None in vals else max(abs(v - b) for v in vals)
        label = name
        if name in params:
            label += f"  ({lo[name]} / {hi[name]})"
        bars.append((swing, label, vals, name))
    if table:
        print(tornado_table(rows, by, b, quantity, bars, table))
    bars.sort(key=lambda t: t[0])
    fig, ax = plt.subplots(figsize=(7, 0.5 * len(bars) + 1.6))
    for i, (_, label, (vlo, vhi), _) in enumerate(bars):
        for v, colour, r, dy in ((vlo, "tab:blue", lo, -0.15), (vhi, "tab:red", hi, 0.15)):
            if v is None:  # the run failed, or stopped before the quantity's abscissa
                why = "failed" if r is None or r["status"] == "failed" else "not reached: the run stopped first"
                ax.text(b, i + dy, f"  {'low' if dy < 0 else 'high'}: {why}", va="center", fontsize=7,
                        color=colour, fontweight="bold")
            else:
                ax.barh(i, v - b, left=b, color=colour, height=0.6)
    ax.set_yticks(range(len(bars)), [t[1] for t in bars], fontsize=8)
    ax.axvline(b, color="black", lw=1)
    ax.set_xlabel(f"{quantity} (base run {b:g})")
    ax.set_title((title + "\n" if title else "") +
                 "one at a time: low (blue) and high (red) setting, largest effect on top", fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=130)
    print(f"wrote {out}")


def cell(r, q):
    """A table cell: the value to 2 decimals, or why there is none."""
    if r is None or r["status"] == "failed":
        return "failed"
    return "stopped before" if r[q] == "" else f"{float(r[q]):.2f}"


def tornado_table(rows, by, b, quantity, bars, quantities):
    for q in quantities:
        if q not in rows[0]:
            sys.exit(f"plot_sweep: no column '{q}'; columns: {', '.join(rows[0])}")
    params = [k for k in rows[0] if k not in ("index", "varied", "status", "reason")]
    lines = ["| parameter (low / high) | " + " | ".join(f"{q}: low / high" for q in quantities) + " |",
             "|---|" + "---|" * len(quantities),
             "| base run | " + " | ".join(cell(by["base"], q) for q in quantities) + " |"]
    # The largest effect on `quantity` first; equal effects in the study's order.
    for swing, _, _, name in sorted(bars, key=lambda t: -t[0]):
        lo, hi = by.get(name + ":low"), by.get(name + ":high")
        label = name + (f" ({lo[name]} / {hi[name]})" if name in params and lo and hi else "")
        lines.append(f"| {label} | " + " | ".join(f"{cell(lo, q)} / {cell(hi, q)}" for q in quantities) + " |")
    return "\n".join(lines)


def band_table(rows, quantities):
    ok = [r for r in rows if r["status"] != "failed"]
    for q in quantities:
        if q not in rows[0]:
            sys.exit(f"plot_sweep: no column '{q}'; columns: {', '.join(rows[0])}")
    lines = ["| quantile | " + " | ".join(quantities) + " |", "|---|" + "---|" * len(quantities)]
    for p in (0.05, 0.5, 0.95):
        vals = [quantile([value(r[q]) for r in ok], p) for q in quantities]
        lines.append(f"| {round(p * 100)} % | " + " | ".join("stopped" if v is None else f"{v:.2f}" for v in vals) + " |")
    return "\n".join(lines)


def band(rows, name, out, xlabel, ylabel, invert, title=None, field=None, curves=()):
    cols = [c for c in rows[0] if c.startswith(name + "@")]
    if not cols:
        sys.exit(f"plot_sweep: no columns '{name}@x'; columns: {', '.join(rows[0])}")
    xs = [float(c.split("@", 1)[1]) for c in cols]
    ok = [r for r in rows if r["status"] != "failed"]
    failed = len(rows) - len(ok)
    if not ok:
        sys.exit("plot_sweep: every sample failed")
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for r in ok:
        pts = [(x, value(r[c])) for x, c in zip(xs, cols) if r[c] != ""]
        if pts:
            ax.plot([p[0] for p in pts], [p[1] for p in pts], color="0.8", lw=0.6, zorder=1)
    qs = {}
    for q in (0.05, 0.5, 0.95):
        qs[q] = [quantile([value(r[c]) for r in ok], q) for c in cols]
    for q, style in ((0.05, "--"), (0.5, "-"), (0.95, "--")):
        pts = [(x, y) for x, y in zip(xs, qs[q]) if y is not None]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], style, color="tab:blue", lw=1.8,
                label=f"{round(q * 100)} %", zorder=3)
    both = [(x, a, c) for x, a, c in zip(xs, qs[0.05], qs[0.95]) if a is not None and c is not None]
    if both:
        ax.fill_between([p[0] for p in both], [p[1] for p in both], [p[2] for p in both],
                        color="tab:blue", alpha=0.15, zorder=2)
    if field:  # a field test file (docs/validation/field_test.csv): its piles and their mean
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        import field_compare

        fl, fm, piles = field_compare.read_field(field)
        for k, c in enumerate(piles):
            ax.plot(fl, c, "o", ms=3.5, color="0.35", zorder=4, label="field test, piles 1-3" if k == 0 else None)
        ax.plot(fl, fm, "k-", lw=2, zorder=4, label="field test, mean")
    for k, spec in enumerate(curves):  # other load-settlement curves (CSV=LABEL), e.g. the Class-A record
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        import field_compare

        path, _, label = spec.partition("=")
        cl, cs = field_compare.read_curve(path)
        colour = ("tab:red", "tab:orange", "tab:purple", "tab:green")[k % 4]
        ax.plot(cl, cs, "-", color=colour, lw=1.5, zorder=4, label=label or path)
    ax.set_xlabel(xlabel or name + " abscissa")
    ax.set_ylabel(ylabel or name)
    if invert:
        ax.invert_yaxis()
    note = f"{len(ok)} samples" + (f", {failed} failed (left out)" if failed else "")
    ax.set_title((title + "\n" if title else "") + f"5 / 50 / 95 % band, {note}", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=130)
    print(f"wrote {out}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("kind", choices=["tornado", "band"])
    ap.add_argument("samples")
    ap.add_argument("name", help="tornado: a quantity column; band: a curve quantity's name")
    ap.add_argument("-o", "--out")
    ap.add_argument("--x-label")
    ap.add_argument("--y-label")
    ap.add_argument("--invert-y", action="store_true", help="y grows downwards (settlement)")
    ap.add_argument("--title", help="a first title line (the model, the study)")
    ap.add_argument("--field", help="band: also draw a field test file (load_kN, pileN_mm columns) and its mean")
    ap.add_argument("--curve", action="append", default=[], help="band: also draw CURVE.csv[=LABEL] (load_kN, settlement_mm)")
    ap.add_argument("--table", help="also print the table of these quantities (comma-separated) in Markdown")
    a = ap.parse_args()
    rows = read(a.samples)
    if not rows:
        sys.exit(f"plot_sweep: {a.samples} has no samples")
    out = a.out or os.path.join(os.path.dirname(a.samples) or ".", f"{a.kind}_{a.name}.png")
    table = a.table.split(",") if a.table else None
    if a.kind == "tornado":
        tornado(rows, a.name, out, a.title, table)
    else:
        if table:
            print(band_table(rows, table))
        band(rows, a.name, out, a.x_label, a.y_label, a.invert_y, a.title, a.field, a.curve)


if __name__ == "__main__":
    main()
