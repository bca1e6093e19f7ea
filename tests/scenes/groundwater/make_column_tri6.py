#!/usr/bin/env python3
"""Writes column_tri6.msh: a 1 m x 10 m column of 6-node triangles (Gmsh 4.1 ASCII), 2 x 40
rectangles each split along a diagonal (alternating), with the physical groups soil (surface),
top, bottom, left and right (lines). Run: python3 make_column_tri6.py > column_tri6.msh"""
nx, ny, W, H = 2, 40, 1.0, 10.0
# nodes on a (2 nx + 1) x (2 ny + 1) grid: every grid point is a corner or a midside node
X = [W * i / (2 * nx) for i in range(2 * nx + 1)]
Y = [H * j / (2 * ny) for j in range(2 * ny + 1)]
tag = lambda i, j: 1 + i + (2 * nx + 1) * j
tris = []
for j in range(ny):
    for i in range(nx):
        a, b = (2 * i, 2 * j), (2 * i + 2, 2 * j)
        c, d = (2 * i + 2, 2 * j + 2), (2 * i, 2 * j + 2)
        mid = lambda p, q: ((p[0] + q[0]) // 2, (p[1] + q[1]) // 2)
        if (i + j) % 2 == 0:  # diagonal a-c
            halves = [(a, b, c), (a, c, d)]
        else:                 # diagonal b-d
            halves = [(a, b, d), (b, c, d)]
        for p, q, r in halves:
            tris.append([tag(*p), tag(*q), tag(*r), tag(*mid(p, q)), tag(*mid(q, r)), tag(*mid(r, p))])
def edge(points):
    return [[tag(*points[k]), tag(*points[k + 2]), tag(*points[k + 1])] for k in range(0, len(points) - 2, 2)]
lines = {
    "bottom": edge([(i, 0) for i in range(2 * nx + 1)]),
    "right": edge([(2 * nx, j) for j in range(2 * ny + 1)]),
    "top": edge([(i, 2 * ny) for i in range(2 * nx, -1, -1)]),
    "left": edge([(0, j) for j in range(2 * ny, -1, -1)]),
}
out = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$PhysicalNames", "5"]
names = list(lines)
for k, n in enumerate(names):
    out.append(f'1 {k + 1} "{n}"')
out.append('2 5 "soil"')
out += ["$EndPhysicalNames", "$Entities", "0 4 1 0"]
for k in range(4):
    out.append(f"{k + 1} 0 0 0 {W} {H} 0 1 {k + 1} 0")
out.append(f"1 0 0 0 {W} {H} 0 1 5 4 1 2 3 4")
out += ["$EndEntities", "$Nodes"]
n_nodes = len(X) * len(Y)
out.append(f"1 {n_nodes} 1 {n_nodes}")
out.append(f"2 1 0 {n_nodes}")
out += [str(t) for t in range(1, n_nodes + 1)]
for j in range(len(Y)):
    for i in range(len(X)):
        out.append(f"{X[i]:.17g} {Y[j]:.17g} 0")
out += ["$EndNodes", "$Elements"]
n_el = len(tris) + sum(len(v) for v in lines.values())
out.append(f"5 {n_el} 1 {n_el}")
e = 1
for k, n in enumerate(names):
    out.append(f"1 {k + 1} 8 {len(lines[n])}")
    for l in lines[n]:
        out.append(f"{e} " + " ".join(map(str, l)))
        e += 1
out.append(f"2 1 9 {len(tris)}")
for t in tris:
    out.append(f"{e} " + " ".join(map(str, t)))
    e += 1
out += ["$EndElements"]
print("\n".join(out))
