#!/usr/bin/env python3
"""Holes and silhouettes of spatch's patches against Mesa llvmpipe drawing the source mesh.

The hole measure of ../shared/MEASURES.md ("Holes") with an independent reference: llvmpipe
(headless EGL through moderngl) draws every triangle of the source mesh (PLY or OBJ) with the
depth test and no culling, and writes each pixel's eye depth; `spatch render SCENE` draws
the patches with its defaults (or the flags after `--`) at the same camera and writes its
depth (`--depth FILE.tif`). Views: the 14 of MEASURES.md (6 axes, 8 diagonals), fov 40°,
target the bounding box centre c, eye at c + d · R / sin(20°) · 1.05 (R the half diagonal),
up +y (+z when looking along y), at every size asked for.

Per size it prints, summed over the views:
- holes: pixels of the reference eroded by 2 px that spatch leaves empty or draws more than
  --tolerance · R behind the reference (a see-through hole shows a farther surface), over
  the eroded reference's pixels (of them, "see-through": drawn, but behind);
- overreach: pixels spatch draws farther than 2 px from the reference (past the
  silhouette), over the reference's pixels. A surface seen exactly edge-on (a flat sheet
  from its side) counts here: llvmpipe draws no triangle of zero area, spatch a line.

Setup (Debian): apt-get install libgl1-mesa-dri libegl1; then
  python3 -m venv /tmp/venv && /tmp/venv/bin/pip install moderngl numpy pillow
Usage:
  /tmp/venv/bin/python bench/llvmpipe_holes.py --spatch target/release/spatch \\
      --mesh bun_zipper.ply --scene bunny.spatch --sizes 500 1000 [--json] \\
      [--max-holes PERCENT] [-- extra spatch render flags]
With --max-holes it exits 1 when a size's hole fraction exceeds PERCENT. With --save DIR it
writes each view's map as DIR/SIZE_VIEW.png: the reference grey, holes left empty red,
see-through holes blue, overreach green.
"""

import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from llvmpipe_compare import (  # noqa: E402
    box_centre_radius,
    comparison_parser,
    look_at,
    perspective,
    read_mesh,
    split_spatch_flags,
)

VERTEX = """
#version 330
uniform mat4 mvp;
uniform mat4 view;
in vec3 pos;
out float eye_depth;
void main() {
    eye_depth = -(view * vec4(pos, 1.0)).z;
    gl_Position = mvp * vec4(pos, 1.0);
}
"""

FRAGMENT = """
#version 330
in float eye_depth;
out float depth;
void main() {
    depth = eye_depth;
}
"""


def standard_views():
    """The 14 view directions (target to eye): the 6 axes, then the 8 diagonals."""
    views = [np.array(v, dtype=np.float64) for v in np.vstack([np.eye(3), -np.eye(3)])]
    views = [views[k] for k in (0, 3, 1, 4, 2, 5)]
    for sx in (1, -1):
        for sy in (1, -1):
            for sz in (1, -1):
                views.append(np.array([sx, sy, sz], dtype=np.float64) / math.sqrt(3))
    return views


class Camera:
    """Eye, target, up and near/far of one view of a box with centre `c`, half diagonal `r`."""

    def __init__(self, c, r, direction, fov):
        self.eye = c + direction * r / math.sin(math.radians(fov / 2)) * 1.05
        self.target = c
        self.up = np.array([0.0, 0.0, 1.0] if abs(direction[1]) > 0.99 else [0.0, 1.0, 0.0])
        dist = np.linalg.norm(self.eye - c)
        self.near, self.far = max(dist - r, dist / 1000) * 0.99, (dist + r) * 1.01


class Reference:
    """llvmpipe drawing the mesh's eye depth into a float framebuffer (no culling)."""

    def __init__(self, v, f):
        import moderngl

        self.ctx = moderngl.create_context(standalone=True, backend="egl")
        renderer = self.ctx.info.get("GL_RENDERER", "?")
        if "llvmpipe" not in renderer:
            sys.exit(f"the GL context is {renderer!r}, not llvmpipe")
        self.prog = self.ctx.program(vertex_shader=VERTEX, fragment_shader=FRAGMENT)
        vbo = self.ctx.buffer(v.astype("f4").tobytes())
        ibo = self.ctx.buffer(f.astype("u4").tobytes())
        self.vao = self.ctx.vertex_array(self.prog, [(vbo, "3f", "pos")], ibo)
        self.ctx.enable(moderngl.DEPTH_TEST)
        self.ctx.disable(moderngl.CULL_FACE)

    def depth(self, camera, fov, size):
        """Eye depth per pixel, rows from the top, NaN where no triangle is drawn."""
        view = look_at(camera.eye, camera.target, camera.up)
        mvp = perspective(fov, 1.0, camera.near, camera.far) @ view
        self.prog["mvp"].write(mvp.T.astype("f4").tobytes())
        self.prog["view"].write(view.T.astype("f4").tobytes())
        colour = self.ctx.texture((size, size), 1, dtype="f4")
        depth = self.ctx.depth_renderbuffer((size, size))
        fbo = self.ctx.framebuffer(color_attachments=[colour], depth_attachment=depth)
        fbo.use()
        fbo.clear(red=float("nan"), depth=1.0)
        self.vao.render()
        data = np.frombuffer(fbo.read(components=1, dtype="f4"), dtype=np.float32)
        for thing in (fbo, colour, depth):
            thing.release()
        return data.reshape(size, size)[::-1]


