#!/usr/bin/env python3
"""Cuts every triangle of a mesh (PLY or OBJ) into four at its edge midpoints, N times, and
writes a binary PLY: a dense scan's triangle count on the same surface (the bunny's 69,451
triangles become 1,111,216 with N = 2), for timing what a triangle count costs the
converter, its error measure and llvmpipe.

Usage: python3 bench/subdivide_mesh.py IN.(ply|obj) OUT.ply [N]   (default N = 2)
Needs numpy (the setup of bench/llvmpipe_compare.py).
"""

import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from llvmpipe_compare import read_mesh  # noqa: E402
from turn_faces import write_ply  # noqa: E402


def subdivide(v, f):
    """One step: a vertex at each edge's midpoint, four triangles per triangle (same winding)."""
    n = len(f)
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    unique, index = np.unique(edges, axis=0, return_inverse=True)
    mid = index.reshape(-1) + len(v)
    v = np.concatenate([v, (v[unique[:, 0]] + v[unique[:, 1]]) / 2])
    ab, bc, ca = mid[:n], mid[n:2 * n], mid[2 * n:]
    a, b, c = f[:, 0], f[:, 1], f[:, 2]
    f = np.concatenate([np.stack(t, 1) for t in ([a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca])])
    return v, f


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    v, f = read_mesh(sys.argv[1])[:2]
    v, f = np.asarray(v, dtype=np.float64), np.asarray(f, dtype=np.int64)
    for _ in range(int(sys.argv[3]) if len(sys.argv) == 4 else 2):
        v, f = subdivide(v, f)
    write_ply(sys.argv[2], v, f)
    print(f"{sys.argv[2]}: {len(v)} vertices, {len(f)} triangles")


if __name__ == "__main__":
    main()
