#!/usr/bin/env python3
"""Triangulates a raw range scan (an ASCII PLY with a `range_grid`, as the Stanford scans
under ../shared/data/bunny/data) into a mesh, as a scanner's software does: each square of
four neighbouring grid samples gives two triangles, kept when their edges are shorter than
4 times the median step between row neighbours (so depth jumps stay open). Triangles are
wound in the grid's image order, which faces them away from the scanner: the kind of scan
mesh with open borders and reversed winding a user may bring.

Usage: python3 bench/range_grid_mesh.py bun000.ply OUT.ply
Needs numpy; writes a binary PLY (bench/turn_faces.py's writer).
"""

import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from turn_faces import write_ply  # noqa: E402


def read_range_grid(path):
    """(points, grid of point indices, -1 where empty) of an ASCII range-grid PLY."""
    with open(path, "rb") as f:
        cols = rows = points = cells = 0
        while True:
            words = f.readline().decode("ascii", "replace").split()
            if words[:2] == ["obj_info", "num_cols"]:
                cols = int(words[2])
            elif words[:2] == ["obj_info", "num_rows"]:
                rows = int(words[2])
            elif words[:2] == ["element", "vertex"]:
                points = int(words[2])
            elif words[:2] == ["element", "range_grid"]:
                cells = int(words[2])
            elif words == ["end_header"]:
                break
        lines = f.read().decode("ascii").split("\n")
    v = np.array([[float(x) for x in line.split()[:3]] for line in lines[:points]])
    grid = np.full(cells, -1, dtype=np.int64)
    for k, line in enumerate(lines[points:points + cells]):
        words = line.split()
        if words and words[0] != "0":
            grid[k] = int(words[1])
    return v, grid.reshape(rows, cols)


def triangulate(v, g):
    """The grid's two triangles per square of four samples, without long edges."""
    a, b, c, d = g[:-1, :-1], g[:-1, 1:], g[1:, :-1], g[1:, 1:]
    steps = np.linalg.norm(v[g[:, 1:]] - v[g[:, :-1]], axis=2)[(g[:, 1:] >= 0) & (g[:, :-1] >= 0)]
    limit = 4 * np.median(steps)
    # Per square, row by row: (a, c, b) then (b, c, d).
    tris = np.stack([np.stack([a, c, b], -1), np.stack([b, c, d], -1)], 2).reshape(-1, 3)
    tris = tris[(tris >= 0).all(axis=1)]
    p = v[tris]
    longest = np.max(np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2), axis=1)
    return tris[longest < limit]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    v, g = read_range_grid(sys.argv[1])
    f = triangulate(v, g)
    write_ply(sys.argv[2], v, f)
    print(f"{sys.argv[2]}: {len(v)} points, {len(f)} triangles")


if __name__ == "__main__":
    main()
