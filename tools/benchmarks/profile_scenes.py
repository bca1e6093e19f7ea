#!/usr/bin/env python3
"""Where the time of the pile scenes and the strip footing goes (issue 37, item 4).

For each scene: the median of --repeat runs of `stratum run` (CPU time of the process, user +
system, and wall time), the run's own split of its time (assembly with the stress updates,
factorization, solve, output; printed by `stratum run` as its `time:` line), and a `perf record`
sample of one more run that splits the assembly into the material updates (samples in the
material plugins' libraries) and the elements (samples in the element and contact plugins'
libraries) as shares of the process's CPU samples. Prints the table and, unless --no-write, rewrites the section
<!-- profile_scenes:begin --> ... <!-- profile_scenes:end --> of docs/benchmarks.md.

Usage: tools/benchmarks/profile_scenes.py [--stratum EXE] [--repeat K] [--no-perf] [--no-write]
       [--label TEXT] [SCENE ...]

perf (Debian's linux-perf) samples the program at 999 Hz with its libraries' symbols; without it
(--no-perf, or perf missing) the material/element split is left out.
"""
import argparse
import datetime
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCENES = ["inputs/loess_pile/hypoelastic.toml", "inputs/loess_pile/cap.toml", "inputs/loess_pile/class_c.toml",
          "inputs/loess_pile/hardening_soil.toml", "inputs/examples/strip_footing_mohr_coulomb.toml"]
TIME_LINE = re.compile(r"^time: ([0-9.]+) s: assembly and stress update ([0-9.]+) s \((\d+)\), linear solver "
                       r"([0-9.]+) s \(analyze ([0-9.]+) x\d+, factorize ([0-9.]+) x(\d+), solve ([0-9.]+) x\d+\), "
                       r"output ([0-9.]+) s")


def plugin_kinds(exe):
    """{library stem: kind} of every plugin `stratum plugins` lists (stratum_<name>.so)."""
    out = subprocess.run([exe, "plugins"], capture_output=True, text=True, check=True).stdout
    kinds = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) >= 2 and parts[0] in ("material", "element", "contact_law"):
            kinds[parts[1]] = parts[0]
    return kinds


def run_once(exe, scene, out_dir, perf_file=None):
    """(cpu s, wall s, parsed time line) of one run."""
    cmd = [exe, "run", scene, "--out", out_dir]
    if perf_file:
        cmd = ["perf", "record", "-q", "-F", "999", "-o", perf_file, "--"] + cmd
    t0 = os.times()
    start = datetime.datetime.now()
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    wall = (datetime.datetime.now() - start).total_seconds()
    t1 = os.times()
    if p.returncode not in (0, 5):
        raise RuntimeError(f"{scene}: exit {p.returncode}: {p.stderr.strip()[-300:]}")
    m = next((TIME_LINE.match(l) for l in p.stdout.splitlines() if TIME_LINE.match(l)), None)
    if not m:
        raise RuntimeError(f"{scene}: no time line in the output")
    cpu = (t1.children_user - t0.children_user) + (t1.children_system - t0.children_system)
    split = {"total": float(m.group(1)), "assembly": float(m.group(2)), "assemblies": int(m.group(3)),
             "analyze": float(m.group(5)), "factorize": float(m.group(6)), "factorizations": int(m.group(7)),
             "solve": float(m.group(8)), "output": float(m.group(9))}
    return cpu, wall, split


def perf_shares(perf_file, kinds):
    """Fractions of the samples in material plugins, element and contact plugins, and libstratum."""
    rep = subprocess.run(["perf", "report", "-i", perf_file, "--no-children", "--sort", "dso", "--stdio"],
                         capture_output=True, text=True).stdout
    shares = {"material": 0.0, "element": 0.0, "framework": 0.0}
    for line in rep.splitlines():
        m = re.match(r"\s*([0-9.]+)%\s+(\S+)", line)
        if not m:
            continue
        pct, dso = float(m.group(1)), m.group(2)
        stem = re.sub(r"^stratum_|\.so.*$", "", dso)
        kind = kinds.get(stem)
        if kind == "material":
            shares["material"] += pct / 100
        elif kind in ("element", "contact_law"):
            shares["element"] += pct / 100
        elif dso.startswith("libstratum"):
            shares["framework"] += pct / 100
    return shares


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--stratum", default=str(ROOT / "build/release/bin/stratum"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-perf", action="store_true")
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--label", default="")
    ap.add_argument("scenes", nargs="*", default=SCENES)
    a = ap.parse_args()
    use_perf = not a.no_perf and shutil.which("perf") is not None
    kinds = plugin_kinds(a.stratum)
    load = os.getloadavg()[0]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for scene in a.scenes:
            runs = [run_once(a.stratum, scene, os.path.join(tmp, f"r{k}")) for k in range(a.repeat)]
            cpu = statistics.median(r[0] for r in runs)
            wall = statistics.median(r[1] for r in runs)
            split = sorted(runs, key=lambda r: r[1])[len(runs) // 2][2]
            material = element = None
            if use_perf:
                pf = os.path.join(tmp, "perf.data")
                run_once(a.stratum, scene, os.path.join(tmp, "p"), pf)
                sh = perf_shares(pf, kinds)
                material, element = sh["material"], sh["element"]
            row = (scene, cpu, wall, split, material, element)
            rows.append(row)
            print(format_row(row), flush=True)
    text = table(rows, load, a.label, use_perf)
    print(text)
    if not a.no_write:
        write_section(text)


def format_row(row):
    scene, cpu, wall, s, material, element = row
    cells = [f"`{scene}`", f"{cpu:.2f}", f"{wall:.2f}", f"{s['assembly']:.2f} ({s['assemblies']})",
             "-" if material is None else f"{100 * material:.0f} %", "-" if element is None else f"{100 * element:.0f} %",
             f"{s['factorize']:.2f} ({s['factorizations']})", f"{s['solve']:.2f}", f"{s['output']:.2f}"]
    return "| " + " | ".join(cells) + " |"


def table(rows, load, label, use_perf):
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    head = (f"Generated by `tools/benchmarks/profile_scenes.py` on {now}{', ' + label if label else ''}; "
            f"load average {load:.2f} at the start. CPU and wall: medians of the runs of the whole process; "
            "the split is the run's own timers (wall seconds; counts in brackets) of the median run: the "
            "assembly includes the stress updates; the material and element columns are the shares of the "
            "process's CPU samples (`perf record`, 999 Hz, one more run) in the material plugins' and in the "
            "element and contact plugins' libraries" + ("" if use_perf else " (perf not used)") + ".\n\n")
    lines = ["| scene | CPU (s) | wall (s) | assembly (s) | material updates (CPU) | elements (CPU) | "
             "factorize (s) | solve (s) | output (s) |", "|---|---|---|---|---|---|---|---|---|"]
    lines += [format_row(r) for r in rows]
    return head + "\n".join(lines) + "\n"


def write_section(text):
    path = ROOT / "docs" / "benchmarks.md"
    doc = path.read_text()
    begin, end = "<!-- profile_scenes:begin -->", "<!-- profile_scenes:end -->"
    block = f"{begin}\n{text}{end}"
    if begin in doc:
        doc = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda _: block, doc, flags=re.S)
    else:
        doc += "\n## Where the pile scenes' time goes (`profile_scenes.py`, issue 37)\n\n" + block + "\n"
    tmp = path.with_suffix(".md.tmp")
    tmp.write_text(doc)
    tmp.replace(path)


if __name__ == "__main__":
    sys.exit(main())
