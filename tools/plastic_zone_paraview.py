"""The plastic-zone picture in ParaView (pvbatch / pvpython).

    pvbatch tools/plastic_zone_paraview.py out/hypoelastic --load 60 [-o zone.png]
    pvpython tools/plastic_zone_paraview.py out/hypoelastic --load 60 --show

Same step selection, categories, colours and framing as tools/plastic_zone.py (imported from
beside this file). Two kinds of files:

- <results>/plastic_zone_<step>.vtp: all integration points of the step with a point array
  "regime" (a category index) whose names are the field data "regime_names"; it opens in the
  ParaView GUI (colour by "regime", "Interpret Values As Categories", tools/README.md).
- for the picture, small files in a temporary folder (removed at the end): the mesh edges and
  the pile cut to the window (lines and polygons), the soil and the interface points inside it.
  Everything drawn lies inside the window, so ParaView's axes grid spans exactly the window (r
  and z in the scene's length unit) and the camera frames it: the window on the left, the
  legend (a categorical colour bar with the models' own regime names and the number of points
  of each in view) on its right.

--show keeps the render window open (pvpython with a display); without it the view is saved
as a PNG.

Which ParaView: written against paraview.simple of 5.10-5.11 (with fallbacks for older
spellings of the window locations) and run in Debian 12's ParaView 5.11.0; paraview.org
binaries bring their own Python and VTK. On Debian the ParaView Python
modules are the package python3-paraview, which conflicts with python3-vtk9 (a dependency of
libvtk9-dev, which Stratum builds against): `apt-get install python3-paraview` removes
libvtk9-dev and python3-vtk9. Do not install it on the build machine; tools/README.md says how
to run a ParaView beside the build (paraview.org binaries, or Debian's packages unpacked with
dpkg-deb -x and run with LD_LIBRARY_PATH / PYTHONPATH).

The geometry (window, clipping, layout) is plain Python without ParaView, tested in
tests/python/test_plot_tools.py.
"""
import math
import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plastic_zone as pz  # noqa: E402

PILE_COLOUR = "#8a8a8a"


# ---------------------------------------------------------------- geometry (no ParaView, no VTK)

def window(full, box, a):
    """(xlim, ylim) of the picture: the pile and a.around diameters beside it, a.below under its
    toe (as tools/plastic_zone.py), the whole mesh with --full or without a pile; --xlim/--ylim
    override either. full = (xmin, xmax, ymin, ymax) of the mesh; box = (R, ytoe, ytop) or None."""
    if box and not a.full:
        R, ytoe, ytop = box
        D = 2.0 * R
        xlim = (full[0], min(full[1], R + a.around * D))
        ylim = (max(full[2], ytoe - a.below * D), max(ytop, full[3]) + 0.15 * D)
    else:
        xlim, ylim = (full[0], full[1]), (full[2], full[3])
    if a.xlim:
        xlim = tuple(a.xlim)
    if a.ylim:
        ylim = tuple(a.ylim)
    return xlim, ylim


def clip_segment(p, q, xlim, ylim):
    """The part of the segment p-q inside the rectangle (Liang-Barsky), or None."""
    x0, y0 = p
    dx, dy = q[0] - x0, q[1] - y0
    t0, t1 = 0.0, 1.0
    for d, lo, hi, v in ((dx, xlim[0], xlim[1], x0), (dy, ylim[0], ylim[1], y0)):
        if d == 0.0:
            if v < lo or v > hi:
                return None
            continue
        ta, tb = (lo - v) / d, (hi - v) / d
        if ta > tb:
            ta, tb = tb, ta
        t0, t1 = max(t0, ta), min(t1, tb)
        if t0 > t1:
            return None
    return (x0 + t0 * dx, y0 + t0 * dy), (x0 + t1 * dx, y0 + t1 * dy)


