#!/usr/bin/env python3
"""Frame time of spatch's patches against Mesa llvmpipe drawing the source mesh.

The comparison of ../shared/MEASURES.md ("Frame time against a peer
renderer"): llvmpipe (headless EGL through moderngl, LP_NUM_THREADS=2) draws
every triangle of the source mesh (PLY or OBJ) with smooth vertex normals, per-pixel
Blinn-Phong, depth test and no culling; frame = draw + finish. spatch renders
the converted scene with `spatch render SCENE --bench N --threads 2 --json`.
Both use the camera of MEASURES.md (bounding-box centre c, half diagonal R,
direction normalize(1, 0.7, 1.3), fov 40°, eye c + d R / sin 20° · 1.05,
up +y), passed to spatch as --eye/--target/--fov. Rounds alternate peer and
spatch; the ratio of the medians of each round is printed, then the median
over rounds.

With --textured (OBJ with `vt` coordinates and a material's `map_Kd`
image; without materials the image `spatch convert` would guess, or the
one named by --texture) llvmpipe samples that texture per pixel for the albedo, bilinearly
with mipmaps, as a viewer of the textured model would; spatch draws the
texture from its colour grids either way. Without it the peer draws every
mesh in plain grey, the measure of MEASURES.md.

Setup (Debian): apt-get install libgl1-mesa-dri libegl1; then
  python3 -m venv /tmp/venv && /tmp/venv/bin/pip install moderngl numpy pillow
Usage:
  LP_NUM_THREADS=2 /tmp/venv/bin/python bench/llvmpipe_compare.py \\
      --spatch target/release/spatch --mesh bun_zipper.ply --scene bunny.spatch \\
      --size 500 --rounds 3 --frames 20 [--textured] [-- extra spatch render flags]
"""

import argparse
import json
import math
import os
import statistics
import struct
import subprocess
import sys
import time
from typing import NamedTuple

import numpy as np

PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
    "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}


