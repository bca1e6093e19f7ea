#!/usr/bin/python3
"""Runs scenes with two stratum programs and compares their results exactly.

    tools/compare_runs.py BEFORE_BIN AFTER_BIN WORKDIR SCENE.toml ...
    tools/compare_runs.py BEFORE_DIR AFTER_BIN WORKDIR SCENE.toml ...

For each scene both programs run `stratum run SCENE --out WORKDIR/{before,after}/NAME`; then
every file of the two result folders is compared. When the first argument is a folder, it holds
results kept from an earlier run (BEFORE_DIR/NAME, e.g. the `after` folder of a comparison made
when the previous change landed): only the after program runs, and its exit status is compared
with 0. Compared:
  * CSV files (curves, recorders, diagnostics): cell by cell, as text, except the columns whose
    name says they hold a time measured on the clock (wall, cpu, seconds of the run);
  * VTK files (.vtu, .vtp): every point, cell and field data array, value by value (bitwise, NaN
    equal to NaN), and the points and cells;
  * summary.toml and other text: line by line, except the lines of measured times;
  * checkpoints (*.ckpt) are left out: they record the digests of the plugin libraries the run
    opened, which differ between two builds by design (docs/design.md, checkpoints).
Both programs run with one BLAS thread (OMP_NUM_THREADS=OPENBLAS_NUM_THREADS=1, as tools/setup.sh
sets for the tests): CHOLMOD's supernodal factorization calls the BLAS, and with two threads its
sums are split differently, which moves the solution in the last bits (1e-15 relative).
Prints one line per scene (identical, or the first differences) and exits 1 when any differs or
a run fails differently. Needs python3-vtk9 for the VTK files.
"""
import csv
import math
import os
import subprocess
import sys

TIME_WORDS = ("wall", "cpu_", "_s]", "seconds", "time_s", "elapsed", "date")


def is_time_column(name):
    n = name.lower()
    return any(w in n for w in TIME_WORDS)


def compare_csv(a, b):
    with open(a, newline="") as fa, open(b, newline="") as fb:
        ra, rb = list(csv.reader(fa)), list(csv.reader(fb))
    if len(ra) != len(rb):
        return [f"{len(ra)} rows against {len(rb)}"]
    header = ra[0] if ra else []
    skip = {i for i, h in enumerate(header) if is_time_column(h)}
    out = []
    for k, (x, y) in enumerate(zip(ra, rb)):
        if len(x) != len(y):
            out.append(f"row {k}: {len(x)} columns against {len(y)}")
            continue
        for i, (u, v) in enumerate(zip(x, y)):
            if i not in skip and u != v:
                out.append(f"row {k} column {header[i] if i < len(header) else i}: {u} against {v}")
                break
        if len(out) > 3:
            break
    return out


def vtk_arrays(path):
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    r = vtk.vtkXMLUnstructuredGridReader() if path.endswith(".vtu") else vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    d = r.GetOutput()
    arrays = {"points": vtk_to_numpy(d.GetPoints().GetData()) if d.GetPoints() else None}
    for kind, data in (("point", d.GetPointData()), ("cell", d.GetCellData()), ("field", d.GetFieldData())):
        for i in range(data.GetNumberOfArrays()):
            arr = data.GetAbstractArray(i)
            name = f"{kind}:{arr.GetName()}"
            if arr.IsA("vtkStringArray"):
                arrays[name] = [arr.GetValue(j) for j in range(arr.GetNumberOfValues())]
            else:
                arrays[name] = vtk_to_numpy(arr)
    if path.endswith(".vtu"):
        arrays["cells"] = vtk_to_numpy(d.GetCells().GetData()) if d.GetCells() else None
        arrays["types"] = [d.GetCellType(i) for i in range(d.GetNumberOfCells())]
    return arrays


def same_values(x, y):
    import numpy as np

    if x is None or y is None:
        return x is None and y is None
    if isinstance(x, list) or isinstance(y, list):
        return list(x) == list(y)
    x, y = np.asarray(x), np.asarray(y)
    if x.shape != y.shape:
        return False
    if x.dtype.kind == "f":
        return bool(np.all((x == y) | (np.isnan(x) & np.isnan(y))))
    return bool(np.array_equal(x, y))


def compare_vtk(a, b):
    xa, xb = vtk_arrays(a), vtk_arrays(b)
    out = []
    if set(xa) != set(xb):
        out.append(f"arrays {sorted(set(xa) ^ set(xb))} in one file only")
    for k in sorted(set(xa) & set(xb)):
        if not same_values(xa[k], xb[k]):
            out.append(f"array {k} differs")
    return out


def compare_text(a, b):
    la = [l for l in open(a).read().splitlines() if not is_time_column(l.split("=")[0])]
    lb = [l for l in open(b).read().splitlines() if not is_time_column(l.split("=")[0])]
    for k, (x, y) in enumerate(zip(la, lb)):
        if x != y:
            return [f"line {k + 1}: {x!r} against {y!r}"]
    return [] if len(la) == len(lb) else [f"{len(la)} lines against {len(lb)}"]


def compare_dirs(da, db):
    problems, files = [], 0
    for root, _, names in os.walk(da):
        for n in sorted(names):
            pa = os.path.join(root, n)
            rel = os.path.relpath(pa, da)
            pb = os.path.join(db, rel)
            if n.endswith(".ckpt"):
                continue
            if not os.path.exists(pb):
                problems.append(f"{rel}: only before")
                continue
            files += 1
            if n.endswith(".csv"):
                p = compare_csv(pa, pb)
            elif n.endswith((".vtu", ".vtp")):
                p = compare_vtk(pa, pb)
            elif n.endswith((".toml", ".txt", ".pvd")):
                p = compare_text(pa, pb)
            else:
                p = [] if open(pa, "rb").read() == open(pb, "rb").read() else ["bytes differ"]
            problems += [f"{rel}: {x}" for x in p]
    for root, _, names in os.walk(db):
        for n in names:
            rel = os.path.relpath(os.path.join(root, n), db)
            if not os.path.exists(os.path.join(da, rel)):
                problems.append(f"{rel}: only after")
    return files, problems


def main():
    if len(sys.argv) < 5:
        print(__doc__, file=sys.stderr)
        return 2
    before, after, work = sys.argv[1:4]
    status = 0
    for scene in sys.argv[4:]:
        name = os.path.splitext(os.path.basename(scene))[0]
        codes = []
        kept = os.path.isdir(before)
        runs = (("after", after),) if kept else (("before", before), ("after", after))
        if kept:
            codes.append(0)
        for label, binary in runs:
            out = os.path.join(work, label, name)
            subprocess.run(["rm", "-rf", out])
            env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
            r = subprocess.run([binary, "run", scene, "--out", out], capture_output=True, text=True, env=env)
            codes.append(r.returncode)
        before_dir = os.path.join(before, name) if kept else os.path.join(work, "before", name)
        files, problems = compare_dirs(before_dir, os.path.join(work, "after", name))
        if codes[0] != codes[1]:
            problems.insert(0, f"exit status {codes[0]} against {codes[1]}")
        if problems:
            status = 1
            print(f"DIFFERS {scene} (exit {codes[0]}/{codes[1]}, {files} files): " + "; ".join(problems[:4]))
        else:
            print(f"identical {scene} (exit {codes[0]}, {files} files)")
    return status


if __name__ == "__main__":
    sys.exit(main())
