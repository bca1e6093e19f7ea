"""Plastic-zone picture of a Stratum run: the integration points coloured by the regime their
model reports (the field "plastic", Material::point_status), one colour per regime, a legend
with each model's own names for its regimes (read from the VTK field data), axes in metres.

    /usr/bin/python3 tools/plastic_zone.py out/hypoelastic --load 60 [-o zone.png]
    /usr/bin/python3 tools/plastic_zone.py out/hill_cylinder --step last

Needs VTK's Python modules and matplotlib (Debian: python3-vtk9, which libvtk9-dev pulls in,
and python3-matplotlib). Use /usr/bin/python3 when another Python is first on PATH.
The ParaView route (tools/plastic_zone_paraview.py, pvpython) uses the same selection and
categories: see tools/README.md.

What it reads from <results>/<stem>_ip_<k>.vtp (written with [output] integration_points =
true, the default) and <stem>_<k>.vtu:
  point data  "plastic" (the code), "domain" (index into the field data "domains"),
              "interface_status" (stick / slip / open of interface points)
  field data  "domains", "plastic_regimes_<domain>" (index = code), "interface_status_names",
              "stage", "step", "load_factor", "head_load_kN", "head_settlement_mm"
  cell data   "domain" of the .vtu: the pile's cells are drawn as a solid, the mesh as lines.

Framing: with a pile (a domain named "pile", or --pile NAME) the window is the pile and
--around pile diameters beside its shaft and --below diameters under its toe (default 4 and 4);
otherwise the whole mesh. --xlim / --ylim (metres) override either.
"""
import argparse
import glob
import math
import os
import sys
import xml.etree.ElementTree as ET

ELASTIC_COLOURS = ["#c9d6e3", "#e8dfc4", "#cfe3c6"]  # pale: below yield (one per model naming)
LINEAR_COLOUR = "#e6e6e6"
UNKNOWN_COLOUR = "#9e9e9e"
# Distinct colours for the yielding / failed regimes (colour-blind friendly order).
REGIME_COLOURS = ["#d62728", "#ff7f0e", "#9467bd", "#2ca02c", "#8c564b", "#e377c2", "#17becf", "#bcbd22",
                  "#1f77b4", "#7f7f7f", "#393b79", "#637939"]
INTERFACE_COLOURS = {"stick": "#1b9e77", "slip": "#e7298a", "open": "#000000"}


def series(results):
    """(ip .pvd, mesh .pvd or None) of a results folder."""
    ip = sorted(glob.glob(os.path.join(results, "*_ip.pvd")))
    if not ip:
        sys.exit(f"plastic_zone: {results}: no *_ip.pvd (run with [output] integration_points = true)")
    stem = ip[0][: -len("_ip.pvd")]
    mesh = stem + ".pvd"
    return ip[0], mesh if os.path.exists(mesh) else None


def datasets(pvd):
    """[(time, file)] of a .pvd, in file order."""
    base = os.path.dirname(pvd)
    return [(float(d.get("timestep")), os.path.join(base, d.get("file")))
            for d in ET.parse(pvd).getroot().iter("DataSet")]


def read(path):
    if path.endswith(".vtp"):
        from vtkmodules.vtkIOXML import vtkXMLPolyDataReader as Reader
    else:
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader as Reader
    r = Reader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


def field_values(data):
    """The field data as {name: value or [strings]}: one-value arrays as scalars."""
    out = {}
    fd = data.GetFieldData()
    for i in range(fd.GetNumberOfArrays()):
        a = fd.GetAbstractArray(i)
        n = a.GetNumberOfValues()
        if a.IsA("vtkStringArray"):
            v = [a.GetValue(k) for k in range(n)]
        else:
            v = [a.GetVariantValue(k).ToDouble() for k in range(n)]
        out[a.GetName()] = v[0] if (n == 1 and not a.GetName().startswith(("plastic_regimes_", "domains",
                                                                              "interface_status_names"))) else v
    return out