def read_ply(path):
    """Vertices (n, 3) float32 and triangles (m, 3) uint32 of a PLY file
    (ascii or binary little endian; polygons fanned into triangles)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii", "replace").splitlines()
    fmt, elements = None, []
    for line in header:
        words = line.split()
        if not words:
            continue
        if words[0] == "format":
            fmt = words[1]
        elif words[0] == "element":
            elements.append({"name": words[1], "count": int(words[2]), "props": []})
        elif words[0] == "property":
            elements[-1]["props"].append(words[1:])
    body = data[end:]
    verts, faces = None, []
    if fmt == "ascii":
        tokens = body.split()
        at = 0
        for el in elements:
            if el["name"] == "vertex":
                n = len(el["props"])
                vals = np.array(tokens[at:at + n * el["count"]], dtype=np.float64)
                at += n * el["count"]
                names = [p[-1] for p in el["props"]]
                vals = vals.reshape(el["count"], n)
                verts = vals[:, [names.index(c) for c in "xyz"]].astype(np.float32)
            else:
                for _ in range(el["count"]):
                    for p in el["props"]:
                        if p[0] == "list":
                            k = int(tokens[at])
                            idx = [int(t) for t in tokens[at + 1:at + 1 + k]]
                            at += 1 + k
                            if el["name"] == "face":
                                faces.extend([idx[0], idx[i], idx[i + 1]] for i in range(1, k - 1))
                        else:
                            at += 1
    elif fmt == "binary_little_endian":
        at = 0
        for el in elements:
            props = el["props"]
            if all(p[0] != "list" for p in props):
                dt = np.dtype([(p[-1], "<" + PLY_TYPES[p[0]]) for p in props])
                arr = np.frombuffer(body, dtype=dt, count=el["count"], offset=at)
                at += dt.itemsize * el["count"]
                if el["name"] == "vertex":
                    verts = np.stack([arr[c] for c in "xyz"], axis=1).astype(np.float32)
                continue
            # A list property: assume triangles first, check, else walk.
            fields = []
            for p in props:
                if p[0] == "list":
                    fields += [("n", "<" + PLY_TYPES[p[1]]), ("i", "<" + PLY_TYPES[p[2]], (3,))]
                else:
                    fields.append((p[-1], "<" + PLY_TYPES[p[0]]))
            dt = np.dtype(fields)
            arr = np.frombuffer(body, dtype=dt, count=el["count"], offset=at)
            if not np.all(arr["n"] == 3):
                sys.exit(f"{path}: only triangle lists are read in binary PLY")
            at += dt.itemsize * el["count"]
            if el["name"] == "face":
                faces = arr["i"].astype(np.uint32)
    else:
        sys.exit(f"{path}: unsupported PLY format {fmt}")
    return verts, np.asarray(faces, dtype=np.uint32).reshape(-1, 3)


def parse_obj(path):
    """The `v`, `vt` and `mtllib` lines of a Wavefront OBJ file and its
    triangles' corners as (position, texture) index pairs: corners `i`,
    `i/t`, `i//n` or `i/t/n`, negative indices counted from the end, -1
    where a corner has no texture index; polygons fanned into triangles;
    everything else is skipped."""
    verts, uvs, corners, libs = [], [], [], []
    with open(path, "r", encoding="utf-8", errors="replace") as f:
        for line in f:
            words = line.split()
            if not words:
                continue
            if words[0] == "v":
                verts.append([float(x) for x in words[1:4]])
            elif words[0] == "vt":
                uvs.append([float(x) for x in words[1:3]])
            elif words[0] == "mtllib":
                libs.append(" ".join(words[1:]))
            elif words[0] == "f":
                idx = []
                for corner in words[1:]:
                    parts = corner.split("/")
                    k = int(parts[0])
                    t = int(parts[1]) if len(parts) > 1 and parts[1] else None
                    uv = -1 if t is None else (t - 1 if t > 0 else len(uvs) + t)
                    idx.append((k - 1 if k > 0 else len(verts) + k, uv))
                for i in range(1, len(idx) - 1):
                    corners.extend([idx[0], idx[i], idx[i + 1]])
    return verts, uvs, corners, libs


def read_obj(path):
    """Vertices (n, 3) float32 and triangles (m, 3) uint32 of a Wavefront
    OBJ file (see `parse_obj`)."""
    verts, _, corners, _ = parse_obj(path)
    faces = [k for k, _ in corners]
    return np.asarray(verts, dtype=np.float32), np.asarray(faces, dtype=np.uint32).reshape(-1, 3)


def guess_texture(path):
    """For an OBJ without materials: the one image beside it named like the
    OBJ or `*_texture`, as `spatch convert` guesses it; else None."""
    folder = os.path.dirname(path) or "."
    stem = os.path.splitext(os.path.basename(path))[0].lower()
    found = [
        os.path.join(folder, name)
        for name in os.listdir(folder)
        if os.path.splitext(name)[1].lower() in (".png", ".jpg", ".jpeg", ".tif", ".tiff")
        and (os.path.splitext(name)[0].lower() == stem
             or os.path.splitext(name)[0].lower().endswith("_texture"))
    ]
    return found[0] if len(found) == 1 else None


class TexturedMesh(NamedTuple):
    """A mesh drawn corner by corner with a texture image."""

    pos: np.ndarray
    uv: np.ndarray
    nrm: np.ndarray
    image: str


def read_textured_obj(path, image=None):
    """The `TexturedMesh` of a Wavefront OBJ: per-corner positions (3m, 3),
    texture coordinates (3m, 2; (0, 0) where a corner has none) and smooth
    normals (3m, 3) of its triangles, and `image` or else the first `map_Kd`
    image of its material libraries (without any, the converter's guess)."""
    verts, uvs, corners, libs = parse_obj(path)
    if not uvs:
        sys.exit(f"{path}: no texture coordinates (vt) for --textured")
    for lib in libs:
        lib_path = os.path.join(os.path.dirname(path), lib)
        with open(lib_path, "r", encoding="utf-8", errors="replace") as f:
            for line in f:
                words = line.split()
                if words and words[0] == "map_Kd" and image is None:
                    image = os.path.join(os.path.dirname(lib_path), words[-1])
    if image is None and not libs:
        image = guess_texture(path)
    if image is None:
        sys.exit(f"{path}: no map_Kd image in its materials; name one with --texture")
    v = np.asarray(verts, dtype=np.float32)
    c = np.asarray(corners, dtype=np.int64)
    f = c[:, 0].reshape(-1, 3).astype(np.uint32)
    n = vertex_normals(v, f)
    uv = np.vstack([np.asarray(uvs, dtype=np.float32), np.zeros((1, 2), np.float32)])[c[:, 1]]
    return TexturedMesh(v[c[:, 0]], uv, n[c[:, 0]], image)


def read_mesh(path):
    """The mesh of a PLY or OBJ file, by its extension."""
    if path.lower().endswith(".obj"):
        return read_obj(path)
    return read_ply(path)


def vertex_normals(v, f):
    """Area-weighted smooth vertex normals."""
    n = np.zeros_like(v)
    fn = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    for k in range(3):
        np.add.at(n, f[:, k], fn)
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return (n / np.maximum(length, 1e-30)).astype(np.float32)


def box_centre_radius(v):
    """The centre and half diagonal of the bounding box of the points `v`."""
    lo, hi = v.min(axis=0).astype(np.float64), v.max(axis=0).astype(np.float64)
    return (lo + hi) / 2, np.linalg.norm(hi - lo) / 2


def measures_camera(v):
    """The camera of MEASURES.md: eye, target, and near/far around the box."""
    c, r = box_centre_radius(v)
    d = np.array([1.0, 0.7, 1.3])
    d /= np.linalg.norm(d)
    eye = c + d * r / math.sin(math.radians(20)) * 1.05
    dist = np.linalg.norm(eye - c)
    return eye, c, max(dist - r, dist / 1000), dist + r


def look_at(eye, target, up):
    f = target - eye
    f /= np.linalg.norm(f)
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    m = np.identity(4)
    m[0, :3], m[1, :3], m[2, :3] = s, u, -f
    m[:3, 3] = -m[:3, :3] @ eye
    return m


def perspective(fov_deg, aspect, near, far):
    t = 1 / math.tan(math.radians(fov_deg) / 2)
    m = np.zeros((4, 4))
    m[0, 0], m[1, 1] = t / aspect, t
    m[2, 2], m[2, 3] = (far + near) / (near - far), 2 * far * near / (near - far)
    m[3, 2] = -1
    return m


VERTEX = """
#version 330
uniform mat4 mvp;
uniform mat4 view;
in vec3 pos;
in vec3 nrm;
out vec3 n_eye;
#ifdef TEXTURED
in vec2 uv;
out vec2 uv_out;
#endif
void main() {
    n_eye = mat3(view) * nrm;
#ifdef TEXTURED
    uv_out = uv;
#endif
    gl_Position = mvp * vec4(pos, 1.0);
}
"""

FRAGMENT = """
#version 330
in vec3 n_eye;
out vec4 colour;
uniform vec3 light;
#ifdef TEXTURED
in vec2 uv_out;
uniform sampler2D albedo_map;
#endif
void main() {
    vec3 n = normalize(n_eye);
    if (!gl_FrontFacing) n = -n;
    vec3 h = normalize(light + vec3(0.0, 0.0, 1.0));
    float diff = max(dot(n, light), 0.0);
    float spec = pow(max(dot(n, h), 0.0), 32.0);
#ifdef TEXTURED
    vec3 albedo = texture(albedo_map, uv_out).rgb;
#else
    vec3 albedo = vec3(220.0 / 255.0);
#endif
    colour = vec4(albedo * (0.2 + 0.8 * diff) + 0.25 * spec, 1.0);
}
"""


class Peer:
    """llvmpipe drawing the mesh into an offscreen framebuffer."""

    def __init__(self, mesh, size, camera, fov):
        """`mesh`: `(v, f)` drawn in grey, or a `TexturedMesh`."""
        import moderngl

        self.ctx = moderngl.create_context(standalone=True, backend="egl")
        renderer = self.ctx.info.get("GL_RENDERER", "?")
        if "llvmpipe" not in renderer:
            sys.exit(f"the GL context is {renderer!r}, not llvmpipe")
        self.renderer = renderer
        eye, target, near, far = camera
        view = look_at(eye, target, np.array([0.0, 1.0, 0.0]))
        mvp = perspective(fov, 1.0, near, far) @ view
        textured = isinstance(mesh, TexturedMesh)
        define = "#version 330\n#define TEXTURED\n" if textured else "#version 330\n"
        prog = self.ctx.program(
            vertex_shader=VERTEX.replace("#version 330\n", define),
            fragment_shader=FRAGMENT.replace("#version 330\n", define),
        )
        prog["mvp"].write(mvp.T.astype("f4").tobytes())
        prog["view"].write(view.T.astype("f4").tobytes())
        light = np.array([-0.4, 0.5, 0.75])
        prog["light"].value = tuple(light / np.linalg.norm(light))
        if textured:
            self.vao = self.textured_vao(prog, mesh)
        else:
            v, f = mesh
            n = vertex_normals(v, f)
            vbo = self.ctx.buffer(np.hstack([v, n]).astype("f4").tobytes())
            ibo = self.ctx.buffer(f.astype("u4").tobytes())
            self.vao = self.ctx.vertex_array(prog, [(vbo, "3f 3f", "pos", "nrm")], ibo)
        self.fbo = self.ctx.simple_framebuffer((size, size), components=4)
        self.fbo.use()
        self.ctx.enable(moderngl.DEPTH_TEST)
        self.ctx.disable(moderngl.CULL_FACE)

    def textured_vao(self, prog, mesh):
        """The corners of a textured mesh and its image as a mipmapped texture."""
        import moderngl
        from PIL import Image

        pos, uv, nrm, image = mesh
        img = Image.open(image).convert("RGB").transpose(Image.Transpose.FLIP_TOP_BOTTOM)
        tex = self.ctx.texture(img.size, 3, img.tobytes())
        tex.build_mipmaps()
        tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
        tex.repeat_x = tex.repeat_y = True
        tex.use(location=0)
        prog["albedo_map"].value = 0
        vbo = self.ctx.buffer(np.hstack([pos, nrm, uv]).astype("f4").tobytes())
        return self.ctx.vertex_array(prog, [(vbo, "3f 3f 2f", "pos", "nrm", "uv")])

    def frame_ms(self):
        start = time.perf_counter()
        self.fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        self.vao.render()
        self.ctx.finish()
        return (time.perf_counter() - start) * 1e3

    def median_ms(self, frames):
        self.frame_ms()  # warm-up
        return statistics.median(self.frame_ms() for _ in range(frames))


def spatch_median_ms(args, camera, extra):
    eye, target, _, _ = camera
    vec = lambda p: ",".join(f"{x:.9g}" for x in p)
    cmd = [
        args.spatch, "render", args.scene, "--bench", str(args.frames), "--threads", "2",
        "--json", "--width", str(args.size), "--height", str(args.size),
        f"--eye={vec(eye)}", f"--target={vec(target)}", "--fov", str(args.fov),
    ] + extra
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out)["details"]["bench"]["ms"]["frame"]["median_ms"]


