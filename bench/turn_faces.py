#!/usr/bin/env python3
"""Writes a mesh (PLY or OBJ) with its faces wound the other way, as a binary PLY.

What an exporter that mirrors, or a scan triangulated in the wrong order, hands a user:
the same surface facing in. `spatch convert` winds it back (docs/algorithms/mesh.md,
"Orientation"); `--keep-winding` shows what culling makes of it.

Usage: python3 bench/turn_faces.py IN.(ply|obj) OUT.ply [--every N]
With --every N only faces 0, N, 2N, ... are turned (scattered flips).
Needs numpy (the setup of bench/llvmpipe_compare.py).
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from llvmpipe_compare import read_mesh  # noqa: E402


def write_ply(path, v, f):
    """Float positions and int triangles as a little-endian binary PLY."""
    header = (
        f"ply\nformat binary_little_endian 1.0\nelement vertex {len(v)}\n"
        "property float x\nproperty float y\nproperty float z\n"
        f"element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    faces = np.zeros(len(f), dtype=[("n", "u1"), ("i", "<i4", 3)])
    faces["n"], faces["i"] = 3, f
    with open(path, "wb") as out:
        out.write(header.encode())
        out.write(np.asarray(v, dtype="<f4").tobytes())
        out.write(faces.tobytes())


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("mesh")
    p.add_argument("out")
    p.add_argument("--every", type=int, default=1, help="turn only every N-th face (default 1)")
    args = p.parse_args()
    v, f = read_mesh(args.mesh)[:2]
    f = np.array(f, dtype=np.int64)
    turn = np.arange(len(f)) % max(args.every, 1) == 0
    f[turn] = f[turn][:, [0, 2, 1]]
    write_ply(args.out, v, f)
    print(f"{args.out}: {int(turn.sum())} of {len(f)} faces turned")


if __name__ == "__main__":
    main()
