#!/usr/bin/env python3
"""Writes a flat unit square of N x N cells as an OBJ, two triangles per cell.

The benchmark input of docs/performance.md's error-measurement section: with the default
N = 707 the square has 708^2 vertices and 999,698 triangles (about 1 M).

Usage: python3 bench/plane_obj.py OUT.obj [N]
"""
import sys


def main() -> None:
    if len(sys.argv) not in (2, 3):
        sys.exit("usage: plane_obj.py OUT.obj [N]")
    out = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) == 3 else 707
    step = 1.0 / n
    with open(out, "w") as f:
        for j in range(n + 1):
            y = j * step
            f.write("".join(f"v {i * step:.7f} {y:.7f} 0\n" for i in range(n + 1)))
        row = n + 1
        for j in range(n):
            lines = []
            for i in range(n):
                a = j * row + i + 1  # OBJ indices start at 1
                b, c, d = a + 1, a + row, a + row + 1
                lines.append(f"f {a} {b} {d}\nf {a} {d} {c}\n")
            f.write("".join(lines))


if __name__ == "__main__":
    main()
