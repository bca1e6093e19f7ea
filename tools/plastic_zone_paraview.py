"""The plastic-zone picture in ParaView (pvpython / pvbatch, or the GUI's Python shell).

    pvpython tools/plastic_zone_paraview.py out/hypoelastic --load 60 [-o zone.png] [--show]

Same step selection, categories, colours and framing as tools/plastic_zone.py (imported from
beside this file): the integration points of the chosen step are written once more, to
<results>/plastic_zone_<step>.vtp, with a point array "regime" (a category index) whose names
are the field data "regime_names"; ParaView then draws them with a categorical colour map and
a legend of the models' own regime names, over the mesh (pile cells solid), with an axes grid
in metres. --show keeps the render window open (pvpython with a display); without it the view
is saved as a PNG. The .vtp it leaves behind opens in the ParaView GUI as it is: colour by
"regime", "Interpret Values As Categories", and the annotations come from the file (see
tools/README.md).

Runs in the ParaView binaries from paraview.org (they bring their own Python and VTK). On
Debian the ParaView Python modules are the package python3-paraview, which conflicts with
python3-vtk9 (a dependency of libvtk9-dev, which Stratum builds against): do not install it on
the build machine; tools/README.md says more.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plastic_zone as pz  # noqa: E402


def write_regimes(a):
    """Writes the chosen step's points with "regime" and "regime_names"; returns what the
    picture needs."""
    ip_pvd, mesh_pvd = pz.series(a.results)
    k, f, fv = pz.pick(ip_pvd, a.load, a.step)
    data = pz.read(f)
    xyz, plastic, domain, itf = pz.point_arrays(data)
    labels, legend = pz.categories(fv, plastic, domain, itf)
    out_vtp = os.path.join(a.results, f"plastic_zone_{k}.vtp")
    pz.write_regime_vtp(data, labels, legend, out_vtp)
    mesh_file, box = None, None
    if mesh_pvd:
        msets = pz.datasets(mesh_pvd)
        if k < len(msets):
            mesh_file = msets[k][1]
            polys = pz.mesh_polygons(pz.read(mesh_file))
            box, pile_idx = pz.pile_box(polys, fv.get("domains", []), a.pile)
            allx = [x for p in polys for x in p[0]]
            ally = [y for p in polys for y in p[1]]
            full = (min(allx), max(allx), min(ally), max(ally))
    if mesh_file is None:
        full = (xyz[:, 0].min(), xyz[:, 0].max(), xyz[:, 1].min(), xyz[:, 1].max())
        pile_idx = []
    if box and not a.full:
        R, ytoe, ytop = box
        D = 2.0 * R
        xlim, ylim = (full[0], R + a.around * D), (ytoe - a.below * D, max(ytop, full[3]) + 0.15 * D)
    else:
        xlim, ylim = (full[0], full[1]), (full[2], full[3])
    xlim = tuple(a.xlim) if a.xlim else xlim
    ylim = tuple(a.ylim) if a.ylim else ylim
    return k, fv, out_vtp, mesh_file, legend, pile_idx, xlim, ylim


def set_either(proxy, name, value, older):
    """Sets a property to `value`, or to `older` where an older ParaView spells it so."""
    try:
        setattr(proxy, name, value)
    except (ValueError, AttributeError):
        setattr(proxy, name, older)


def hex_rgb(h):
    h = h.lstrip("#")
    return [int(h[i:i + 2], 16) / 255.0 for i in (0, 2, 4)]


def main():
    a = pz.arguments([x for x in sys.argv[1:] if x != "--show"])
    show = "--show" in sys.argv[1:]
    from paraview import simple as pv

    k, fv, vtp, mesh_file, legend, pile_idx, xlim, ylim = write_regimes(a)
    view = pv.CreateView("RenderView")
    view.ViewSize = [1400, 1000]
    view.OrientationAxesVisibility = 0
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.Background = [1, 1, 1]
    if mesh_file:
        mesh = pv.XMLUnstructuredGridReader(FileName=[mesh_file])
        lines = pv.Show(mesh, view)
        lines.SetRepresentationType("Wireframe")
        lines.AmbientColor = lines.DiffuseColor = [0.7, 0.7, 0.7]
        pv.ColorBy(lines, None)
        if pile_idx:
            pile = pv.Threshold(Input=mesh)
            pile.Scalars = ["CELLS", "domain"]
            try:  # ParaView >= 5.10
                pile.LowerThreshold, pile.UpperThreshold = min(pile_idx), max(pile_idx)
            except AttributeError:
                pile.ThresholdRange = [min(pile_idx), max(pile_idx)]
            solid = pv.Show(pile, view)
            pv.ColorBy(solid, None)
            solid.AmbientColor = solid.DiffuseColor = hex_rgb("#8a8a8a")
    pts = pv.XMLPolyDataReader(FileName=[vtp])
    disp = pv.Show(pts, view)
    disp.SetRepresentationType("Points")
    disp.PointSize = 5
    try:
        disp.RenderPointsAsSpheres = 1
    except AttributeError:
        pass
    pv.ColorBy(disp, ("POINTS", "regime"))
    lut = pv.GetColorTransferFunction("regime")
    lut.InterpretValuesAsCategories = 1
    ann, colours = [], []
    for i, (label, colour, _) in enumerate(legend):
        ann += [str(i), label]
        colours += hex_rgb(colour)
    lut.Annotations = ann
    lut.IndexedColors = colours
    disp.SetScalarBarVisibility(view, True)
    bar = pv.GetScalarBar(lut, view)
    bar.Title = "regime"
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    set_either(bar, "WindowLocation", "Any Location", "AnyLocation")  # ParaView >= 5.10 / older
    bar.Position = [0.80, 0.35]
    view.AxesGrid.Visibility = 1
    view.AxesGrid.XTitle = "r (m)" if pile_idx else "x (m)"
    view.AxesGrid.YTitle = "z (m)" if pile_idx else "y (m)"
    view.AxesGrid.XTitleColor = view.AxesGrid.YTitleColor = [0, 0, 0]
    view.AxesGrid.XLabelColor = view.AxesGrid.YLabelColor = [0, 0, 0]
    view.AxesGrid.GridColor = [0.2, 0.2, 0.2]
    parts = [f"stage '{fv.get('stage', '?')}'", f"step {int(fv.get('step', k))}",
             f"load factor {fv.get('load_factor', float('nan')):.3g}"]
    hl = fv.get("head_load_kN")
    if isinstance(hl, float) and hl == hl:
        parts.append(f"head load {hl:.1f} kN")
    text = pv.Text(Text=", ".join(parts))
    tr = pv.Show(text, view)
    tr.Color = [0, 0, 0]
    set_either(tr, "WindowLocation", "Upper Center", "UpperCenter")
    view.InteractionMode = "2D"
    cx, cy = 0.5 * (xlim[0] + xlim[1]), 0.5 * (ylim[0] + ylim[1])
    view.CameraFocalPoint = [cx, cy, 0.0]
    view.CameraPosition = [cx, cy, 10.0]
    view.CameraViewUp = [0.0, 1.0, 0.0]
    aspect = view.ViewSize[0] / view.ViewSize[1]
    view.CameraParallelScale = 0.55 * max(ylim[1] - ylim[0], (xlim[1] - xlim[0]) / aspect * 1.4)
    if show:
        pv.Interact(view)
        return
    out = a.output or os.path.join(a.results, f"plastic_zone_{k}_paraview.png")
    pv.SaveScreenshot(out + ".tmp.png", view, ImageResolution=view.ViewSize)
    os.replace(out + ".tmp.png", out)
    print(f"plastic_zone_paraview: step {k} -> {out} (and {vtp})")


if __name__ == "__main__":
    main()
