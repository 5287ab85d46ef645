#!/usr/bin/env python3
"""Renders a ricci-flow result (ASCII PLY) as two pictures: the mesh with a checkerboard texture
taken from its layout, and the layout itself.

A result PLY (ASCII or binary), read by measure_layouts.read_ply. A small z-buffer rasterizer in numpy (no graphics stack needed). The checkerboard comes from the
texture coordinates (per vertex or per face corner) or, for layouts on the unit sphere, from the
longitude and latitude of the sphere point, interpolated per pixel.

usage: render_pictures.py RESULT.ply MESH.png LAYOUT.png [--view AZIMUTH ELEVATION] [--checks N]
                          [--seams]
"""
import argparse
import math
import os
import struct
import sys
import zlib

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import measure_layouts  # noqa: E402  (the one PLY reader of the scripts)

LIGHT = np.array([0.3, 0.4, 1.0]) / np.linalg.norm([0.3, 0.4, 1.0])
CHECK_A = np.array([232.0, 126.0, 52.0])
CHECK_B = np.array([248.0, 244.0, 232.0])
BACKGROUND = np.array([255, 255, 255], dtype=np.uint8)


def read_result(path):
    """Vertex properties, triangles and per-corner texture coordinates (or None) of a result PLY,
    by the scripts' one PLY reader (measure_layouts.read_ply; ASCII or binary)."""
    vertex, face = measure_layouts.read_ply(path)
    texcoord = face.get("texcoord_double") or face.get("texcoord")
    return {"vertex": {k: np.asarray(x, dtype=float) for k, x in vertex.items()},
            "faces": np.array([[int(i) for i in t] for t in face["vertex_indices"]], dtype=int),
            "texcoord": None if texcoord is None else np.array(texcoord).reshape(-1, 3, 2)}


def write_png(path, image):
    height, width, _ = image.shape
    raw = b"".join(b"\x00" + image[y].tobytes() for y in range(height))

    def chunk(kind, payload):
        return (struct.pack(">I", len(payload)) + kind + payload
                + struct.pack(">I", zlib.crc32(kind + payload) & 0xFFFFFFFF))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


def checker(u, v, checks):
    parity = (np.floor(u * checks) + np.floor(v * checks)).astype(int) % 2
    return np.where(parity[..., None] == 1, CHECK_A, CHECK_B)


def sphere_checker(p, checks):
    p = p / np.linalg.norm(p, axis=-1, keepdims=True)
    lon = (np.arctan2(p[..., 1], p[..., 0]) + math.pi) / (2 * math.pi)
    lat = (np.arcsin(np.clip(p[..., 2], -1, 1)) + math.pi / 2) / math.pi
    return checker(lon, lat * 0.5, checks)


SEAM = np.array([30.0, 50.0, 140.0])
CONE = np.array([200.0, 20.0, 30.0])


def seams_and_cones(faces, uv, curvature):
    """Per face corner: whether the side opposite it is a seam (a side of the mesh's boundary, or
    one whose two faces give its ends other texture coordinates), and whether the corner is a
    cone (an interior vertex whose curvature, ricci_curvature, is beyond 1e-6)."""
    side_uv = {}
    for f, t in enumerate(faces):
        for k in range(3):
            a, b = t[(k + 1) % 3], t[(k + 2) % 3]
            side_uv[(a, b)] = (uv[f, (k + 1) % 3], uv[f, (k + 2) % 3])
    seam = np.zeros(faces.shape, dtype=bool)
    for f, t in enumerate(faces):
        for k in range(3):
            a, b = t[(k + 1) % 3], t[(k + 2) % 3]
            twin = side_uv.get((b, a))
            seam[f, k] = twin is None or not (np.allclose(twin[1], uv[f, (k + 1) % 3], atol=1e-9)
                                              and np.allclose(twin[0], uv[f, (k + 2) % 3],
                                                              atol=1e-9))
    curved = np.abs(np.nan_to_num(curvature, nan=0.0)) > 1e-6
    boundary = set()
    for (a, b) in side_uv:
        if (b, a) not in side_uv:
            boundary.update((a, b))
    cone = curved[faces] & ~np.isin(faces, list(boundary))
    return seam, cone


