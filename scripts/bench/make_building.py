#!/usr/bin/env python3
"""make_building.py OUT.obj — a test building for the point-cloud benchmarks
(issue 34): a two-storey house (walls with recessed windows and a door, a
gable roof with overhang, a chimney), a flat-roofed garage, a low garden
wall and the ground around them, in metres, y up, as an OBJ of quads with
materials (walls, roof, ground). `bbcgen sample OUT.obj --normals` scans it.
Deterministic: no randomness."""
import sys

verts, faces = [], []
mats = {"wall": (0.85, 0.80, 0.70), "roof": (0.55, 0.20, 0.15), "ground": (0.35, 0.45, 0.25),
        "glass": (0.25, 0.30, 0.35)}


def quad(a, b, c, d, mat):
    i = len(verts)
    verts.extend([a, b, c, d])
    faces.append((mat, (i + 1, i + 2, i + 3, i + 4)))


def box(x0, y0, z0, x1, y1, z1, mat, top=True, bottom=False):
    """An axis-aligned box, outward faces."""
    quad((x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1), mat)  # +z
    quad((x1, y0, z0), (x0, y0, z0), (x0, y1, z0), (x1, y1, z0), mat)  # -z
    quad((x1, y0, z1), (x1, y0, z0), (x1, y1, z0), (x1, y1, z1), mat)  # +x
    quad((x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0), mat)  # -x
    if top:
        quad((x0, y1, z1), (x1, y1, z1), (x1, y1, z0), (x0, y1, z0), mat)
    if bottom:
        quad((x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1), mat)


def window(axis, fixed, u0, y0, u1, y1, out, depth=0.08):
    """A window (its frame and shutters) `depth` proud of a wall, on axis
    'x' (a wall at x = fixed facing +-x) or 'z'."""
    f = fixed + out * depth

    def p(u, y, w):
        return (w, y, u) if axis == "x" else (u, y, w)
    if (axis == "z") == (out > 0):
        quad(p(u0, y0, f), p(u1, y0, f), p(u1, y1, f), p(u0, y1, f), "glass")
    else:
        quad(p(u1, y0, f), p(u0, y0, f), p(u0, y1, f), p(u1, y1, f), "glass")


# the ground: 30 x 30 m
quad((-15, 0, 15), (15, 0, 15), (15, 0, -15), (-15, 0, -15), "ground")
# the house: 12 x 8 m, walls 6 m, ridge at 9.5 m along x, 0.5 m overhang
W, D, H, R = 6.0, 4.0, 6.0, 9.5
box(-W, 0, -D, W, H, D, "wall", top=False)
for x in (-4.5, -1.5, 1.5, 4.5):
    for y in (1.0, 3.8):
        if not (x == -1.5 and y == 1.0):
            window("z", D, x - 0.6, y, x + 0.6, y + 1.4, +1)
        window("z", -D, x - 0.6, y, x + 0.6, y + 1.4, -1)
window("z", D, -2.0, 0.0, -1.0, 2.2, +1, 0.05)  # the door
for z in (-2.0, 2.0):
    window("x", W, z - 0.6, 3.8, z + 0.6, 5.2, +1)
    window("x", -W, z - 0.6, 3.8, z + 0.6, 5.2, -1)
# gables
for s in (-1, 1):
    quad((s * W, H, s * D), (s * W, H, -s * D), (s * W, R, 0), (s * W, R, 0), "wall")
o = 0.5
quad((-W - o, H - 0.3, D + o), (W + o, H - 0.3, D + o), (W + o, R, 0), (-W - o, R, 0), "roof")
quad((W + o, H - 0.3, -D - o), (-W - o, H - 0.3, -D - o), (-W - o, R, 0), (W + o, R, 0), "roof")
# chimney through the roof
box(2.5, 7.0, -1.8, 3.3, 10.5, -1.0, "wall")
# the garage: 5 x 6 m, 3 m high, flat roof, its door on +z
box(W, 0, -1.0, W + 5.0, 3.0, 5.0, "wall")
window("z", 5.0, W + 0.7, 0.0, W + 4.3, 2.4, +1, 0.05)
# a garden wall 1 m high along the front, with a gate
box(-14, 0, 11.8, -1.5, 1.0, 12.2, "wall")
box(1.5, 0, 11.8, 14, 1.0, 12.2, "wall")

# `make_building.py OUT.obj [N]`: with N, every face cut into an N x N grid
# (quads into quads, a gable's triangle into triangles): the building as a
# finely tessellated mesh (a remeshed scan), the same surface
out = sys.argv[1]
sub = int(sys.argv[2]) if len(sys.argv) > 2 else 1
if sub > 1:
    old_faces, faces = faces, []

    def lerp(a, b, t):
        return tuple(a[k] + (b[k] - a[k]) * t for k in range(3))

    def vid(p):
        verts.append(p)
        return len(verts)

    for m, ix in old_faces:
        a, b, c, d = (verts[i - 1] for i in ix)
        tri = c == d
        grid = {}
        for i in range(sub + 1):
            for j in range(sub + 1):
                u, v = i / sub, j / sub
                if tri:  # a, b, c: barycentric, only i + j <= sub
                    if i + j <= sub:
                        grid[i, j] = vid(tuple(a[k] + u * (b[k] - a[k]) + v * (c[k] - a[k]) for k in range(3)))
                else:
                    grid[i, j] = vid(lerp(lerp(a, b, u), lerp(d, c, u), v))
        for i in range(sub):
            for j in range(sub):
                if not tri:
                    faces.append((m, (grid[i, j], grid[i + 1, j], grid[i + 1, j + 1], grid[i, j + 1])))
                elif i + j < sub:
                    p3 = grid[i, j + 1]
                    faces.append((m, (grid[i, j], grid[i + 1, j], p3, p3)))
                    if i + j + 1 < sub:
                        q = grid[i + 1, j + 1]
                        faces.append((m, (grid[i + 1, j], q, p3, p3)))
mtl = out[:-4] + ".mtl"
with open(mtl, "w") as f:
    for name, c in mats.items():
        f.write(f"newmtl {name}\nKd {c[0]} {c[1]} {c[2]}\n\n")
with open(out, "w") as f:
    f.write(f"# a test building (scripts/bench/make_building.py)\nmtllib {mtl.split('/')[-1]}\n")
    for v in verts:
        f.write("v %g %g %g\n" % v)
    cur = None
    for m, ix in faces:
        if m != cur:
            f.write(f"g {m}\nusemtl {m}\n")
            cur = m
        if verts[ix[2] - 1] == verts[ix[3] - 1]:  # a gable: a triangle
            f.write("f %d %d %d\n" % ix[:3])
        else:
            f.write("f %d %d %d %d\n" % ix)
