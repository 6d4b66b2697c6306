#!/usr/bin/env python3
"""Writes a rolling terrain of N x N cells (1 m each) as a binary little-endian PLY mesh.

The input of docs/scale.md's mesh-tile memory figures: the density is fixed (two triangles
per square metre), so a larger N gives a larger terrain, not a finer one, and a tile of a
given size holds the same faces whatever N is. Heights are a few sine waves (up to about
6 m), so the surface is not flat and segmentation has work to do.

Usage: python3 bench/terrain_ply.py OUT.ply N
"""
import math
import struct
import sys


def height(x: float, y: float) -> float:
    return 3.0 * math.sin(x / 17.0) * math.cos(y / 23.0) + 1.5 * math.sin((x + y) / 7.0)


def main() -> None:
    if len(sys.argv) != 3:
        sys.exit("usage: terrain_ply.py OUT.ply N")
    out, n = sys.argv[1], int(sys.argv[2])
    row = n + 1
    with open(out, "wb") as f:
        header = (
            "ply\nformat binary_little_endian 1.0\n"
            f"element vertex {row * row}\nproperty float x\nproperty float y\nproperty float z\n"
            f"element face {2 * n * n}\nproperty list uchar int vertex_indices\nend_header\n"
        )
        f.write(header.encode())
        pack = struct.Struct("<fff").pack
        for j in range(row):
            f.write(b"".join(pack(i, j, height(i, j)) for i in range(row)))
        tri = struct.Struct("<Biii").pack
        for j in range(n):
            faces = []
            for i in range(n):
                a = j * row + i
                b, c, d = a + 1, a + row, a + row + 1
                faces.append(tri(3, a, b, d) + tri(3, a, d, c))
            f.write(b"".join(faces))


if __name__ == "__main__":
    main()