def rasterize(points, depth, attributes, shade, size, color_of, edges=False, marks=None):
    """points: per face corner pixel positions (F, 3, 2); depth (F, 3), smaller in front;
    attributes (F, 3, k) interpolated per pixel; shade (F,) brightness; color_of maps interpolated
    attributes (n, k) to colors (n, 3); edges darkens pixels within half a pixel of a side; marks,
    (seam, cone) of seams_and_cones, draws the seams as lines and the cones as dots."""
    image = np.tile(BACKGROUND, (size, size, 1)).astype(float)
    zbuffer = np.full((size, size), np.inf)
    for f in range(len(points)):
        p = points[f]
        lo = np.maximum(np.floor(p.min(axis=0)).astype(int), 0)
        hi = np.minimum(np.ceil(p.max(axis=0)).astype(int), size - 1)
        if np.any(hi < lo):
            continue
        xs, ys = np.meshgrid(np.arange(lo[0], hi[0] + 1) + 0.5, np.arange(lo[1], hi[1] + 1) + 0.5)
        d = (p[1, 0] - p[0, 0]) * (p[2, 1] - p[0, 1]) - (p[2, 0] - p[0, 0]) * (p[1, 1] - p[0, 1])
        if abs(d) < 1e-12:
            continue
        b1 = ((xs - p[0, 0]) * (p[2, 1] - p[0, 1]) - (p[2, 0] - p[0, 0]) * (ys - p[0, 1])) / d
        b2 = ((p[1, 0] - p[0, 0]) * (ys - p[0, 1]) - (xs - p[0, 0]) * (p[1, 1] - p[0, 1])) / d
        b0 = 1 - b1 - b2
        inside = (b0 >= -1e-9) & (b1 >= -1e-9) & (b2 >= -1e-9)
        if not inside.any():
            continue
        z = b0 * depth[f, 0] + b1 * depth[f, 1] + b2 * depth[f, 2]
        iy, ix = np.nonzero(inside)
        gx, gy = ix + lo[0], iy + lo[1]
        closer = z[iy, ix] < zbuffer[gy, gx]
        if not closer.any():
            continue
        iy, ix, gx, gy = iy[closer], ix[closer], gx[closer], gy[closer]
        bary = np.stack([b0[iy, ix], b1[iy, ix], b2[iy, ix]], axis=1)
        color = color_of(bary @ attributes[f]) * shade[f]
        if edges:
            # distance to each side in pixels: barycentric coordinate times the altitude
            sides = [np.linalg.norm(p[(k + 2) % 3] - p[(k + 1) % 3]) for k in range(3)]
            altitude = np.array([abs(d) / max(s, 1e-12) for s in sides])
            near = (bary * altitude).min(axis=1) < 0.5
            color[near] *= 0.55
        if marks is not None:
            seam, cone = marks[0][f], marks[1][f]
            if seam.any() or cone.any():
                sides = [np.linalg.norm(p[(k + 2) % 3] - p[(k + 1) % 3]) for k in range(3)]
                altitude = np.array([abs(d) / max(s, 1e-12) for s in sides])
                to_side = np.where(seam, bary * altitude, np.inf).min(axis=1)
                color[to_side < 1.0] = SEAM
                pixel = np.stack([gx + 0.5, gy + 0.5], axis=1)
                for k in np.nonzero(cone)[0]:
                    color[np.linalg.norm(pixel - p[k], axis=1) < 4.5] = CONE
        zbuffer[gy, gx] = z[iy, ix]
        image[gy, gx] = color
    return np.clip(image, 0, 255).astype(np.uint8)


def view_rotation(azimuth, elevation):
    a, e = math.radians(azimuth), math.radians(elevation)
    rz = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
    rx = np.array([[1, 0, 0], [0, math.cos(e), -math.sin(e)], [0, math.sin(e), math.cos(e)]])
    return rx @ rz


def principal_frame(x):
    centred = x - x.mean(axis=0)
    _, _, vt = np.linalg.svd(centred, full_matrices=False)
    frame = vt.copy()
    if np.linalg.det(frame) < 0:
        frame[2] *= -1
    return frame  # rows: largest extent -> x, then y, view along the smallest