def spatch_depth(args, camera, size, extra, work):
    """spatch's eye depth of the same view (NaN where nothing is drawn)."""
    from PIL import Image

    vec = lambda p: ",".join(f"{x:.9g}" for x in p)
    image, depth = os.path.join(work, "view.png"), os.path.join(work, "view.tif")
    cmd = [
        args.spatch, "render", args.scene, "-o", image, "--depth", depth,
        "--width", str(size), "--height", str(size), "--threads", "2",
        f"--eye={vec(camera.eye)}", f"--target={vec(camera.target)}",
        f"--up={vec(camera.up)}", "--fov", str(args.fov),
    ] + extra
    subprocess.run(cmd, check=True, capture_output=True, text=True)
    return np.asarray(Image.open(depth), dtype=np.float32)


def grow(mask, px):
    """`mask` dilated by a (2 px + 1)² square."""
    out = mask.copy()
    h, w = mask.shape
    for dy in range(-px, px + 1):
        for dx in range(-px, px + 1):
            shifted = np.zeros_like(mask)
            shifted[max(dy, 0):h + min(dy, 0), max(dx, 0):w + min(dx, 0)] = mask[
                max(-dy, 0):h + min(-dy, 0), max(-dx, 0):w + min(-dx, 0)
            ]
            out |= shifted
    return out


def compare(reference, patches, tolerance):
    """(eroded reference pixels, holes, of them drawn behind, reference pixels, overreach) of
    one view."""
    covered = np.isfinite(reference)
    inner = ~grow(~covered, 2)
    drawn = np.isfinite(patches)
    behind = drawn & covered & (patches > reference + tolerance)
    holes = inner & (~drawn | behind)
    overreach = drawn & ~grow(covered, 2)
    counts = (inner, holes, inner & behind, covered, overreach)
    return tuple(int(m.sum()) for m in counts), (covered, holes & ~behind, holes & behind, overreach)


def save_map(path, masks):
    """One view's comparison as an RGB image (see the module docs for the colours)."""
    from PIL import Image

    covered, empty, behind, overreach = masks
    rgb = np.zeros(covered.shape + (3,), dtype=np.uint8)
    rgb[covered] = (96, 96, 96)
    for mask, colour in ((empty, (255, 0, 0)), (behind, (0, 96, 255)), (overreach, (0, 255, 0))):
        rgb[mask] = colour
    Image.fromarray(rgb).save(path)


def main():
    argv, extra = split_spatch_flags(sys.argv[1:])
    p = comparison_parser(__doc__)
    p.add_argument("--sizes", type=int, nargs="+", default=[500])
    p.add_argument("--fov", type=float, default=40.0)
    p.add_argument("--tolerance", type=float, default=0.02,
                   help="depth behind the reference that still covers it, in R (default 0.02)")
    p.add_argument("--max-holes", type=float, help="fail when holes exceed this percent")
    p.add_argument("--json", action="store_true")
    p.add_argument("--save", metavar="DIR", help="write each view's map of holes as a PNG here")
    args = p.parse_args(argv)
    v, f = read_mesh(args.mesh)[:2]
    c, r = box_centre_radius(v)
    peer = Reference(v, f)
    rows, failed = [], False
    with tempfile.TemporaryDirectory() as work:
        for size in args.sizes:
            totals = np.zeros(5, dtype=np.int64)
            for view, direction in enumerate(standard_views()):
                camera = Camera(c, r, direction, args.fov)
                reference = peer.depth(camera, args.fov, size)
                patches = spatch_depth(args, camera, size, extra, work)
                counts, masks = compare(reference, patches, args.tolerance * r)
                totals += counts
                if args.save:
                    os.makedirs(args.save, exist_ok=True)
                    save_map(os.path.join(args.save, f"{size}_{view:02}.png"), masks)
            inner, holes, behind, covered, over = (int(t) for t in totals)
            row = {
                "size": size,
                "reference_pixels": inner,
                "hole_pixels": holes,
                "holes_percent": 100 * holes / max(inner, 1),
                "see_through_pixels": behind,
                "overreach_pixels": over,
                "overreach_percent": 100 * over / max(covered, 1),
            }
            rows.append(row)
            failed |= args.max_holes is not None and row["holes_percent"] > args.max_holes
    if args.json:
        print(json.dumps({"renderer": "llvmpipe", "scene": args.scene, "sizes": rows}))
    else:
        print(f"{args.scene} against llvmpipe (no culling), 14 views; spatch flags: {extra}")
        for row in rows:
            print(
                f"  {row['size']}²: holes {row['hole_pixels']} of {row['reference_pixels']} "
                f"({row['holes_percent']:.4f} %; {row['see_through_pixels']} see-through), "
                f"overreach {row['overreach_pixels']} ({row['overreach_percent']:.4f} %)"
            )
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