def clip_polygon(points, xlim, ylim):
    """The polygon cut to the rectangle (Sutherland-Hodgman; the pile is convex), maybe empty."""
    def cut(pts, inside, cross):
        out = []
        for i, cur in enumerate(pts):
            prev = pts[i - 1]
            if inside(cur):
                if not inside(prev):
                    out.append(cross(prev, cur))
                out.append(cur)
            elif inside(prev):
                out.append(cross(prev, cur))
        return out

    def at_x(x):
        return lambda p, q: (x, p[1] + (q[1] - p[1]) * (x - p[0]) / (q[0] - p[0]))

    def at_y(y):
        return lambda p, q: (p[0] + (q[0] - p[0]) * (y - p[1]) / (q[1] - p[1]), y)

    pts = list(points)
    for inside, cross in ((lambda p: p[0] >= xlim[0], at_x(xlim[0])), (lambda p: p[0] <= xlim[1], at_x(xlim[1])),
                          (lambda p: p[1] >= ylim[0], at_y(ylim[0])), (lambda p: p[1] <= ylim[1], at_y(ylim[1]))):
        if not pts:
            break
        pts = cut(pts, inside, cross)
    return pts


def mesh_edges(polys, xlim, ylim):
    """The cell outlines cut to the window: [((x0, y0), (x1, y1))], each edge of the mesh once."""
    seen, out = set(), []
    for xs, ys, _ in polys:
        n = len(xs)
        for i in range(n):
            p, q = (xs[i], ys[i]), (xs[(i + 1) % n], ys[(i + 1) % n])
            key = (min(p, q), max(p, q))
            if key in seen:
                continue
            seen.add(key)
            s = clip_segment(p, q, xlim, ylim)
            if s is not None and s[0] != s[1]:
                out.append(s)
    return out


def in_view(labels, legend, xs, ys, xlim, ylim, skip):
    """(indices of the points drawn, legend of the categories among them with their counts
    [(label, colour, count)], new category index per drawn point). `skip`: per point, True for
    the pile's points (the pile is drawn as a solid)."""
    keep = [i for i in range(len(labels))
            if not skip[i] and xlim[0] <= xs[i] <= xlim[1] and ylim[0] <= ys[i] <= ylim[1]]
    counts = {}
    for i in keep:
        counts[labels[i]] = counts.get(labels[i], 0) + 1
    shown = [(label, colour, counts[label]) for label, colour, _ in legend if label in counts]
    index = {label: k for k, (label, _, _) in enumerate(shown)}
    return keep, shown, [index[labels[i]] for i in keep]


def layout(xlim, ylim, height=1300, plot_height=1100, left=215, bottom=100, legend_width=560):
    """Pixels of the view and the camera that puts the window `left` px from the view's left and
    `bottom` px from its bottom, `plot_height` px high, with `legend_width` px on its right:
    (view size [w, h], focal point (x, y), parallel scale, window's right edge as a view fraction)."""
    sx, sy = xlim[1] - xlim[0], ylim[1] - ylim[0]
    ppm = plot_height / sy  # pixels per length unit
    plot_w = sx * ppm
    if plot_w > 1400:  # a wide window (a footing, --full): fit the width instead
        ppm = 1400 / sx
        plot_w, plot_height = 1400.0, sy * ppm
        height = int(round(plot_height + bottom + 100))
    width = int(round(left + plot_w + 60 + legend_width))
    width += width % 2
    height += height % 2
    cx = xlim[0] - left / ppm + 0.5 * width / ppm
    cy = ylim[0] - bottom / ppm + 0.5 * height / ppm
    return [width, height], (cx, cy), 0.5 * height / ppm, (left + plot_w) / width


# ---------------------------------------------------------------- the files the picture reads

def write_cells(cells, kind, path, regimes=None, regimes_on_points=False):
    """A .vtp of cells of one kind ("lines", "polys" or "verts"), each a list of (x, y, z) points,
    with the int array "regime" (one value a cell) as cell data, or as point data when the cells
    are single points (regimes_on_points)."""
    from vtkmodules.vtkCommonCore import vtkIntArray, vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

    pts, cell_array = vtkPoints(), vtkCellArray()
    for cell in cells:
        cell_array.InsertNextCell(len(cell))
        for x, y, z in cell:
            cell_array.InsertCellPoint(pts.InsertNextPoint(x, y, z))
    pd = vtkPolyData()
    pd.SetPoints(pts)
    {"lines": pd.SetLines, "polys": pd.SetPolys, "verts": pd.SetVerts}[kind](cell_array)
    if regimes is not None:
        reg = vtkIntArray()
        reg.SetName("regime")
        for r in regimes:
            reg.InsertNextValue(r)
        (pd.GetPointData() if regimes_on_points else pd.GetCellData()).AddArray(reg)
    write_polydata(pd, path)


