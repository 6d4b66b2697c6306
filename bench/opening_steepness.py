#!/usr/bin/env python3
"""How steep a line of sight must be to cross a spanning surface of each
opening of a mesh at most once (docs/algorithms/render.md, "Open surfaces").

For every boundary loop of a PLY mesh (read as bench/llvmpipe_compare.py
reads it): its outward normal n (the Newell normal of the loop walked
against its faces' winding, as a cap closing the hole would be wound),
its radius and half thickness along n, and L, the largest slope of the
loop over its plane: max |h(p) - h(q)| / |p' - q'| over pairs of points
of the loop (h the height along n, p' the projection), sampled at
SAMPLES points per edge. When the projected loop is simple, a spanning
surface that is a graph over the plane with that slope exists, and a line
making less than atan(1 / L) with n crosses it at most once. Sampling can
only miss steeper pairs, so L is a lower bound: enough to show where such
a rule cannot apply. Last, the angle between n and the line of sight of
spatch's automatic camera (--eye-direction: the direction from the model
toward the eye).

Usage: bench/opening_steepness.py MESH.ply [--samples N]
           [--eye-direction X,Y,Z]
Needs numpy.
"""
import argparse
import os
import sys

try:
    import numpy as np
except ImportError:
    sys.exit("opening_steepness.py needs numpy (e.g. python3 -m venv /tmp/venv && /tmp/venv/bin/pip install numpy)")

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from llvmpipe_compare import read_ply  # noqa: E402


def boundary_loops(faces):
    """Each boundary loop as vertex indices, in the direction of its faces' edges."""
    edges = {e for a, b, c in faces for e in ((a, b), (b, c), (c, a))}
    nxt = {a: b for (a, b) in edges if (b, a) not in edges}
    loops, seen = [], set()
    for start in nxt:
        if start in seen:
            continue
        loop, v = [], start
        while v not in seen and v in nxt:
            seen.add(v)
            loop.append(v)
            v = nxt[v]
        loops.append(loop)
    return loops


def steepness(points, samples):
    """Outward normal, radius, half thickness and largest slope L of a loop
    given in cap order."""
    n = np.cross(points, np.roll(points, -1, axis=0)).sum(axis=0)
    n /= np.linalg.norm(n)
    centre = points.mean(axis=0)
    h = (points - centre) @ n
    u = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    w = np.cross(n, u)
    q = np.stack([(points - centre) @ u, (points - centre) @ w], axis=1)
    t = np.arange(samples) / samples
    qs = (q[:, None] * (1 - t)[None, :, None] + np.roll(q, -1, 0)[:, None] * t[None, :, None]).reshape(-1, 2)
    hs = (h[:, None] * (1 - t) + np.roll(h, -1)[:, None] * t).reshape(-1)
    slope = 0.0
    for k in range(0, len(qs), 512):
        dq = np.linalg.norm(qs[k:k + 512, None] - qs[None], axis=2)
        dh = np.abs(hs[k:k + 512, None] - hs[None])
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(dq > 0, dh / dq, 0.0)
        slope = max(slope, ratio.max())
    radius = np.linalg.norm(q, axis=1).max()
    return n, radius, (h.max() - h.min()) / 2, slope


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh")
    parser.add_argument("--samples", type=int, default=8)
    parser.add_argument("--eye-direction", default="1,0.7,1.3",
                        help="direction from the model toward the eye (spatch's automatic camera)")
    args = parser.parse_args()
    vertices, faces = read_ply(args.mesh)
    vertices = vertices.astype(np.float64)
    faces = faces.tolist()
    toward_eye = np.array([float(x) for x in args.eye_direction.split(",")])
    sight = -toward_eye / np.linalg.norm(toward_eye)
    print("vertices  radius      half-thickness/radius  L      atan(1/L)  angle(sight, n)")
    for loop in boundary_loops(faces):
        if len(loop) < 3:
            continue
        n, radius, half, slope = steepness(vertices[loop][::-1], args.samples)
        limit = np.degrees(np.arctan2(1.0, slope))
        angle = np.degrees(np.arccos(np.clip(sight @ n, -1, 1)))
        print(f"{len(loop):8d}  {radius:.4e}  {half / radius:21.3f}  {slope:5.3f}  "
              f"{limit:8.1f}°  {angle:14.1f}°")


if __name__ == "__main__":
    main()
