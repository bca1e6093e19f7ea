"""Render the plastic zone of a pile run at a chosen head load to PNG (ParaView, pvbatch).

    pvbatch tools/plastic_zone.py out/hypoelastic --load 60 [-o zone.png] [--width 1200]

Reads <dir>/<scene>_ip.pvd (the integration points, written with [output]
integration_points = true) and <dir>/curves/load_settlement.csv. Step times are
"stage index + load factor", so in the loading stage (the last one) the head load is
lambda * F; F follows from the last row of the curve and the last time step. The step
whose load is nearest to --load is drawn: the points coloured by the field "plastic"
(Material::point_status: -1 not reported, 0 elastic, >= 1 yielding or failed; for
Duncan-Chang 1 failed and 2 cut off in tension, for the cap the regime 1 tension,
2 envelope, 3 corner, 4 cap), over the mesh outline, in the r-z plane.
With ParaView: `xvfb-run -a pvbatch tools/plastic_zone.py ...` (pvbatch needs an X server or
an offscreen build). Debian's python3-paraview conflicts with python3-vtk9, which Stratum's
libvtk9-dev pulls in, so on the build machine the same script runs under
`/usr/bin/python3` instead: without ParaView's modules it draws the same picture with VTK's
Python reader and matplotlib (python3-vtk9, python3-matplotlib).
"""
import argparse
import glob
import math
import os
import sys

try:
    from paraview import simple as pv
except ImportError:  # plain python3: VTK's reader and matplotlib
    pv = None


def pick_step(pvd, curve, load):
    """(file of the step, its time, its head load) nearest to `load` in the loading stage."""
    import xml.etree.ElementTree as ET

    steps = sorted((float(d.get("timestep")), d.get("file")) for d in ET.parse(pvd).getroot().iter("DataSet"))
    rows = [tuple(map(float, l.split(","))) for l in open(curve).read().splitlines()[1:] if l.strip()]
    t_last = steps[-1][0]
    stage = math.floor(t_last - 1e-12)
    frac, P_last = t_last - stage, rows[-1][0]
    if not (frac > 0 and P_last > 0):
        sys.exit("plastic_zone: the last step is not in a loaded stage")
    force = P_last / frac
    t, f = min(((t, f) for t, f in steps if t > stage), key=lambda s: abs((s[0] - stage) * force - load))
    return os.path.join(os.path.dirname(pvd), f), t, (t - stage) * force


