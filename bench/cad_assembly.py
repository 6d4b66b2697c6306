#!/usr/bin/env python3
"""Writes a CAD assembly as one OBJ: copies of the shared CAD parts, each rotated, scaled and
placed, one `o` object per part.

The shared data has single CAD parts only (cad/fandisk.obj, cad/cube-meshed.ply,
cad/cylinder.ply); issue 22 item 8 measures the crease patches of assemblies too (its
example: 29 meshes, 75k triangles). This places 29 parts (3 fandisks, 13 meshed cubes,
13 open tubes) on a 6 x 5 grid of cells 1.1 wide, every part scaled to a size from 0.6 to
1.0 and turned about a random axis (fixed seed), so parts sit close and some overlap, as
bolts sit in plates. About 90k triangles. Docs: docs/algorithms/edges.md.

Usage: python3 bench/cad_assembly.py DATA_DIR OUT.obj [SEED]
  (DATA_DIR: the shared data folder, the one holding cad/)
"""
import math
import random
import sys


def read_obj(path):
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                verts.append(tuple(float(x) for x in parts[1:4]))
            elif parts[0] == "f":
                idx = [int(p.split("/")[0]) for p in parts[1:]]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    faces.append((idx[0], idx[k], idx[k + 1]))
    return verts, faces


def read_ascii_ply(path):
    with open(path) as f:
        lines = f.read().split("\n")
    nv = nf = 0
    k = 0
    while lines[k].strip() != "end_header":
        parts = lines[k].split()
        if parts[:2] == ["element", "vertex"]:
            nv = int(parts[2])
        elif parts[:2] == ["element", "face"]:
            nf = int(parts[2])
        k += 1
    k += 1
    verts = [tuple(float(x) for x in lines[k + i].split()[:3]) for i in range(nv)]
    faces = []
    for i in range(nf):
        idx = [int(x) for x in lines[k + nv + i].split()[1:]]
        for j in range(1, len(idx) - 1):
            faces.append((idx[0], idx[j], idx[j + 1]))
    return verts, faces


def normalized(part):
    """The part centred on the origin, its largest side 1."""
    verts, faces = part
    lo = [min(v[i] for v in verts) for i in range(3)]
    hi = [max(v[i] for v in verts) for i in range(3)]
    centre = [(lo[i] + hi[i]) / 2 for i in range(3)]
    size = max(hi[i] - lo[i] for i in range(3))
    return [tuple((v[i] - centre[i]) / size for i in range(3)) for v in verts], faces


def rotation(rng):
    """A rotation matrix about a random unit axis by a random angle."""
    z = rng.uniform(-1, 1)
    t = rng.uniform(0, 2 * math.pi)
    r = math.sqrt(1 - z * z)
    x, y = r * math.cos(t), r * math.sin(t)
    a = rng.uniform(0, 2 * math.pi)
    c, s, C = math.cos(a), math.sin(a), 1 - math.cos(a)
    return [
        [c + x * x * C, x * y * C - z * s, x * z * C + y * s],
        [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
        [z * x * C - y * s, z * y * C + x * s, c + z * z * C],
    ]


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit("usage: cad_assembly.py DATA_DIR OUT.obj [SEED]")
    data, out = sys.argv[1], sys.argv[2]
    rng = random.Random(int(sys.argv[3]) if len(sys.argv) == 4 else 22)
    parts = {
        "fandisk": normalized(read_obj(f"{data}/cad/fandisk.obj")),
        "cube": normalized(read_ascii_ply(f"{data}/cad/cube-meshed.ply")),
        "tube": normalized(read_ascii_ply(f"{data}/cad/cylinder.ply")),
    }
    names = ["fandisk"] * 3 + ["cube"] * 13 + ["tube"] * 13
    rng.shuffle(names)
    base = 1
    with open(out, "w") as f:
        f.write("# CAD assembly written by bench/cad_assembly.py from the shared CAD parts\n")
        for k, name in enumerate(names):
            verts, faces = parts[name]
            m = rotation(rng)
            scale = rng.uniform(0.6, 1.0)
            offset = (1.1 * (k % 6), 1.1 * (k // 6), rng.uniform(-0.2, 0.2))
            f.write(f"o {name}_{k}\n")
            for v in verts:
                p = [sum(m[i][j] * v[j] for j in range(3)) * scale + offset[i] for i in range(3)]
                f.write(f"v {p[0]:.7f} {p[1]:.7f} {p[2]:.7f}\n")
            for a, b, c in faces:
                f.write(f"f {a + base} {b + base} {c + base}\n")
            base += len(verts)


if __name__ == "__main__":
    main()
