#!/usr/bin/env python3
"""make_plot.py OUT.obj TREE.obj... — a test forest plot for the point-cloud
benchmarks (issue 34): a 40 x 40 m patch of gently rolling ground with the
given trees (OBJ files, y up, metres: `bbcgen tree` writes such) standing on
it at fixed spots, as one OBJ whose materials are the trees' own (their MTL
files are merged, names prefixed) plus the ground's. Sampled by `bbcgen
sample`, a plot's scan is mostly ground, as a terrestrial or airborne scan
of a forest plot is. Deterministic: no randomness."""
import math
import os
import sys

SIZE, STEPS = 40.0, 40
SPOTS = [(-11, -9, 0), (8, -12, 70), (-3, 4, 140), (12, 7, 210), (-14, 13, 280), (2, -2, 330),
         (15, -1, 45), (-7, -15, 100)]


def ground(x, z):
    return 0.6 * math.sin(x / 7.0) * math.cos(z / 9.0) + 0.02 * x


out = sys.argv[1]
trees = sys.argv[2:]
odir = os.path.dirname(os.path.abspath(out))
lines, mtl = [], ["newmtl plot_ground\nKd 0.40 0.33 0.22\n"]
nv = nvt = nvn = 0
# the ground: a height field of quads
for j in range(STEPS + 1):
    for i in range(STEPS + 1):
        x, z = -SIZE / 2 + SIZE * i / STEPS, -SIZE / 2 + SIZE * j / STEPS
        lines.append("v %.4f %.4f %.4f" % (x, ground(x, z), z))
lines.append("g ground\nusemtl plot_ground")
for j in range(STEPS):
    for i in range(STEPS):
        a = j * (STEPS + 1) + i + 1
        lines.append("f %d %d %d %d" % (a, a + STEPS + 1, a + STEPS + 2, a + 1))
nv = (STEPS + 1) ** 2
for t, path in enumerate(trees):
    sx, sz, rot = SPOTS[t % len(SPOTS)]
    c, s = math.cos(math.radians(rot)), math.sin(math.radians(rot))
    base = ground(sx, sz) - 0.05  # a little into the ground
    pre = "t%d_" % t
    tdir = os.path.dirname(os.path.abspath(path))
    vs = vts = vns = 0
    for raw in open(path):
        w = raw.split()
        if not w:
            continue
        if w[0] == "v":
            x, y, z = float(w[1]), float(w[2]), float(w[3])
            lines.append("v %.5f %.5f %.5f" % (sx + c * x - s * z, base + y, sz + s * x + c * z))
            vs += 1
        elif w[0] == "vt":
            lines.append(raw.rstrip())
            vts += 1
        elif w[0] == "vn":
            x, y, z = float(w[1]), float(w[2]), float(w[3])
            lines.append("vn %.5f %.5f %.5f" % (c * x - s * z, y, s * x + c * z))
            vns += 1
        elif w[0] == "f":
            out_f = []
            for ref in w[1:]:
                parts = ref.split("/")
                offs = (nv, nvt, nvn)
                out_f.append("/".join(str(int(p) + offs[k]) if p else "" for k, p in enumerate(parts)))
            lines.append("f " + " ".join(out_f))
        elif w[0] == "usemtl":
            lines.append("usemtl " + pre + w[1])
        elif w[0] in ("g", "o"):
            lines.append("g " + pre + (w[1] if len(w) > 1 else "tree"))
        elif w[0] == "mtllib":
            for m in open(os.path.join(tdir, " ".join(w[1:]))):
                mw = m.split()
                if mw and mw[0] == "newmtl":
                    m = "newmtl " + pre + mw[1] + "\n"
                elif mw and mw[0].startswith("map_"):  # textures by absolute path
                    m = mw[0] + " " + os.path.relpath(os.path.join(tdir, mw[-1]), odir) + "\n"
                mtl.append(m if m.endswith("\n") else m + "\n")
    nv, nvt, nvn = nv + vs, nvt + vts, nvn + vns
mname = os.path.splitext(os.path.basename(out))[0] + ".mtl"
with open(os.path.join(odir, mname), "w") as f:
    f.write("".join(mtl))
with open(out, "w") as f:
    f.write("# a test forest plot (scripts/bench/make_plot.py)\nmtllib %s\n" % mname)
    f.write("\n".join(lines) + "\n")