def write_lines(segments, path):
    write_cells([[(p[0], p[1], 0.0), (q[0], q[1], 0.0)] for p, q in segments], "lines", path)


def write_polygons(polygons, category, path):
    cells = [[(x, y, -1e-3) for x, y in poly] for poly in polygons]  # behind the points
    write_cells(cells, "polys", path, [category] * len(cells))


def write_points(xyz, keep, category, path, z=1e-3):
    shown = list(zip(keep, category))
    cells = [[(float(xyz[i, 0]), float(xyz[i, 1]), z)] for i, _ in shown]
    write_cells(cells, "verts", path, [c for _, c in shown], regimes_on_points=True)


def write_polydata(pd, path):
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    w = vtkXMLPolyDataWriter()
    w.SetFileName(path)
    w.SetInputData(pd)
    if w.Write() != 1:
        sys.exit(f"plastic_zone_paraview: cannot write {path}")


def prepare(a, tmp):
    """Writes <results>/plastic_zone_<k>.vtp and the picture's files into `tmp`; returns what the
    picture needs."""
    ip_pvd, mesh_pvd = pz.series(a.results)
    k, f, fv = pz.pick(ip_pvd, a.load, a.step)
    data = pz.read(f)
    xyz, plastic, domain, itf = pz.point_arrays(data)
    labels, legend = pz.categories(fv, plastic, domain, itf)
    out_vtp = os.path.join(a.results, f"plastic_zone_{k}.vtp")
    pz.write_regime_vtp(data, labels, legend, out_vtp)
    domains = fv.get("domains", [])
    polys, box, pile_idx, full = pz.mesh_frame(mesh_pvd, k, domains, a.pile, xyz)
    xs, ys = xyz[:, 0], xyz[:, 1]
    xlim, ylim = window(full, box, a)
    kinds = {label: kind for label, _, kind in legend}
    skip = [bool(box) and kinds[labels[i]] == "linear" and domain is not None and int(domain[i]) in pile_idx
            for i in range(len(labels))]
    keep, shown, category = in_view(labels, legend, xs, ys, xlim, ylim, skip)
    files = {"points": os.path.join(tmp, "points.vtp")}
    itf_pts = [j for j, i in enumerate(keep) if kinds[labels[i]] == "interface"]
    soil_pts = [j for j, i in enumerate(keep) if kinds[labels[i]] != "interface"]
    write_points(xyz, [keep[j] for j in soil_pts], [category[j] for j in soil_pts], files["points"])
    if itf_pts:
        files["interface"] = os.path.join(tmp, "interface.vtp")
        write_points(xyz, [keep[j] for j in itf_pts], [category[j] for j in itf_pts], files["interface"], 2e-3)
    if polys:
        files["mesh"] = os.path.join(tmp, "mesh.vtp")
        write_lines(mesh_edges(polys, xlim, ylim), files["mesh"])
        pile = [clip_polygon(list(zip(p[0], p[1])), xlim, ylim) for p in polys if p[2] in pile_idx]
        pile = [p for p in pile if len(p) >= 3]
        if pile:
            shown.append(("pile (" + ", ".join(domains[i] for i in pile_idx) + ")", PILE_COLOUR, None))
            files["pile"] = os.path.join(tmp, "pile.vtp")
            write_polygons(pile, len(shown) - 1, files["pile"])
    stem = os.path.basename(ip_pvd)[: -len("_ip.pvd")]
    return k, fv, out_vtp, files, shown, len(keep), xlim, ylim, box is not None, stem