def prefixed(fv, prefix):
    """(value, unit) of the field-data value named prefix + unit (head_load_kN, head_load_N, ...)."""
    for name, v in fv.items():
        if name.startswith(prefix):
            return v, name[len(prefix):].replace("_per_", "/")
    return None, ""


def length_unit(fv):
    """The scene's length unit: the second entry of the `units` field data ("N, mm, MPa"), else m."""
    u = fv.get("units")
    return u.split(",")[1].strip() if isinstance(u, str) and u.count(",") == 2 else "m"


def pick(ip_pvd, load=None, step=None):
    """(index, file, field data) of the step to draw: nearest head load to `load` (kN) among the
    steps of the last stage that carries one, else step `step` ("last" or an index)."""
    sets = datasets(ip_pvd)
    if load is not None:
        best = None
        for k, (_, f) in enumerate(sets):
            fv = field_values(read(f))
            h = prefixed(fv, "head_load_")[0]
            if isinstance(h, float) and math.isfinite(h):
                key = (abs(h - load), -k)
                if best is None or key < best[0]:
                    best = (key, k, f, fv)
        if best is None:
            sys.exit("plastic_zone: no step carries a head load (no pile in the scene?): use --step")
        return best[1], best[2], best[3]
    k = len(sets) - 1 if step in (None, "last") else int(step)
    if not 0 <= k < len(sets):
        sys.exit(f"plastic_zone: step {k} outside 0..{len(sets) - 1}")
    return k, sets[k][1], field_values(read(sets[k][1]))


def categories(fv, plastic, domain, interface_status=None):
    """Per point a category label, and the ordered [(label, colour, kind)] of the legend.

    kind: "elastic", "regime", "linear", "interface", "unknown". Labels join domains whose models
    give a code the same name (e.g. "elastic")."""
    domains = fv.get("domains", [])
    regimes = {d: fv.get("plastic_regimes_" + d) for d in domains}
    itf_names = fv.get("interface_status_names") or ["stick", "slip", "open"]
    labels = []
    order = []  # (rank, label, kind)
    seen = {}
    for i in range(len(plastic)):
        d = int(domain[i]) if domain is not None else -1
        name = domains[d] if 0 <= d < len(domains) else ""
        code = int(plastic[i])
        names = regimes.get(name)
        st = int(interface_status[i]) if interface_status is not None else -1
        if st >= 0:
            label = "interface: " + (itf_names[st] if st < len(itf_names) else str(st))
            kind, rank = "interface", (3, st, 0)
        elif names is not None and len(names) == 1:
            label, kind, rank = "linear elastic (" + name + ")", "linear", (4, d, 0)
        elif names is not None and 0 <= code < len(names):
            label = names[code]
            kind, rank = ("elastic", (0, d)) if code == 0 else ("regime", (1, code, d))
        elif code == 0:
            label, kind, rank = "elastic", "elastic", (0, d)
        else:
            label = "not reported" if code < 0 else f"status {code}"
            kind, rank = "unknown", (5, code, 0)
        labels.append(label)
        if label not in seen:
            seen[label] = (rank, kind)
    order = sorted(seen.items(), key=lambda kv: kv[1][0])
    legend, n_regime, n_elastic = [], 0, 0
    for label, (_, kind) in order:
        if kind == "elastic":
            colour = ELASTIC_COLOURS[n_elastic % len(ELASTIC_COLOURS)]
            n_elastic += 1
        elif kind == "linear":
            colour = LINEAR_COLOUR
        elif kind == "interface":
            colour = INTERFACE_COLOURS.get(label.split(": ", 1)[1], "#444444")
        elif kind == "unknown":
            colour = UNKNOWN_COLOUR
        else:
            colour = REGIME_COLOURS[n_regime % len(REGIME_COLOURS)]
            n_regime += 1
        legend.append((label, colour, kind))
    return labels, legend


