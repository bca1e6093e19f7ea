#!/usr/bin/env python3
"""Excess pore pressure around a pile: filled contours of the node field `p` of a run's VTK series.

usage: tools/plot_pore_pressure.py RESULTS.pvd --time T [--time T2 ...] [--window R DEPTH] -o FIG.png

One panel per requested analysis time (the ParaView time of the series: one unit per static
stage, seconds in consolidation stages; docs/groundwater.md, "Time"), the dataset nearest to it.
`p` lives on the corner nodes of the porous cells (quad8p4, tri6p3); each cell is drawn through
its corners, split into two triangles, with p interpolated linearly, as the element does. The
cells of the domain --solid (default: pile) and those without p are drawn grey. Axisymmetric
results: x = r, y = z.
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from system_python import require  # noqa: E402


def datasets(pvd):
    root = ET.parse(pvd).getroot()
    folder = os.path.dirname(os.path.abspath(pvd))
    return [(float(d.get("timestep")), os.path.join(folder, d.get("file"))) for d in root.iter("DataSet")]


def read(path):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    xy = vtk_to_numpy(g.GetPoints().GetData())[:, :2]
    # the node field of the pore pressure, named with its unit ("p [kPa]", "p [MPa]" in N, mm)
    pd = g.GetPointData()
    names = [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())]
    name = next((n for n in names if n.startswith("p [")), None)
    if name is None:
        sys.exit(f"plot_pore_pressure: {path} has no node field 'p [<unit>]' (no porous cells)")
    p = vtk_to_numpy(pd.GetArray(name))
    cells = [[g.GetCell(c).GetPointId(i) for i in range(4)] for c in range(g.GetNumberOfCells())]
    domain = g.GetCellData().GetArray("domain")
    names = g.GetFieldData().GetAbstractArray("domains")
    names = [names.GetValue(i) for i in range(names.GetNumberOfValues())] if names else []
    cell_domain = [names[int(domain.GetValue(c))] if domain and int(domain.GetValue(c)) < len(names) else ""
                   for c in range(len(cells))]
    return xy, p, cells, cell_domain, name[3:-1]


def main():
    require(__file__, ["numpy", "matplotlib", "vtkmodules"], "python3-numpy python3-matplotlib python3-vtk9")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.tri as mtri
    import numpy as np

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("pvd")
    ap.add_argument("--time", type=float, action="append", required=True)
    ap.add_argument("--label", action="append", default=[], help="panel title, one per --time")
    ap.add_argument("--window", type=float, nargs=2, default=None, metavar=("R", "DEPTH"))
    ap.add_argument("--solid", default="pile", help="domain drawn grey (default: pile)")
    ap.add_argument("-o", "--output", required=True)
    a = ap.parse_args()
    series = datasets(a.pvd)
    fig, axes = plt.subplots(1, len(a.time), figsize=(4.2 * len(a.time), 6), squeeze=False)
    levels = None
    for k, t in enumerate(a.time):
        tk, path = min(series, key=lambda d: abs(d[0] - t))
        xy, p, cells, cell_domain, unit = read(path)
        tris, grey = [], []
        for c, dom in zip(cells, cell_domain):
            if dom == a.solid:
                grey.append(c)
            elif all(np.isfinite(p[i]) for i in c):
                tris += [[c[0], c[1], c[2]], [c[0], c[2], c[3]]]
            else:
                grey.append(c)
        tri = mtri.Triangulation(xy[:, 0], xy[:, 1], np.array(tris))
        pv = np.nan_to_num(p)
        if levels is None:
            top = max(1.0, float(np.nanmax(np.abs(p))))
            levels = np.linspace(-top, top, 25)
        ax = axes[0][k]
        cs = ax.tricontourf(tri, pv, levels=levels, cmap="RdBu_r", extend="both")
        for c in grey:
            ax.fill(xy[c, 0], xy[c, 1], color="0.6", lw=0)
        ax.set_aspect("equal")
        if a.window:
            ax.set_xlim(0, a.window[0])
            ax.set_ylim(-a.window[1], 0)
        ax.set_xlabel("r (m)")
        ax.set_ylabel("z (m)")
        title = a.label[k] if k < len(a.label) else f"time {tk:g}"
        ax.set_title(f"{title}\nmax p = {np.nanmax(p):.1f} {unit}, min p = {np.nanmin(p):.1f} {unit}", fontsize=9)
    fig.colorbar(cs, ax=axes[0].tolist(), label=f"excess pore pressure p ({unit}, compression +)", shrink=0.8)
    fig.savefig(a.output, dpi=110, bbox_inches="tight")
    print(f"wrote {a.output}")


if __name__ == "__main__":
    main()