def hex_rgb(h):
    h = h.lstrip("#")
    return [int(h[i:i + 2], 16) / 255.0 for i in (0, 2, 4)]


def caption(fv, k):
    parts = [f"stage '{fv.get('stage', '?')}'", f"step {int(fv.get('step', k))}",
             f"load factor {fv.get('load_factor', float('nan')):.3g}"]
    (hl, hlu), (hs, hsu) = pz.prefixed(fv, "head_load_"), pz.prefixed(fv, "head_settlement_")
    if isinstance(hl, float) and math.isfinite(hl):
        parts.append(f"head load {hl:.1f} {hlu}")
    if isinstance(hs, float) and math.isfinite(hs):
        parts.append(f"settlement {hs:.2f} {hsu}")
    return ", ".join(parts)


# ---------------------------------------------------------------- ParaView

def set_either(proxy, name, value, older):
    """Sets a property to `value`, or to `older` where an older ParaView spells it so."""
    try:
        setattr(proxy, name, value)
    except (ValueError, AttributeError):
        setattr(proxy, name, older)


def solid(rep, colour):
    """A representation in one colour: no array (ColorArrayName is the documented property;
    ColorBy(rep, None) fails in ParaView 5.11 on a representation that was never coloured)."""
    rep.ColorArrayName = ["POINTS", ""]
    rep.AmbientColor = rep.DiffuseColor = hex_rgb(colour)


def flat(rep):
    """Colours as in the legend: no shading of the spheres and faces."""
    rep.Ambient, rep.Diffuse = 1.0, 0.0


