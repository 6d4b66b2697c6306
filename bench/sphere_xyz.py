#!/usr/bin/env python3
"""Writes N points on a wavy unit sphere as an XYZ text cloud (one `x y z` line a point).

The cloud benchmark of docs/performance.md's error-measurement section (issue 19: the
`--report` of a 1 M-point cloud against the conversion alone). Directions are uniform on
the sphere (seeded, so the file is the same on every run); the radius is
1 + 0.05 sin(5 lon) sin(4 lat), a relief of a few hundred point spacings a wave, so the
patches are curved and their cells twisted, unlike the plane of plane_obj.py.

Usage: python3 bench/sphere_xyz.py OUT.xyz [N] [SEED]   (N = 1,000,000, SEED = 1)
"""
import math
import random
import sys


def main() -> None:
    if len(sys.argv) not in (2, 3, 4):
        sys.exit("usage: sphere_xyz.py OUT.xyz [N] [SEED]")
    out = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) >= 3 else 1_000_000
    rng = random.Random(int(sys.argv[3]) if len(sys.argv) == 4 else 1)
    with open(out, "w") as f:
        lines = []
        for _ in range(n):
            z = rng.uniform(-1.0, 1.0)
            lon = rng.uniform(-math.pi, math.pi)
            lat = math.asin(z)
            r = 1.0 + 0.05 * math.sin(5.0 * lon) * math.sin(4.0 * lat)
            ring = math.sqrt(max(0.0, 1.0 - z * z)) * r
            lines.append(f"{ring * math.cos(lon):.6f} {ring * math.sin(lon):.6f} {z * r:.6f}\n")
            if len(lines) == 65536:
                f.write("".join(lines))
                lines.clear()
        f.write("".join(lines))


if __name__ == "__main__":
    main()
