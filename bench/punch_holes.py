#!/usr/bin/env python3
"""Writes a mesh (PLY or OBJ) with small holes punched in it, as a binary PLY.

What a scan full of small holes hands a user: the surface with `COUNT` faces left out,
chosen at random (seeded) among faces that share no vertex with another left-out face, so
each is an opening of its own. `spatch convert` stores at most 256 openings; a mesh with more
is drawn from both sides everywhere (merging them was measured and not kept:
docs/algorithms/render.md, "Open surfaces").

Usage: python3 bench/punch_holes.py IN.(ply|obj) OUT.ply COUNT [--seed S]
Needs numpy (the setup of bench/llvmpipe_compare.py).
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from llvmpipe_compare import read_mesh  # noqa: E402
from turn_faces import write_ply  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("mesh")
    p.add_argument("out")
    p.add_argument("count", type=int)
    p.add_argument("--seed", type=int, default=1)
    a = p.parse_args()
    v, f = read_mesh(a.mesh)
    f = np.asarray(f)
    rng = np.random.default_rng(a.seed)
    taken = np.zeros(len(v), dtype=bool)
    holes = []
    for t in rng.permutation(len(f)):
        if len(holes) == a.count:
            break
        if not taken[f[t]].any():
            taken[f[t]] = True
            holes.append(t)
    keep = np.ones(len(f), dtype=bool)
    keep[holes] = False
    write_ply(a.out, v, f[keep])
    print(f"{a.out}: {len(holes)} of {len(f)} faces left out")


if __name__ == "__main__":
    main()