def main():
    a = pz.arguments([x for x in sys.argv[1:] if x != "--show"])
    show = "--show" in sys.argv[1:]
    from paraview import simple as pv

    tmp = tempfile.mkdtemp(prefix="plastic_zone_pv_")
    try:
        k, fv, vtp, files, shown, n_points, xlim, ylim, pile_scene, stem = prepare(a, tmp)
        size, focal, scale, right = layout(xlim, ylim)
        view = pv.CreateView("RenderView")
        view.ViewSize = size
        view.OrientationAxesVisibility = 0
        try:
            view.UseColorPaletteForBackground = 0
        except AttributeError:
            pass
        view.Background = [1, 1, 1]
        lut = pv.GetColorTransferFunction("regime")
        lut.InterpretValuesAsCategories = 1
        ann, colours = [], []
        for i, (label, colour, count) in enumerate(shown):
            ann += [str(i), label if count is None else f"{label} ({count})"]
            colours += hex_rgb(colour)
        lut.Annotations = ann
        lut.IndexedColors = colours
        if "mesh" in files:
            mesh = pv.XMLPolyDataReader(FileName=[files["mesh"]])
            lines = pv.Show(mesh, view)
            solid(lines, "#b0b0b0")
            lines.LineWidth = 1.0
        if "pile" in files:
            pile = pv.XMLPolyDataReader(FileName=[files["pile"]])
            prep = pv.Show(pile, view)
            pv.ColorBy(prep, ("CELLS", "regime"))
            prep.LookupTable = lut
            prep.SetScalarBarVisibility(view, False)
            flat(prep)
        pts = pv.XMLPolyDataReader(FileName=[files["points"]])
        disp = pv.Show(pts, view)
        disp.SetRepresentationType("Points")
        # about tile the window: a diameter from the pixels per point of the plot area
        plot_px = (right * size[0] - 215) * 1100.0
        disp.PointSize = max(3.0, min(12.0, 0.5 * math.sqrt(plot_px / max(n_points, 1))))
        try:
            disp.RenderPointsAsSpheres = 1
        except AttributeError:
            pass
        flat(disp)
        pv.ColorBy(disp, ("POINTS", "regime"))
        disp.LookupTable = lut
        if "interface" in files:
            itf = pv.XMLPolyDataReader(FileName=[files["interface"]])
            irep = pv.Show(itf, view)  # interface points as squares, a little larger (as plastic_zone.py)
            irep.SetRepresentationType("Points")
            irep.PointSize = 1.5 * disp.PointSize
            flat(irep)
            pv.ColorBy(irep, ("POINTS", "regime"))
            irep.LookupTable = lut
            irep.SetScalarBarVisibility(view, False)
        lut.RescaleTransferFunction(0.0, float(max(len(shown) - 1, 1)))
        disp.SetScalarBarVisibility(view, True)
        bar = pv.GetScalarBar(lut, view)
        bar.Title = "regime (integration points in view)"
        bar.ComponentTitle = ""
        bar.TitleColor = bar.LabelColor = [0, 0, 0]
        bar.TitleFontSize, bar.LabelFontSize = 18, 18
        bar.TitleBold = 1
        bar.HorizontalTitle = 1
        try:
            bar.TitleJustification = "Left"
        except (ValueError, AttributeError):
            pass
        set_either(bar, "WindowLocation", "Any Location", "AnyLocation")  # ParaView >= 5.10 / older
        bar.Orientation = "Vertical"
        bar.ScalarBarLength = min(0.8, 0.06 * len(shown) + 0.05)
        bar.Position = [min(right + 0.04, 0.9), 0.90 - bar.ScalarBarLength]
        try:
            bar.TextPosition = "Ticks right/top, annotations left/bottom"
            bar.TextPosition = "Ticks left/bottom, annotations right/top"
        except (ValueError, AttributeError):
            pass
        lu = pz.length_unit(fv)
        grid = view.AxesGrid
        grid.Visibility = 1
        grid.UseCustomBounds = 1
        grid.CustomBounds = [xlim[0], xlim[1], ylim[0], ylim[1], 0.0, 0.0]
        # ParaView writes the vertical axis's title horizontally: a short one, explained below the legend
        grid.XTitle = f"r: distance from the pile axis ({lu})" if pile_scene else f"x ({lu})"
        grid.YTitle = f"z ({lu})" if pile_scene else f"y ({lu})"
        grid.AxesToLabel = 1 | 2  # the min-x and min-y edges (vtkGridAxesActor: MIN_X, MIN_Y)
        grid.FacesToRender = 4  # the x-y face only (MIN_XY)
        for ax in "XY":
            setattr(grid, ax + "TitleColor", [0, 0, 0])
            setattr(grid, ax + "LabelColor", [0, 0, 0])
            setattr(grid, ax + "TitleFontSize", 20)
            setattr(grid, ax + "LabelFontSize", 18)
        grid.GridColor = [0.55, 0.55, 0.55]
        grid.ShowGrid = 0
        grid.ShowTicks = 1
        grid.ShowEdges = 1
        if pile_scene:
            note = pv.Text(Text=f"r: distance from the pile axis ({lu})\nz: elevation, ground at 0 ({lu})\n"
                                "mesh: thin grey lines")
            nr = pv.Show(note, view)
            nr.Color = [0.2, 0.2, 0.2]
            nr.FontSize = 16
            nr.Justification = "Left"
            set_either(nr, "WindowLocation", "Any Location", "AnyLocation")
            nr.Position = [bar.Position[0], max(0.02, bar.Position[1] - 0.1)]
        title = pv.Text(Text=f"{a.title or stem + ': plastic zone'}\n{caption(fv, k)}")
        tr = pv.Show(title, view)
        tr.Color = [0, 0, 0]
        tr.FontSize = 20
        set_either(tr, "WindowLocation", "Upper Left Corner", "UpperLeftCorner")
        view.InteractionMode = "2D"
        view.CameraParallelProjection = 1
        view.CameraFocalPoint = [focal[0], focal[1], 0.0]
        view.CameraPosition = [focal[0], focal[1], 10.0]
        view.CameraViewUp = [0.0, 1.0, 0.0]
        view.CameraParallelScale = scale
        if show:
            pv.Interact(view)
            return
        out = a.output or os.path.join(a.results, f"plastic_zone_{k}_paraview.png")
        pv.SaveScreenshot(out + ".tmp.png", view, ImageResolution=size)
        os.replace(out + ".tmp.png", out)
        print(f"plastic_zone_paraview: step {k} ({caption(fv, k)}) -> {out} (and {vtp})")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