def matplotlib_render(a, pvd, curve, out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

    f, t, shown = pick_step(pvd, curve, a.load)
    r = vtkXMLPolyDataReader()
    r.SetFileName(f)
    r.Update()
    data = r.GetOutput()
    arr = data.GetPointData().GetArray("plastic")
    if arr is None:
        sys.exit(f"plastic_zone: {f} has no field 'plastic'")
    xyz = vtk_to_numpy(data.GetPoints().GetData())
    code = vtk_to_numpy(arr)
    print(f"plastic_zone: time {t:.6g}, head load {shown:.2f} kN (asked {a.load:g} kN)")
    fig, ax = plt.subplots(figsize=(a.width / 200, a.width * 0.75 / 200), dpi=200)
    names = {-1: "not reported (linear, pile)", 0: "elastic", 1: "failed / tension regime",
             2: "tension cut-off / envelope", 3: "corner", 4: "cap"}
    for c in sorted(set(code.astype(int))):
        m = code.astype(int) == c
        ax.scatter(xyz[m, 0], xyz[m, 1], s=3 if c <= 0 else 8, label=f"{c}: {names.get(c, '')}",
                   color="0.8" if c < 0 else None)
    if a.radius:
        ax.set_xlim(0, a.radius)
    if a.depth:
        ax.set_ylim(-a.depth, 0.05 * a.depth)
    ax.set_aspect("equal")
    ax.set_xlabel("r (m)")
    ax.set_ylabel("z (m)")
    ax.set_title(f"plastic (Material::point_status) at head load {shown:.1f} kN")
    ax.legend(loc="lower right", fontsize=6, markerscale=2)
    fig.tight_layout()
    tmp = out + ".tmp.png"
    fig.savefig(tmp)
    os.replace(tmp, out)
    print(f"plastic_zone: wrote {out}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("results", help="the run's output directory, e.g. out/hypoelastic")
    ap.add_argument("--load", type=float, required=True, help="head load (kN)")
    ap.add_argument("-o", "--output", default=None, help="PNG file (default: <dir>/plastic_zone_<load>kN.png)")
    ap.add_argument("--width", type=int, default=1200)
    ap.add_argument("--radius", type=float, default=None, help="show r up to this (m); default: all")
    ap.add_argument("--depth", type=float, default=None, help="show z down to this depth (m)")
    a = ap.parse_args()

    ip = glob.glob(os.path.join(a.results, "*_ip.pvd"))
    curve = os.path.join(a.results, "curves", "load_settlement.csv")
    if not ip or not os.path.exists(curve):
        sys.exit(f"plastic_zone: {a.results}: needs *_ip.pvd (integration_points = true) and curves/load_settlement.csv")
    out = a.output or os.path.join(a.results, f"plastic_zone_{a.load:g}kN.png")
    if pv is None:
        matplotlib_render(a, ip[0], curve, out)
        return
    rows = [tuple(map(float, l.split(","))) for l in open(curve).read().splitlines()[1:] if l.strip()]
    reader = pv.PVDReader(FileName=ip[0])
    times = list(reader.TimestepValues)
    t_last = times[-1]
    stage = math.floor(t_last - 1e-12)
    frac = t_last - stage
    P_last = rows[-1][0]
    if not (frac > 0 and P_last > 0):
        sys.exit("plastic_zone: the last step is not in a loaded stage")
    force = P_last / frac  # the stage's total head load F: load = lambda F
    loading = [t for t in times if t > stage]
    t = min(loading, key=lambda t: abs((t - stage) * force - a.load))
    shown = (t - stage) * force
    print(f"plastic_zone: time {t:.6g}, head load {shown:.2f} kN (asked {a.load:g} kN)")

    view = pv.CreateView("RenderView")
    view.ViewSize = [a.width, int(a.width * 0.75)]
    view.ViewTime = t
    view.OrientationAxesVisibility = 0
    view.Background = [1, 1, 1]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    src = reader
    if a.radius or a.depth:
        clip = pv.Clip(Input=reader)
        clip.ClipType = "Box"
        clip.ClipType.Position = [0.0, -(a.depth or 1e6), -1.0]
        clip.ClipType.Length = [a.radius or 1e6, a.depth or 1e6, 2.0]
        clip.Invert = 1
        src = clip
    glyph = pv.Show(src, view)
    glyph.SetRepresentationType("Points")
    glyph.PointSize = 6
    pv.ColorBy(glyph, ("POINTS", "plastic"))
    lut = pv.GetColorTransferFunction("plastic")
    lut.ApplyPreset("Rainbow Uniform", True)
    lut.RescaleTransferFunction(-1.0, 4.0)
    glyph.SetScalarBarVisibility(view, True)
    bar = pv.GetScalarBar(lut, view)
    bar.Title = "plastic (point_status)"
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    mesh_pvd = [p for p in glob.glob(os.path.join(a.results, "*.pvd")) if not p.endswith("_ip.pvd")]
    if mesh_pvd:
        mesh = pv.PVDReader(FileName=mesh_pvd[0])
        outline = pv.Show(mesh, view)
        outline.SetRepresentationType("Wireframe")
        outline.AmbientColor = outline.DiffuseColor = [0.6, 0.6, 0.6]
        outline.ColorArrayName = ["POINTS", ""]
    text = pv.Text(Text=f"head load {shown:.1f} kN")
    tr = pv.Show(text, view)
    tr.Color = [0, 0, 0]
    tr.WindowLocation = "Upper Center"
    view.InteractionMode = "2D"
    pv.ResetCamera(view)
    if a.radius or a.depth:
        view.CameraFocalPoint = [(a.radius or 1.0) / 2, -(a.depth or 1.0) / 2, 0]
        view.CameraPosition = [(a.radius or 1.0) / 2, -(a.depth or 1.0) / 2, 10]
        view.CameraParallelScale = max(a.radius or 0, a.depth or 0) / 2 * 1.1
    tmp = out + ".tmp.png"
    pv.SaveScreenshot(tmp, view, ImageResolution=view.ViewSize)
    os.replace(tmp, out)
    print(f"plastic_zone: wrote {out}")


if __name__ == "__main__":
    main()