def split_spatch_flags(argv):
    """The script's own arguments and the spatch flags after `--`."""
    if "--" not in argv:
        return argv, []
    k = argv.index("--")
    return argv[:k], argv[k + 1:]


def comparison_parser(doc):
    """An argument parser described by `doc`'s first line, with the arguments every
    comparison with llvmpipe takes: the spatch binary, the source mesh and the scene."""
    p = argparse.ArgumentParser(description=doc.split("\n")[0])
    p.add_argument("--spatch", required=True)
    p.add_argument("--mesh", required=True)
    p.add_argument("--scene", required=True)
    return p


def main():
    argv, extra = split_spatch_flags(sys.argv[1:])
    p = comparison_parser(__doc__)
    p.add_argument("--size", type=int, default=500)
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--frames", type=int, default=20)
    p.add_argument("--fov", type=float, default=40.0)
    p.add_argument("--textured", action="store_true",
                   help="llvmpipe samples the OBJ's map_Kd texture (see the module doc)")
    p.add_argument("--texture", help="with --textured: the image, for an OBJ without materials")
    args = p.parse_args(argv)
    if os.environ.get("LP_NUM_THREADS") != "2":
        print("note: LP_NUM_THREADS is not 2", file=sys.stderr)
    v, f = read_mesh(args.mesh)
    camera = measures_camera(v)
    mesh = read_textured_obj(args.mesh, args.texture) if args.textured else (v, f)
    peer = Peer(mesh, args.size, camera, args.fov)
    ratios = []
    for r in range(args.rounds):
        gl = peer.median_ms(args.frames)
        sp = spatch_median_ms(args, camera, extra)
        ratios.append(gl / sp)
        print(f"round {r + 1}: llvmpipe {gl:.2f} ms, spatch {sp:.2f} ms, ratio {gl / sp:.2f}")
    print(
        f"{os.path.basename(args.mesh)} {args.size}²: {len(f)} triangles"
        f"{' textured' if args.textured else ''} on {peer.renderer}; "
        f"median ratio llvmpipe / spatch {statistics.median(ratios):.2f} over {args.rounds} rounds"
    )


if __name__ == "__main__":
    main()