def write_regime_vtp(data, labels, legend, path):
    """Writes the points of `data` with a point array "regime" (index into `legend`) and the field
    data "regime_names" (the legend's labels): ParaView colours it by category (tools/README.md)."""
    from vtkmodules.vtkCommonCore import vtkIntArray, vtkStringArray
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    index = {label: i for i, (label, _, _) in enumerate(legend)}
    reg = vtkIntArray()
    reg.SetName("regime")
    reg.SetNumberOfTuples(len(labels))
    for i, label in enumerate(labels):
        reg.SetValue(i, index[label])
    data.GetPointData().AddArray(reg)
    names = vtkStringArray()
    names.SetName("regime_names")
    for label, _, _ in legend:
        names.InsertNextValue(label)
    data.GetFieldData().AddArray(names)
    w = vtkXMLPolyDataWriter()
    w.SetFileName(path + ".tmp")
    w.SetInputData(data)
    if w.Write() != 1:
        sys.exit(f"plastic_zone: cannot write {path}")
    os.replace(path + ".tmp", path)


def point_arrays(data):
    from vtkmodules.util.numpy_support import vtk_to_numpy

    pd = data.GetPointData()
    arr = pd.GetArray("plastic")
    if arr is None:
        sys.exit("plastic_zone: the integration points have no field 'plastic'")
    dom = pd.GetArray("domain")
    itf = pd.GetArray("interface_status")
    xyz = vtk_to_numpy(data.GetPoints().GetData())
    return (xyz, vtk_to_numpy(arr), None if dom is None else vtk_to_numpy(dom),
            None if itf is None else vtk_to_numpy(itf))


