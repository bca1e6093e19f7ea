#!/usr/bin/env python3
"""Work-precision of the loess pile scenes, and what "do only what the scene needs" saves.

Runs `stratum run` on variants of inputs/loess_pile/{hypoelastic,cap}.toml (load-step count,
global solver, Duncan-Chang update, convergence tolerance), loads the head only up to the
quantity-of-interest load and compares the head settlement there with a reference run of
1000 load increments and force_rtol = 1e-7. Prints each table as it goes and rewrites the
section <!-- bench_pile:begin --> ... <!-- bench_pile:end --> of docs/benchmarks.md
(temporary file + rename) after each part (pile scenes, footing, profile), so that a run stopped
early keeps what it finished. Wall times are medians of --repeat runs of the whole process; a
run that takes longer than LONG seconds is not repeated (its noise is small against its length,
and the full footing matrix would otherwise take hours).

Usage: tools/benchmarks/bench_pile.py [--stratum EXE] [--repeat K] [--quick] [--no-write]
"""
import argparse
import datetime
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
# Quantity of interest: the head settlement at 105 kN (the plan's load) for the cap scene, which
# reaches it; the Duncan-Chang scene fails at about 74 kN (docs/validation/loess_pile.md), so its
# settlement is taken at 45 kN, a load it reaches with any step count (a 200-step run to 60 kN
# fails just short of it).
QOI = {"hypoelastic": 45.0, "cap": 105.0}
TIMEOUT = 600.0  # s per stratum run; --quick: 240
LONG = 20.0  # s: a run longer than this is not repeated


def scene_text(name, steps, force, solver="newton", update=None, rtol=None, vtk=True):
    """The scene inputs/loess_pile/<name>.toml with the loading stage's steps and force replaced,
    and optionally another solver, Duncan-Chang update or cap integrator, force tolerance, no VTK.
    The text is run from a temporary folder, so its includes are made absolute."""
    folder = ROOT / "inputs" / "loess_pile"
    t = (folder / f"{name}.toml").read_text()
    t = re.sub(r'(?m)^(\s*)"([^"\n]+\.toml)"', lambda m: f'{m.group(1)}"{(folder / m.group(2)).resolve()}"', t)
    t = re.sub(r"(?m)^steps = \d+ .*$|^steps = (60|10)\s*(#.*)?$", f"steps = {steps}", t)
    t = re.sub(r"(?m)^force = 150\.0", f"force = {force}", t)
    t = re.sub(r'(?m)^solver = "newton"', f'solver = "{solver}"', t)
    if solver != "newton":  # the [solver] table holds newton's parameters: drop it whole
        t = re.sub(r"(?ms)^\[solver\]\n.*?(?=^\[)", "", t)
    if update and name == "cap":  # the cap's integrator, in the included material set
        assert not re.search(r"(?m)^\[materials\.loess\]", t), "cap.toml: [materials.loess] is written out"
        t += f'\n[materials.loess]\nintegrator = "{update}"\n'
    elif update:
        t = re.sub(r'(?m)^update = "explicit".*$', f'update = "{update}"', t)
        if update != "explicit":  # keeping branch decisions belongs to the explicit update
            t = re.sub(r"(?m)^branch_iteration = .*\n", "", t)
    if rtol:
        t = re.sub(r"(?m)^force_rtol = .*$", f"force_rtol = {rtol}", t)
    if not vtk:
        t = re.sub(r"(?m)^vtk = true", "vtk = false", t)
        t = re.sub(r"(?m)^integration_points = true", "integration_points = false", t)
    return t


