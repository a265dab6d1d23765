#!/usr/bin/env python3
"""Writes scenes/cube_room.obj and scenes/cube_room.mtl: the cube room of the thesis'
Figures 6.7, 6.8, 6.10 and 6.11 (Feixas 2002, section 6.4.2) as far as its text tells it --
a room with a table and chairs, "the shadow of the chair near the right wall" (6.7b), the
chair's shadow on "the front wall" (6.8b), "the shadows on the table" (6.8b). Everything
else (sizes, the light, the materials, where each chair stands) is invented here and listed
in docs/chapter6-protocol.md. Run from the repository root: python3 scripts/cube_room.py

Units: metres; y is up; the room is the cube [0, 4]^3 seen from inside (faces
counter-clockwise seen from the side light reaches). Every face is cut into a grid of
cells no longer than MAX_EDGE, so the roots of the hierarchy are of similar size.
"""

import math

MAX_EDGE = 0.5
SIDE = 4.0
LIGHT = (1.5, 2.5, 1.5, 2.5)  # x0, x1, z0, z1: a 1 m x 1 m ceiling light at the centre
LIGHT_GAP = 0.01  # the light hangs 1 cm below the ceiling

MATERIALS = {
    "wall": ((0.70, 0.70, 0.68), None),
    "floor": ((0.45, 0.38, 0.30), None),
    "ceiling": ((0.75, 0.75, 0.75), None),
    "table": ((0.55, 0.40, 0.25), None),
    "chair": ((0.60, 0.20, 0.15), None),
    "light": ((0.0, 0.0, 0.0), (12.0, 12.0, 11.0)),
}

out = []
verts = []


def vid(p):
    verts.append(p)
    return len(verts)


def quad(a, b, c, d):
    """A planar quad a b c d (counter-clockwise seen from its front), cut into cells."""
    def lerp(p, q, t):
        return tuple(p[i] + (q[i] - p[i]) * t for i in range(3))

    def dist(p, q):
        return math.sqrt(sum((p[i] - q[i]) ** 2 for i in range(3)))

    n = max(1, math.ceil(max(dist(a, b), dist(d, c)) / MAX_EDGE - 1e-9))
    m = max(1, math.ceil(max(dist(a, d), dist(b, c)) / MAX_EDGE - 1e-9))
    for i in range(n):
        for j in range(m):
            def at(u, v):
                return lerp(lerp(a, b, u), lerp(d, c, u), v)
            p = [at(i / n, j / m), at((i + 1) / n, j / m), at((i + 1) / n, (j + 1) / m), at(i / n, (j + 1) / m)]
            ids = [vid(q) for q in p]
            out.append("f " + " ".join(str(k) for k in ids))


def box(x0, x1, y0, y1, z0, z1, skip=()):
    """The outside faces of an axis-aligned box, except those named in skip."""
    faces = {
        "-y": [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],
        "+y": [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)],
        "-x": [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],
        "+x": [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)],
        "-z": [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)],
        "+z": [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],
    }
    for k, f in faces.items():
        if k not in skip:
            quad(*f)


def table(cx, cz, w, d, h=0.75, top=0.05, leg=0.06):
    out.append("o table")
    out.append("usemtl table")
    box(cx - w / 2, cx + w / 2, h - top, h, cz - d / 2, cz + d / 2)
    for sx in (-1, 1):
        for sz in (-1, 1):
            x = cx + sx * (w / 2 - 0.08)
            z = cz + sz * (d / 2 - 0.08)
            box(x - leg / 2, x + leg / 2, 0.0, h - top, z - leg / 2, z + leg / 2, skip=("-y", "+y"))


def chair(name, cx, cz, facing, s=0.45, h=0.45, seat=0.04, leg=0.04, back=0.45, bt=0.04):
    """A chair centred at (cx, cz) whose sitter faces `facing` (+x, -x, +z or -z): the
    back stands on the seat's opposite edge."""
    out.append(f"o {name}")
    out.append("usemtl chair")
    x0, x1, z0, z1 = cx - s / 2, cx + s / 2, cz - s / 2, cz + s / 2
    box(x0, x1, h - seat, h, z0, z1)
    for x in (x0 + 0.03, x1 - 0.03 - leg):
        for z in (z0 + 0.03, z1 - 0.03 - leg):
            box(x, x + leg, 0.0, h - seat, z, z + leg, skip=("-y", "+y"))
    if facing == "+x":
        box(x0, x0 + bt, h, h + back, z0, z1, skip=("-y",))
    elif facing == "-x":
        box(x1 - bt, x1, h, h + back, z0, z1, skip=("-y",))
    elif facing == "+z":
        box(x0, x1, h, h + back, z0, z0 + bt, skip=("-y",))
    else:
        box(x0, x1, h, h + back, z1 - bt, z1, skip=("-y",))


S = SIDE
# The room, faces towards the inside. Front wall z = 0, right wall x = S (seen from the front).
out.append("o room")
out.append("usemtl floor")
quad((0, 0, 0), (0, 0, S), (S, 0, S), (S, 0, 0))
out.append("usemtl ceiling")
quad((0, S, 0), (S, S, 0), (S, S, S), (0, S, S))
out.append("usemtl wall")
quad((0, 0, 0), (S, 0, 0), (S, S, 0), (0, S, 0))  # front, z = 0
quad((0, 0, S), (0, S, S), (S, S, S), (S, 0, S))  # back, z = S
quad((0, 0, 0), (0, S, 0), (0, S, S), (0, 0, S))  # left, x = 0
quad((S, 0, 0), (S, 0, S), (S, S, S), (S, S, 0))  # right, x = S
out.append("o light")
out.append("usemtl light")
x0, x1, z0, z1 = LIGHT
y = S - LIGHT_GAP
quad((x0, y, z0), (x1, y, z0), (x1, y, z1), (x0, y, z1))
table(2.0, 2.2, 1.4, 0.9)
chair("chair near the right wall", 3.55, 2.2, "-x")
chair("chair near the front wall", 2.0, 0.45, "+z")
chair("chair left", 0.95, 2.2, "+x")
chair("chair back", 2.0, 3.15, "-z")

header = [
    "# The cube room of Feixas (2002), Figs. 6.7, 6.8, 6.10, 6.11: a room with a table and",
    "# four chairs. Written by scripts/cube_room.py; what is invented: docs/chapter6-protocol.md.",
    "# Licence: CC0 (written for sceneinfo).",
    "mtllib cube_room.mtl",
]
with open("scenes/cube_room.obj", "w") as f:
    f.write("\n".join(header) + "\n")
    for p in verts:
        f.write("v %.4f %.4f %.4f\n" % p)
    f.write("\n".join(out) + "\n")
with open("scenes/cube_room.mtl", "w") as f:
    f.write("# Materials of scenes/cube_room.obj (invented; scripts/cube_room.py)\n")
    for name, (kd, ke) in MATERIALS.items():
        f.write(f"newmtl {name}\nKd {kd[0]} {kd[1]} {kd[2]}\n")
        if ke:
            f.write(f"Ke {ke[0]} {ke[1]} {ke[2]}\n")
print(len(verts), "vertices", sum(1 for l in out if l.startswith("f ")), "faces")
