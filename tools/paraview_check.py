"""Open every VTK output of result folders in ParaView and list its arrays (pvpython).

    pvpython tools/paraview_check.py out/hypoelastic out/terzaghi ...

For each folder: every .pvd collection is opened with ParaView's own reader (PVDReader, the
reader the GUI uses for File > Open), every time step of it is updated, and the point, cell and
field arrays of its first and last steps are listed with their component names. A file that
ParaView cannot read, a step without points, or an array whose name carries neither a unit in
brackets ("stress [kPa]") nor one of the integer codes (domain, set_id, plastic,
interface_status) is reported, and the exit status is 1. Field data follow the CSV columns'
spelling (head_load_kN) and are listed, not judged.

Which ParaView: Debian's python3-paraview (5.11) conflicts with python3-vtk9, which Stratum's
build needs (plastic_zone_paraview.py says how to run one beside the build).
"""
import glob
import os
import re
import sys

CODES = {"domain", "set_id", "plastic", "interface_status"}
UNIT = re.compile(r"^.+ \[[^\]]+\]$")


def arrays(info):
    """(name, components, component names) of a vtkPVDataSetAttributesInformation."""
    out = []
    for i in range(info.GetNumberOfArrays()):
        a = info.GetArrayInformation(i)
        n = a.GetNumberOfComponents()
        comps = [a.GetComponentName(c) or "" for c in range(n)] if n > 1 else []
        out.append((a.GetName(), n, comps))
    return out


def check_folder(folder, simple):
    problems = []
    pvds = sorted(glob.glob(os.path.join(folder, "*.pvd")))
    if not pvds:
        return [f"{folder}: no .pvd collection"]
    for pvd in pvds:
        reader = simple.PVDReader(FileName=pvd)
        times = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
        for t in times:
            reader.UpdatePipeline(t)
        for label, t in (("first", times[0]), ("last", times[-1])):
            reader.UpdatePipeline(t)
            info = reader.GetDataInformation().DataInformation
            if info.GetNumberOfPoints() == 0:
                problems.append(f"{pvd} at time {t}: no points")
            print(f"{os.path.relpath(pvd)}: {len(times)} steps; {label} step (time {t:g}): "
                  f"{info.GetNumberOfPoints()} points, {info.GetNumberOfCells()} cells")
            for kind, attrs in (("point", info.GetPointDataInformation()),
                                ("cell", info.GetCellDataInformation())):
                for name, n, comps in arrays(attrs):
                    ok = name in CODES or UNIT.match(name)
                    print(f"  {kind:5} {name!r}" + (f" ({', '.join(comps)})" if comps else "")
                          + ("" if ok else "   <-- no unit"))
                    if not ok:
                        problems.append(f"{pvd}: {kind} array {name!r} names no unit")
            fields = arrays(info.GetFieldDataInformation())
            print("  field " + ", ".join(name for name, _, _ in fields))
        simple.Delete(reader)
    return problems


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    from paraview import simple  # noqa: E402 (pvpython only)

    problems = []
    for folder in sys.argv[1:]:
        problems += check_folder(folder, simple)
    for p in problems:
        print("paraview_check: " + p, file=sys.stderr)
    print(f"paraview_check: {len(sys.argv) - 1} folders, {len(problems)} problems")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