def run(exe, text, repeat=1, timeout=None):
    """Runs a scene; returns (ok, settlement curve, median wall s, profile line, message)."""
    walls, out = [], ""
    timeout = timeout or TIMEOUT
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "pile.toml"
        p.write_text(text)
        for _ in range(repeat):
            t0 = time.perf_counter()
            try:
                r = subprocess.run([exe, "run", str(p), "--out", str(Path(d) / "out")], capture_output=True,
                                   text=True, timeout=timeout,
                                   env=dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1"))
            except subprocess.TimeoutExpired:
                return False, [], time.perf_counter() - t0, "", f"timeout after {timeout:.0f} s"
            walls.append(time.perf_counter() - t0)
            out = r.stdout
            if r.returncode != 0:
                msg = (r.stderr.strip() or out).replace(str(p), "scene.toml").splitlines()
                return False, [], statistics.median(walls), "", (msg[-1] if msg else "")[:220]
            if walls[-1] > LONG:
                break
        curve = []
        csv = Path(d) / "out" / "curves" / "load_settlement.csv"
        if csv.exists():
            for line in csv.read_text().splitlines()[1:]:
                a, b = line.split(",")
                curve.append((float(a), float(b)))
    prof = next((l for l in out.splitlines() if l.startswith("time:")), "")
    stopped = next((l for l in out.splitlines() if l.startswith("stopped:")), "")
    note = ""
    if stopped:  # where and why the run ended before its load: the last converged level, the reason
        reason = stopped[len("stopped:"):].split("(")[0].strip()
        note = f"stopped at {curve[-1][0]:.4g} (last converged load): {reason}" if curve else f"stopped: {reason}"
    return True, curve, statistics.median(walls), prof, note


def at_load(curve, load):
    for (p0, s0), (p1, s1) in zip(curve, curve[1:]):
        if p0 <= load <= p1 and p1 > p0:
            return s0 + (s1 - s0) * (load - p0) / (p1 - p0)
    return float("nan")


def table(head, rows):
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    text = "\n".join(lines)
    print(text, flush=True)
    return text


def write_section(md, pending, no_write, name="bench_pile"):
    """Rewrites the section `name` of docs/benchmarks.md with the parts done so far."""
    if no_write:
        return
    parts = md + ([f"*This regeneration has not yet run: {', '.join(pending)}.*\n"] if pending else [])
    docs = ROOT / "docs" / "benchmarks.md"
    old = docs.read_text()
    begin, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
    block = f"{begin}\n" + "\n".join(parts) + f"\n{end}"
    if begin in old:
        new = old[: old.index(begin)] + block + old[old.index(end) + len(end):]
    else:
        new = old.rstrip("\n") + "\n\n" + block + "\n"
    tmp = docs.with_suffix(".md.tmp")
    tmp.write_text(new)
    tmp.replace(docs)
    print(f"wrote {docs}" + (f" (not yet run: {', '.join(pending)})" if pending else ""), flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--stratum", default=str(ROOT / "build" / "release" / "bin" / "stratum"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--quick", action="store_true", help="fewer variants, reference of 200 steps")
    ap.add_argument("--no-write", action="store_true")
    a = ap.parse_args()
    global TIMEOUT
    if a.quick:
        TIMEOUT = 240.0
    if not Path(a.stratum).exists():
        sys.exit(f"bench_pile: {a.stratum} not found: build first (tools/bench)")
    md = []
    stamp = datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC")
    load = os.getloadavg()[0]
    md.append("## The loess pile: work-precision, profile, what is skipped (`bench_pile.py`)\n")
    md.append(f"Generated by `tools/benchmarks/bench_pile.py` on {stamp}, load average {load:.2f} at the start; "
              f"wall times are medians of {a.repeat} runs of the whole `stratum run` process (TOML to "
              f"curves, VTK and checkpoints; a run longer than {LONG:.0f} s once), OPENBLAS_NUM_THREADS = "
              "OMP_NUM_THREADS = 1, the element loop on all cores (the scenes' default).\n")
    ref_steps = 200 if a.quick else 1000

    # ---- work-precision
    for name in ("hypoelastic", "cap"):
        Q = QOI[name]
        ok, ref, ref_wall, _, msg = run(a.stratum, scene_text(name, ref_steps, Q, rtol="1e-7", vtk=False))
        w_ref = at_load(ref, Q) if ok else float("nan")
        print(f"{name}: reference ({ref_steps} steps to {Q} kN, force_rtol 1e-7): w = {w_ref:.5f} mm, "
              f"{ref_wall:.1f} s {msg}", flush=True)
        md.append(f"### Work-precision: {name} scene, head settlement at {Q:g} kN\n")
        md.append(f"VTK output is off in these runs (its cost is in the profile below). "
                  f"Reference: {ref_steps} equal load steps to {Q:g} kN with force_rtol = 1e-7: "
                  f"**w = {w_ref:.5f} mm** ({ref_wall:.1f} s). Each row loads the head to {Q:g} kN in the "
                  "given number of equal steps; *error* = |w - w_ref| / w_ref. The cap scene is measured at "
                  "105 kN, the Duncan-Chang scene at 45 kN: it fails at about 74 kN (its Class-A record), "
                  "before 105 kN.\n")
        steps_list = [2, 6, 24] if a.quick else [2, 4, 8, 24, 48]
        variants = []
        # the other updates / integrators, each at the step counts given (they are slower or fail)
        updates = ["explicit", "incremental", "recovery"] if name == "hypoelastic" else [None, "sandler_rubin"]
        for rtol in (["1e-5"] if a.quick else ["1e-3", "1e-5", "1e-7"]):
            for n in steps_list:
                variants.append(("newton", updates[0], rtol, n))
        for upd in updates[1:]:  # substepped or thesis algorithms, ~10x per step or failing: two counts
            for n in steps_list[1:3]:
                variants.append(("newton", upd, "1e-5", n))
        for solver in ["modified_newton", "kinsol"]:
            for n in steps_list:
                variants.append((solver, updates[0], "1e-5", n))
        rows = []
        for solver, upd, rtol, n in variants:
            ok, curve, wall, prof, msg = run(a.stratum, scene_text(name, n, Q, solver, upd, rtol, vtk=False), a.repeat)
            w = at_load(curve, Q) if ok else float("nan")
            err = abs(w - w_ref) / w_ref if ok and w == w else float("nan")
            iters = re.search(r"\((\d+)\), linear", prof)
            rows.append([solver, upd or "closest_point", rtol, n, f"{w:.4f}" if w == w else "-",
                         f"{err:.1e}" if err == err else "failed", f"{wall:.2f}",
                         iters.group(1) if iters else "-", msg or ""])
            print(rows[-1], flush=True)
        md.append(table(["solver", "update / integrator", "force_rtol", "steps", "w (mm)", "error",
                         "wall (s)", "assemblies", "note"], rows) + "\n")

    write_section(md, ["the strip footing", "the profile"], a.no_write)

    # ---- the strip footing (catalogue P4): footing load at a settlement of 0.06 m (3 % of B)
    def footing(steps, solver="newton", integrator="closest_point", rtol="1e-8"):
        t = (ROOT / "inputs" / "verification" / "strip_footing.toml").read_text()
        t = re.sub(r"(?m)^steps = 30\n", "", t)
        t = re.sub(r'\[\[constraints\]\]\nnodes = "foot.top".*\nuy = -0.06.*\n', "", t)
        t = re.sub(r'(?m)^integrator = "closest_point"', f'integrator = "{integrator}"', t)
        t = re.sub(r"(?m)^force_rtol = .*$", f"force_rtol = {rtol}", t)
        t = re.sub(r'(?m)^solver = "newton"', f'solver = "{solver}"', t)
        if solver != "newton":
            t = re.sub(r"(?m)^\[solver\][^\n]*\nline_search = \d+[^\n]*\n(#[^\n]*\n|\s+#[^\n]*\n)*", "", t)
            t = t.replace("[analysis]\n", f'[analysis]\nsolver = "{solver}"\n', 1)
        t += (f'\n[output]\nvtk = false\n[[stages]]\nname = "footing"\nsteps = {steps}\n[[stages.actions]]\n'
              'type = "load"\ncells = "foot"\nsettlement = 0.06\n')
        return t

    fsteps = [10, 30] if a.quick else [5, 10, 30, 100]
    ok, ref, ref_wall, _, msg = run(a.stratum, footing(200 if a.quick else 1000, rtol="1e-10"))
    P_ref = ref[-1][0] if ok and ref else float("nan")
    print(f"footing: reference P = {P_ref:.5f} kN/m, {ref_wall:.1f} s {msg}", flush=True)
    md.append("### Work-precision: strip footing, footing load at 0.06 m settlement\n")
    md.append(f"`inputs/verification/strip_footing.toml` (von Mises, catalogue P4) with the footing pushed "
              f"down 0.06 m by a head-displacement `load` action; quantity: the footing load P (kN/m, half "
              f"footing) at the end. Reference: {200 if a.quick else 1000} steps, closest_point, force_rtol "
              f"1e-10: **P = {P_ref:.4f} kN/m** ({ref_wall:.1f} s; (2 + pi) k B/2 = 514.16).\n")
    rows = []
    # Newton with the two integrators that return an algorithmic tangent over steps and tolerances;
    # the explicit integrators (no consistent tangent: Newton needs 100-200 s per run and often
    # fails, see the stability matrix) once each at 30 steps; the other solvers with closest_point.
    fvariants = [("newton", i, r, n) for i in ["closest_point", "cutting_plane"]
                 for r in (["1e-8"] if a.quick else ["1e-4", "1e-8"]) for n in fsteps]
    if not a.quick:
        fvariants += [("newton", i, "1e-4", 30) for i in ["modified_euler", "midpoint"]]
    fvariants += [(sv, "closest_point", "1e-8", n) for sv in ["modified_newton", "kinsol"]
                  for n in (fsteps[-1:] if a.quick else [10, 30])]
    for solver, integ, rtol, n in fvariants:
        ok, curve, wall, prof, msg = run(a.stratum, footing(n, solver, integ, rtol), a.repeat)
        P = curve[-1][0] if ok and curve and abs(curve[-1][1] - 60.0) < 1e-6 else float("nan")
        err = abs(P - P_ref) / P_ref if P == P else float("nan")
        iters = re.search(r"\((\d+)\), linear", prof)
        rows.append([solver, integ, rtol, n, f"{P:.3f}" if P == P else "-", f"{err:.1e}" if err == err else "failed",
                     f"{wall:.2f}", iters.group(1) if iters else "-", msg or ""])
        print(rows[-1], flush=True)
    md.append(table(["solver", "integrator", "force_rtol", "steps", "P (kN/m)", "error", "wall (s)",
                     "assemblies", "note"], rows) + "\n")

    write_section(md, ["the profile"], a.no_write)

    # ---- profile and skipped work of the default scene (shortened to the field's first 4 increments)
    md.append("### Profile of the pile scene and what skipping saves\n")
    md.append("The default Duncan-Chang scene with the head loaded to 60 kN in 24 steps of 2.5 kN (the part "
              "of the curve before failure; the full run to failure is in `docs/validation/loess_pile.md`). "
              "`stratum run` prints the split of its time (assembly includes the material updates).\n")
    rows = []
    base = scene_text("hypoelastic", 24, 60.0)
    for label, text in [("default (VTK with integration points each step)", base),
                        ("no VTK output", scene_text("hypoelastic", 24, 60.0, vtk=False)),
                        ("linear_solver = umfpack (before the auto rule)",
                         base.replace('linear_solver = "auto"', 'linear_solver = "umfpack"')),
                        ("linear cells' stiffness at every assembly (reuse_linear_stiffness = false)",
                         base.replace('linear_solver = "auto"',
                                      'linear_solver = "auto"\nreuse_linear_stiffness = false')),
                        ("symbolic analysis before every factorization (reuse_symbolic = false)",
                         base.replace('linear_solver = "auto"',
                                      'linear_solver = "auto"\nreuse_symbolic = false')),
                        ("element loop on one thread (threads = 1; default: all cores)",
                         base.replace('linear_solver = "auto"', 'linear_solver = "auto"\nthreads = 1')),
                        ("modified_newton (factorization reused in a step)",
                         scene_text("hypoelastic", 24, 60.0, solver="modified_newton"))]:
        ok, curve, wall, prof, msg = run(a.stratum, text, a.repeat)
        rows.append([label, f"{wall:.2f}", prof.replace("time: ", "").replace("|", "/") or msg])
        print(rows[-1], flush=True)
    md.append(table(["variant", "wall (s)", "split printed by stratum run"], rows) + "\n")
    lib = subprocess.run([a.stratum, "check", "inputs/loess_pile/hypoelastic.toml"], cwd=ROOT,
                         capture_output=True, text=True).stdout.strip()
    libraries = len(list((Path(a.stratum).resolve().parents[1] / "plugins").glob("*.so")))

    def process_ms(args):  # median wall time of a short stratum command, 15 runs
        ts = []
        for _ in range(15):
            t0 = time.perf_counter()
            subprocess.run([a.stratum] + args, cwd=ROOT, capture_output=True)
            ts.append(time.perf_counter() - t0)
        return 1e3 * statistics.median(ts)

    none_ms, all_ms = process_ms(["--version"]), process_ms(["plugins"])
    opened = re.search(r"(\d+) plugin librar", lib)
    opened = int(opened.group(1)) if opened else 0
    md.append(f"Plugins opened on demand: `stratum check` of the scene reports *{lib}*; the build has "
              f"{libraries} plugin libraries, the rest are never opened. Opening all of them costs "
              f"{all_ms - none_ms:.1f} ms (`stratum plugins`, which opens every library, {all_ms:.1f} ms, "
              f"against `stratum --version`, which opens none, {none_ms:.1f} ms; medians of 15), so the "
              f"libraries the scene does not open would cost about "
              f"{(all_ms - none_ms) * (1 - opened / max(libraries, 1)):.1f} ms: the on-demand rule matters for "
              "start-up and for not failing on a plugin the scene does not use, not for run time. The "
              "symbolic factorization is done once per stage (the `analyze` count above equals the number "
              "of stages; the reuse_symbolic = false row analyses before every factorization).\n")

    write_section(md, [], a.no_write)


if __name__ == "__main__":
    main()