def to_pixels(xy, size, margin=0.06, unit_square=False):
    lo, hi = xy.min(axis=(0, 1)), xy.max(axis=(0, 1))
    if unit_square:
        lo, hi = np.zeros(2), np.ones(2)
    scale = (1 - 2 * margin) * size / max(hi[0] - lo[0], hi[1] - lo[1])
    centre = (lo + hi) / 2
    out = (xy - centre) * scale + size / 2
    out[..., 1] = size - out[..., 1]  # image rows grow downwards
    return out


def render_surface(corners_3d, attributes, color_of, size, edges=False, marks=None):
    p0, p1, p2 = corners_3d[:, 0], corners_3d[:, 1], corners_3d[:, 2]
    normal = np.cross(p1 - p0, p2 - p0)
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    shade = 0.35 + 0.65 * np.abs(normal @ LIGHT)
    pixels = to_pixels(corners_3d[..., :2], size)
    return rasterize(pixels, -corners_3d[..., 2], attributes, shade, size, color_of, edges, marks)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("result")
    parser.add_argument("mesh_png")
    parser.add_argument("layout_png")
    parser.add_argument("--view", nargs=2, type=float, metavar=("AZIMUTH", "ELEVATION"),
                        help="rotation of the principal frame, degrees")
    parser.add_argument("--checks", type=float, default=16, help="checks across the texture")
    parser.add_argument("--size", type=int, default=520)
    parser.add_argument("--poincare", action="store_true",
                        help="the texture is the Poincare disk: frame it and draw its circle")
    parser.add_argument("--seams", action="store_true",
                        help="draw the seams (blue) and the cones (red) on both pictures")
    args = parser.parse_args()

    ply = read_result(args.result)
    v, faces = ply["vertex"], ply["faces"]
    x = np.stack([v["x"], v["y"], v["z"]], axis=1)
    sphere = "layout_z" in v and "texture_u" not in v
    if ply["texcoord"] is not None:
        uv = ply["texcoord"]
    elif "texture_u" in v:
        t = np.stack([v["texture_u"], v["texture_v"]], axis=1)
        uv = t[faces]
    elif sphere:
        uv = None
    else:
        sys.exit(f"{args.result}: no layout in this result")

    frame = principal_frame(x)
    if args.view:
        frame = view_rotation(*args.view) @ frame
    corners = (x - x.mean(axis=0)) @ frame.T
    corners = corners[faces]

    if sphere:
        s = np.stack([v["layout_x"], v["layout_y"], v["layout_z"]], axis=1)
        attributes = s[faces]
        color_of = lambda a: sphere_checker(a, args.checks)  # noqa: E731
    else:
        attributes = uv
        color_of = lambda a: checker(a[:, 0], a[:, 1], args.checks)  # noqa: E731
    marks = seams_and_cones(faces, uv, v["ricci_curvature"]) if args.seams and uv is not None else None
    write_png(args.mesh_png, render_surface(corners, attributes, color_of, args.size, marks=marks))

    if sphere:
        tilt = view_rotation(20, -60)
        layout = (s @ tilt.T)[faces]
        image = render_surface(layout, attributes, color_of, args.size, edges=len(faces) < 5000)
    else:
        pixels = to_pixels(uv, args.size, unit_square=args.poincare)
        image = rasterize(pixels, np.zeros(uv.shape[:2]), uv, np.ones(len(faces)), args.size,
                          color_of, edges=len(faces) < 5000 and marks is None, marks=marks)
        if args.poincare:  # the disk's boundary circle
            angle = np.linspace(0, 2 * math.pi, 4 * args.size)
            circle = to_pixels(np.stack([(1 + np.cos(angle)) / 2, (1 + np.sin(angle)) / 2],
                                        axis=1)[None], args.size, unit_square=True)[0]
            ix = np.clip(circle[:, 0].astype(int), 0, args.size - 1)
            iy = np.clip(circle[:, 1].astype(int), 0, args.size - 1)
            image[iy, ix] = (60, 60, 60)
    write_png(args.layout_png, image)


if __name__ == "__main__":
    main()
