#!/usr/bin/env python3
"""The bored pile in soft clay (inputs/clay_pile/clay_pile.toml): time of all its stages, and what
the run gives at the stage ends (docs/validation/clay_pile.md).

Runs `stratum run` on the scene `--repeat` times (default 3), with its output as written (VTK of
every step, history, curves) and once more without VTK, and prints the wall and CPU time (the
child's user + system) of each, their medians, the steps, cut-backs and factorizations of the run
(summary.toml), the head settlement at the end of each loading and consolidation stage, the head
load at 10 % of the diameter and the largest excess pore pressure recorded beside the shaft in
the drained stage. Rewrites the section <!-- bench_clay_pile:begin --> ... :end --> of
docs/benchmarks.md (--no-write: print only).
"""
import argparse
import csv
import datetime
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_pile import ROOT, table, write_section  # noqa: E402

SCENE = ROOT / "inputs" / "clay_pile" / "clay_pile.toml"


def run(stratum, out, vtk=True):
    """One run: (wall s, CPU s of the child)."""
    scene = SCENE
    if not vtk:  # the same scene without its VTK series, beside the output (includes made absolute)
        text = SCENE.read_text().replace('"../materials/', f'"{SCENE.parent.parent}/materials/')
        assert "\nvtk = true\n" in text
        scene = out.parent / f"{out.name}_clay_pile.toml"
        scene.write_text(text.replace("\nvtk = true\n", "\nvtk = false\n"))
    args = [stratum, "run", str(scene), "--out", str(out), "--quiet"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    r = subprocess.run(args, capture_output=True, text=True, timeout=600)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        sys.exit(f"bench_clay_pile: stratum exited {r.returncode}: {r.stderr.strip()}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def summary(out):
    import tomllib

    return tomllib.loads((out / "summary.toml").read_text())


def rows_of(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--stratum", default=str(ROOT / "build" / "release" / "bin" / "stratum"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-write", action="store_true")
    a = ap.parse_args()
    if not Path(a.stratum).exists():
        sys.exit(f"bench_clay_pile: {a.stratum} not found: build first (tools/bench)")
    times, times_novtk = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(a.repeat):
            times.append(run(a.stratum, Path(tmp) / f"run{k}"))
            times_novtk.append(run(a.stratum, Path(tmp) / f"novtk{k}", vtk=False))
        out = Path(tmp) / "run0"
        s = summary(out)
        head = rows_of(out / "history" / "head.csv")
        shaft = rows_of(out / "history" / "shaft_mid.csv")
        curve = rows_of(out / "curves" / "load_settlement.csv")
        files = sum(1 for _ in out.rglob("*") if _.is_file())
    names = {"1": "geostatic", "2": "boring", "3": "concrete", "4": "undrained_load", "5": "consolidation",
             "6": "drained_load"}
    ends = {}
    for r in head:
        ends[r["stage"]] = float(r["uy_m"])
    drained_p = max((abs(float(r["p_kPa"])) for r in shaft if r["stage"] == "6"), default=float("nan"))
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    md = ["## The bored pile in soft clay (`bench_clay_pile.py`)\n",
          f"{stamp}, load average {os.getloadavg()[0]:.1f} at the start, {os.cpu_count()} cores; "
          f"`inputs/clay_pile/clay_pile.toml` (docs/validation/clay_pile.md), {a.repeat} runs each.\n"]
    med = lambda xs, i: statistics.median(x[i] for x in xs)  # noqa: E731
    md.append(table(["output", "wall s (median)", "CPU s (median)", "runs (wall s)"],
                    [["as the scene asks (VTK of every step)", f"{med(times, 0):.2f}", f"{med(times, 1):.2f}",
                      ", ".join(f"{t[0]:.2f}" for t in times)],
                     ["`[output] vtk = false`", f"{med(times_novtk, 0):.2f}", f"{med(times_novtk, 1):.2f}",
                      ", ".join(f"{t[0]:.2f}" for t in times_novtk)]]) + "\n")
    md.append(f"Stages {s['stages_done']} of {s['stages']} done, then `{s['stop_reason']}` "
              f"(the drained stage's stop at 10 % of d); {s['steps_done']} steps, {s['cutbacks']} cut-backs, "
              f"{s['work']['factorizations']} factorizations, {files} files written.\n")
    rows = [[names.get(k, k), f"{-1000 * v:.2f}"] for k, v in sorted(ends.items()) if k in ("4", "5", "6")]
    md.append(table(["at the end of stage", "head settlement (mm, from the start of the undrained loading)"], rows)
              + "\n")
    last = curve[-1] if curve else {}
    md.append(f"Head load at the drained stage's stop: {s['head_load']:.1f} kN at "
              f"{s['head_settlement']:.1f} mm; largest |p| beside the shaft at mid-depth in that stage: "
              f"{drained_p:.2f} kPa (drained: small against the 29 kPa of the undrained loading). "
              f"Curve rows: {len(curve)} (last: {', '.join(f'{k} = {v}' for k, v in last.items())}).\n")
    print(md[-1], flush=True)
    write_section(md, [], a.no_write, name="bench_clay_pile")


if __name__ == "__main__":
    main()