def mesh_polygons(grid):
    """(polygons [(xs, ys, domain)], domain names) of the .vtu cells through their corner nodes."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    pts = vtk_to_numpy(grid.GetPoints().GetData())
    dom = grid.GetCellData().GetArray("domain")
    polys = []
    for c in range(grid.GetNumberOfCells()):
        cell = grid.GetCell(c)
        ids = []
        for e in range(cell.GetNumberOfEdges()):  # boundary order; a quadratic edge is (a, b, mid)
            edge = cell.GetEdge(e)
            n = edge.GetNumberOfPoints()
            ids += [edge.GetPointId(0)] + ([edge.GetPointId(2)] if n == 3 else [])
        xs = [pts[i, 0] for i in ids]
        ys = [pts[i, 1] for i in ids]
        polys.append((xs, ys, int(dom.GetTuple1(c)) if dom is not None else -1))
    return polys


def pile_box(polys, domains, pile_name):
    """(r_max, y_min, y_max) of the pile cells, or None."""
    names = [pile_name] if pile_name else [d for d in domains if d == "pile"] or \
        [d for d in domains if "pile" in d and "interface" not in d]
    idx = [i for i, d in enumerate(domains) if d in names]
    xs, ys = [], []
    for px, py, d in polys:
        if d in idx:
            xs += px
            ys += py
    if not xs:
        return None, idx
    return (max(xs), min(ys), max(ys)), idx


def mesh_frame(mesh_pvd, k, domains, pile, xyz):
    """What frames the picture of step k (shared with plastic_zone_paraview.py): (the mesh's cells
    as polygons, the pile's box (R, ytoe, ytop) or None, the pile's domain indices, and full =
    (xmin, xmax, ymin, ymax) of the mesh, or of the points xyz when there is no mesh)."""
    polys, box, pile_idx = [], None, []
    if mesh_pvd:
        msets = datasets(mesh_pvd)
        if k < len(msets):
            polys = mesh_polygons(read(msets[k][1]))
            box, pile_idx = pile_box(polys, domains, pile)
    if polys:
        allx = [x for p in polys for x in p[0]]
        ally = [y for p in polys for y in p[1]]
        full = (min(allx), max(allx), min(ally), max(ally))
    else:
        xs, ys = xyz[:, 0], xyz[:, 1]
        full = (float(xs.min()), float(xs.max()), float(ys.min()), float(ys.max()))
    return polys, box, pile_idx, full


def render(a):
    from system_python import require

    require(__file__, ["matplotlib", "vtkmodules"],
            "matplotlib and VTK's Python modules (Debian: python3-matplotlib python3-vtk9)")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection
    from matplotlib.lines import Line2D

    ip_pvd, mesh_pvd = series(a.results)
    k, f, fv = pick(ip_pvd, a.load, a.step)
    data = read(f)
    xyz, plastic, domain, itf = point_arrays(data)
    labels, legend = categories(fv, plastic, domain, itf)
    domains = fv.get("domains", [])
    polys, box, pile_idx, full = mesh_frame(mesh_pvd, k, domains, a.pile, xyz)
    xs, ys = xyz[:, 0], xyz[:, 1]
    if box and not a.full:
        R, ytoe, ytop = box
        D = 2.0 * R
        xlim = (full[0], R + a.around * D)
        ylim = (ytoe - a.below * D, max(ytop, full[3]) + 0.15 * D)
    else:
        pad = 0.02 * max(full[1] - full[0], full[3] - full[2])
        xlim, ylim = (full[0] - pad, full[1] + pad), (full[2] - pad, full[3] + pad)
    if a.xlim:
        xlim = tuple(a.xlim)
    if a.ylim:
        ylim = tuple(a.ylim)
    w, h = xlim[1] - xlim[0], ylim[1] - ylim[0]
    plot_h = 8.0 if h > 1.5 * w else 6.5
    plot_w = min(max(plot_h * w / h, 2.5), 9.0)
    W, H = plot_w + 4.2, plot_h + 1.5
    fig = plt.figure(figsize=(W, H), dpi=a.dpi)
    ax = fig.add_axes([0.8 / W, 0.65 / H, plot_w / W, plot_h / H])
    if polys:
        ax.add_collection(PolyCollection([list(zip(p[0], p[1])) for p in polys], facecolors="none",
                                         edgecolors="#b0b0b0", linewidths=0.35, zorder=1))
        pile = [list(zip(p[0], p[1])) for p in polys if p[2] in pile_idx]
        if pile:
            ax.add_collection(PolyCollection(pile, facecolors="#8a8a8a", edgecolors="#555555", linewidths=0.5,
                                             zorder=2))
    inside = (xs >= xlim[0]) & (xs <= xlim[1]) & (ys >= ylim[0]) & (ys <= ylim[1])
    n_in = max(int(inside.sum()), 1)
    # Marker area so that the points about tile the window (points^2 of the plot area / count).
    size = max(1.5, min(40.0, 0.18 * (plot_w * 72) * (plot_h * 72) / n_in))
    handles = []
    for label, colour, kind in legend:
        sel = [i for i, l in enumerate(labels) if l == label]
        if not sel:
            continue
        pile_point = kind in ("linear",) and domain is not None and int(domain[sel[0]]) in pile_idx
        if pile_point:
            continue  # the pile is drawn as a solid
        marker = "s" if kind == "interface" else "o"
        z = 3 if kind in ("elastic", "linear", "unknown") else 4
        ax.scatter(xs[sel], ys[sel], s=size * (1.6 if kind == "interface" else 1.0), c=colour, marker=marker,
                   edgecolors="none", zorder=z)
        count = int(sum(1 for i in sel if inside[i]))
        if count == 0:
            continue
        handles.append(Line2D([], [], ls="", marker=marker, markersize=8, markerfacecolor=colour,
                              markeredgecolor="#555555", markeredgewidth=0.4, label=f"{label} ({count})"))
    if pile_idx and box:
        handles.append(Line2D([], [], ls="", marker="s", markersize=9, markerfacecolor="#8a8a8a",
                              markeredgecolor="#555555", label="pile (" + ", ".join(domains[i] for i in pile_idx) + ")"))
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.set_aspect("equal", adjustable="box")
    pile_scene = box is not None
    lu = length_unit(fv)
    ax.set_xlabel(a.xlabel or (f"r: distance from the pile axis ({lu})" if pile_scene else f"x ({lu})"))
    ax.set_ylabel(a.ylabel or (f"z: elevation, ground at 0 ({lu})" if pile_scene else f"y ({lu})"))
    ax.grid(True, color="#dddddd", linewidth=0.5, zorder=0)
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False,
              title="regime (integration points in view)", title_fontsize=8, alignment="left")
    stem = os.path.basename(ip_pvd)[: -len("_ip.pvd")]
    parts = [f"stage '{fv.get('stage', '?')}'", f"step {int(fv.get('step', k))}",
             f"load factor {fv.get('load_factor', float('nan')):.3g}"]
    (hl, hlu), (hs, hsu) = prefixed(fv, "head_load_"), prefixed(fv, "head_settlement_")
    if isinstance(hl, float) and math.isfinite(hl):
        parts.append(f"head load {hl:.1f} {hlu}")
    if isinstance(hs, float) and math.isfinite(hs):
        parts.append(f"settlement {hs:.2f} {hsu}")
    fig.text(0.1 / W, 1 - 0.3 / H, a.title or f"{stem}: plastic zone", fontsize=11, fontweight="bold", ha="left",
             va="center")
    fig.text(0.1 / W, 1 - 0.6 / H, ", ".join(parts), fontsize=9, ha="left", va="center")
    for x0, y0, x1, y1, text in a.line or []:
        ax.plot([float(x0), float(x1)], [float(y0), float(y1)], color="black", lw=4, solid_capstyle="butt", zorder=6)
        handles.append(Line2D([], [], color="black", lw=4, label=text))
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False,
                  title="regime (integration points in view)", title_fontsize=8, alignment="left")
    for r, text in a.arc or []:
        import numpy as np

        t = np.linspace(0.0, 2.0 * np.pi, 721)
        ax.plot(float(r) * np.cos(t), float(r) * np.sin(t), ls="--", color="black", lw=1.0, zorder=5)
        handles.append(Line2D([], [], ls="--", color="black", lw=1.0, label=text))
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False,
                  title="regime (integration points in view)", title_fontsize=8, alignment="left")
    if a.vtp:
        write_regime_vtp(data, labels, legend, os.path.join(a.results, f"plastic_zone_{k}.vtp"))
    out = a.output or os.path.join(a.results, f"plastic_zone_{k}.png")
    tmp = out + ".tmp.png"
    fig.savefig(tmp)
    os.replace(tmp, out)
    print(f"plastic_zone: step {k} ({', '.join(parts)}) -> {out}")


def arguments(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", help="the run's output folder, e.g. out/hypoelastic")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--load", type=float, help="draw the step whose head load (kN) is nearest to this")
    g.add_argument("--step", default=None, help="draw output step N (0 = initial state) or 'last' (default)")
    ap.add_argument("-o", "--output", help="PNG file (default <results>/plastic_zone_<step>.png)")
    ap.add_argument("--pile", help="the pile's domain name (default: 'pile', else a domain named *pile*)")
    ap.add_argument("--around", type=float, default=4.0, help="pile diameters shown beside the shaft (4)")
    ap.add_argument("--below", type=float, default=4.0, help="pile diameters shown below the toe (4)")
    ap.add_argument("--full", action="store_true", help="show the whole mesh")
    ap.add_argument("--xlim", type=float, nargs=2, metavar=("MIN", "MAX"), help="horizontal window (m)")
    ap.add_argument("--ylim", type=float, nargs=2, metavar=("MIN", "MAX"), help="vertical window (m)")
    ap.add_argument("--title", help="title (default: '<scene>: plastic zone')")
    ap.add_argument("--xlabel")
    ap.add_argument("--ylabel")
    ap.add_argument("--dpi", type=int, default=150)
    ap.add_argument("--line", nargs=5, action="append", metavar=("X0", "Y0", "X1", "Y1", "LABEL"),
                    help="draw a thick line (m), e.g. a footing")
    ap.add_argument("--arc", nargs=2, action="append", metavar=("R", "LABEL"),
                    help="draw a dashed circle of radius R (m) about the origin, e.g. a closed-form plastic radius")
    ap.add_argument("--vtp", action="store_true",
                    help="also write <results>/plastic_zone_<step>.vtp with the point array 'regime' for ParaView")
    return ap.parse_args(argv)


if __name__ == "__main__":
    render(arguments())
