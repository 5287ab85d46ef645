#!/usr/bin/env python3
"""Measures delivered layouts, whatever tool wrote them, with geometry written here.

Usage: measure_layouts.py FILE [FILE ...] [--tsv OUT] [--disk-texcoords]

FILE is a PLY that ricci-flow wrote, or an OBJ with a texture coordinate per face corner
(f v/vt), as Boundary First Flattening and CEPS write them. Per file:

* faces, and faces turned over in the layout (orientation as drawn: straight sides);
* the quasi-conformal ratio of each face's affine map from 3D to its layout (singular values'
  ratio): median, p95, max;
* PLY only: the angle sum at every interior vertex of the delivered mesh, its corner angles
  measured in the layout's model (Euclidean angles in the plane, hyperbolic angles between the
  geodesic sides in the Poincare disk, spherical ones on the unit sphere), against 2 pi - Kbar
  (Kbar: ricci_target; 0 at the vertices of a subdivision); the largest error, over all interior
  vertices and over those the layout cuts open (corners at more than one position).

The layout of a ricci-flow PLY: layout_corners per face corner where the file has them (the
model's coordinates, in each face's chart), else layout_x/y/z per vertex; the model per face from
ricci_layout (1 plane, 2 Poincare disk, 3 sphere).
"""
import argparse
import math
import os
import struct
import sys

import numpy as np

TYPES = {"char": "b", "uchar": "B", "int8": "b", "uint8": "B", "short": "h", "ushort": "H",
         "int16": "h", "uint16": "H", "int": "i", "uint": "I", "int32": "i", "uint32": "I",
         "float": "f", "float32": "f", "double": "d", "float64": "d"}
PLANE, DISK, SPHERE = 1, 2, 3
DISK_TEXCOORDS = False  # --disk-texcoords


def read_ply(path):
    """(vertex properties, face properties): dicts of name -> array (lists: list of lists)."""
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    fmt, elements = "ascii", []
    for line in data[:end].decode().split("\n"):
        w = line.split()
        if not w:
            continue
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "element":
            elements.append((w[1], int(w[2]), []))
        elif w[0] == "property":
            elements[-1][2].append(tuple(w[1:]))
    body, pos = data[end:], 0
    tokens = body.split() if fmt == "ascii" else None
    order = ">" if fmt == "binary_big_endian" else "<"

    def take(t):
        nonlocal pos
        if tokens is not None:
            pos += 1
            return float(tokens[pos - 1])
        v = struct.unpack_from(order + TYPES[t], body, pos)[0]
        pos += struct.calcsize(TYPES[t])
        return v

    out = {}
    for name, count, props in elements:
        values = {p[-1]: [] for p in props}
        for _ in range(count):
            for p in props:
                if p[0] == "list":
                    n = int(take(p[1]))
                    values[p[3]].append([take(p[2]) for _ in range(n)])
                else:
                    values[p[1]].append(take(p[0]))
        out[name] = {k: (np.array(v, dtype=float) if v and not isinstance(v[0], list) else v)
                     for k, v in values.items()}
    return out.get("vertex", {}), out.get("face", {})


def read_obj(path):
    """Positions (n, 3), faces (m, 3) and per-corner texture coordinates (m, 3, 2)."""
    v, vt, faces, uv = [], [], [], []
    for line in open(path, errors="replace"):
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            v.append([float(x) for x in w[1:4]])
        elif w[0] == "vt":
            vt.append([float(x) for x in w[1:3]])
        elif w[0] == "f":
            corners = [c.split("/") for c in w[1:]]
            idx = [int(c[0]) - 1 if int(c[0]) > 0 else len(v) + int(c[0]) for c in corners]
            tex = [int(c[1]) - 1 if int(c[1]) > 0 else len(vt) + int(c[1]) for c in corners]
            for i in range(1, len(idx) - 1):  # fans
                faces.append([idx[0], idx[i], idx[i + 1]])
                uv.append([vt[tex[0]], vt[tex[i]], vt[tex[i + 1]]])
    return np.array(v), np.array(faces, dtype=int), np.array(uv)


def frames(t):
    """Per triangle of R^3 (m, 3, 3): its edge vectors in an orthonormal frame of its plane, as
    2 x 2 matrices (columns: corner 1 - corner 0, corner 2 - corner 0)."""
    e1, e2 = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    x = e1 / np.linalg.norm(e1, axis=1)[:, None]
    y = np.cross(np.cross(e1, e2), x)
    y /= np.linalg.norm(y, axis=1)[:, None]
    m = np.empty((len(t), 2, 2))
    m[:, 0, 0], m[:, 0, 1] = np.einsum("ij,ij->i", e1, x), np.einsum("ij,ij->i", e2, x)
    m[:, 1, 0], m[:, 1, 1] = np.einsum("ij,ij->i", e1, y), np.einsum("ij,ij->i", e2, y)
    return m


def quasi_conformal(surface, layout):
    """Per face: the singular values' ratio of the affine map between two triangles of R^3."""
    with np.errstate(all="ignore"):
        m = frames(surface)  # its inverse by the adjugate: degenerate faces give inf, not errors
        det = m[:, 0, 0] * m[:, 1, 1] - m[:, 0, 1] * m[:, 1, 0]
        inverse = np.stack([np.stack([m[:, 1, 1], -m[:, 0, 1]], axis=1),
                            np.stack([-m[:, 1, 0], m[:, 0, 0]], axis=1)], axis=1) / det[:, None, None]
        j = frames(layout) @ inverse
        # The singular values of a 2 x 2 matrix in closed form: |conformal part| +- |anti-part|.
        conformal = np.hypot(j[:, 0, 0] + j[:, 1, 1], j[:, 1, 0] - j[:, 0, 1]) / 2
        anti = np.hypot(j[:, 0, 0] - j[:, 1, 1], j[:, 1, 0] + j[:, 0, 1]) / 2
        return (conformal + anti) / np.abs(conformal - anti)


def orientation(model, t):
    """Per face: > 0 when counter-clockwise as drawn (plane and disk: straight; sphere: seen from
    outside)."""
    if model == SPHERE:
        return np.einsum("ij,ij->i", np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]),
                         t[:, 0] + t[:, 1] + t[:, 2])
    a, b = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]


def corner_angle(model, p, q, r):
    """The angle at corner p of the triangle p, q, r (arrays (m, 3)), in the model's geometry."""
    if model == PLANE:
        a, b = q - p, r - p
        return np.abs(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0],
                                 a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1]))
    if model == SPHERE:
        # In extended precision too: q - (p . q) p cancels for small triangles.
        p, q, r = (x.astype(np.longdouble) for x in (p, q, r))
        tq = q - np.einsum("ij,ij->i", p, q)[:, None] * p
        tr = r - np.einsum("ij,ij->i", p, r)[:, None] * p
        return np.abs(np.arctan2(np.einsum("ij,ij->i", np.cross(tq, tr), p),
                                 np.einsum("ij,ij->i", tq, tr)))
    # The Poincare disk: the Moebius map taking p to 0 makes the geodesics from p straight rays.
    # In extended precision: 1 - conj(p) q cancels near the rim, and the measure should not add
    # rounding of its own to the layout's.
    zp, zq, zr = (x[:, 0].astype(np.longdouble) + 1j * x[:, 1].astype(np.longdouble)
                  for x in (p, q, r))
    wq = (zq - zp) / (1 - np.conj(zp) * zq)
    wr = (zr - zp) / (1 - np.conj(zp) * zr)
    c = wr * np.conj(wq)
    return np.abs(np.arctan2(c.imag, c.real))


def angle_sums(faces, corners, model, kbar, num_vertices):
    """(largest error, interior vertices checked, largest error at cut vertices, cut vertices)."""
    total = np.zeros(num_vertices, dtype=np.longdouble)
    for c in range(3):
        p, q, r = corners[:, c], corners[:, (c + 1) % 3], corners[:, (c + 2) % 3]
        np.add.at(total, faces[:, c], corner_angle(model, p, q, r))
    # Interior: every edge at the vertex has two faces.
    edges = {}
    for t in faces:
        for c in range(3):
            key = (min(t[c], t[(c + 1) % 3]), max(t[c], t[(c + 1) % 3]))
            edges[key] = edges.get(key, 0) + 1
    boundary = np.zeros(num_vertices, dtype=bool)
    for (a, b), n in edges.items():
        if n != 2:
            boundary[a] = boundary[b] = True
    used = np.zeros(num_vertices, dtype=bool)
    used[faces.ravel()] = True
    # Cut open: a vertex whose corners sit at more than one position.
    first = np.full((num_vertices, corners.shape[2]), np.nan)
    cut = np.zeros(num_vertices, dtype=bool)
    for c in range(3):
        v = faces[:, c]
        unset = np.isnan(first[v, 0])
        first[v[unset]] = corners[unset, c]
        cut[v] |= np.linalg.norm(corners[:, c] - first[v], axis=1) > 1e-9
    check = used & ~boundary & np.isfinite(kbar)
    error = np.abs(total - (2 * np.longdouble(math.pi) - kbar)).astype(float)
    worst = float(error[check].max()) if check.any() else float("nan")
    on_cut = check & cut
    worst_cut = float(error[on_cut].max()) if on_cut.any() else float("nan")
    return worst, int(check.sum()), worst_cut, int(on_cut.sum())


def measure_ply(path):
    v, f = read_ply(path)
    faces = np.array(f["vertex_indices"], dtype=int)
    surface = np.stack([v["x"], v["y"], v["z"]], axis=1)
    n = len(surface)
    model = np.asarray(f["ricci_layout"], dtype=int) if "ricci_layout" in f else None
    if "layout_corners" in f:
        c = np.array(f["layout_corners"]).reshape(-1, 3, 2)
        corners = np.concatenate([c, np.zeros(c.shape[:2] + (1,))], axis=2)
        if "layout_x" in v:  # sphere components of a mixed file: their vertices' positions
            p = np.stack([v["layout_x"], v["layout_y"], v["layout_z"]], axis=1)
            own = ~np.isfinite(corners).all(axis=(1, 2))
            corners[own] = p[faces[own]]
    elif "layout_x" in v:
        p = np.stack([v["layout_x"], v["layout_y"], v["layout_z"]], axis=1)
        corners = p[faces]
    elif DISK_TEXCOORDS and "texcoord_double" in f:  # older files: one Poincare disk chart
        c = 2 * np.array(f["texcoord_double"]).reshape(-1, 3, 2) - 1
        corners = np.concatenate([c, np.zeros(c.shape[:2] + (1,))], axis=2)
        model = np.full(len(faces), DISK)
    else:
        return {"file": path, "faces": len(faces), "models": "none"}
    if model is None:  # files without ricci_layout: the plane where z = 0, else the sphere
        model = np.where(np.all(corners[:, :, 2] == 0, axis=1), PLANE, SPHERE)
    kbar = np.array(v["ricci_target"], dtype=float)
    if "ricci_input_face" in v:  # a subdivision's new vertices are flat
        kbar[np.asarray(v["ricci_input_face"]) >= 0] = 0
    row = {"file": path, "faces": len(faces)}
    names = {PLANE: "plane", DISK: "poincare-disk", SPHERE: "sphere"}
    row["models"] = ",".join(names[m] for m in sorted(set(model.tolist())) if m in names)
    qc, flipped = [], 0
    worst = worst_cut = float("nan")
    checked = checked_cut = 0
    for m in (PLANE, DISK, SPHERE):
        sel = model == m
        if not sel.any():
            continue
        t = corners[sel]
        flipped += int(np.sum(~(orientation(m, t) > 0)))
        qc.append(quasi_conformal(surface[faces[sel]], t))
        # Angle sums per model; a vertex's faces all lie in one component, so in one model.
        kb = kbar.copy()
        kb[np.setdiff1d(np.arange(n), faces[sel].ravel())] = np.nan
        w, k, wc, kc = angle_sums(faces[sel], t, m, kb, n)
        worst = np.nanmax([worst, w]) if k else worst
        worst_cut = np.nanmax([worst_cut, wc]) if kc else worst_cut
        checked, checked_cut = checked + k, checked_cut + kc
    row.update(summary(np.concatenate(qc), flipped))
    row.update({"angle_error": worst, "interior_vertices": checked, "cut_angle_error": worst_cut,
                "cut_vertices": checked_cut})
    return row


def summary(qc, flipped):
    finite = qc[np.isfinite(qc)]
    return {"flipped": flipped, "degenerate": int(len(qc) - len(finite)),
            "qc_median": float(np.median(finite)) if len(finite) else float("nan"),
            "qc_p95": float(np.percentile(finite, 95)) if len(finite) else float("nan"),
            "qc_max": float(finite.max()) if len(finite) else float("nan")}


def measure_obj(path):
    v, faces, uv = read_obj(path)
    corners = np.concatenate([uv, np.zeros(uv.shape[:2] + (1,))], axis=2)
    row = {"file": path, "faces": len(faces), "models": "plane"}
    row.update(summary(quasi_conformal(v[faces], corners), int(np.sum(~(orientation(
        PLANE, corners) > 0)))))
    return row


COLUMNS = ("file", "faces", "models", "flipped", "degenerate", "qc_median", "qc_p95", "qc_max",
           "angle_error", "interior_vertices", "cut_angle_error", "cut_vertices")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("files", nargs="+")
    parser.add_argument("--tsv")
    parser.add_argument("--disk-texcoords", action="store_true",
                        help="PLYs without layout_corners (written before them): texcoord_double "
                        "as (z + 1) / 2 of one Poincare disk")
    args = parser.parse_args()
    global DISK_TEXCOORDS
    DISK_TEXCOORDS = args.disk_texcoords
    rows = []
    for path in args.files:
        row = measure_obj(path) if path.lower().endswith(".obj") else measure_ply(path)
        rows.append(row)
        print("\t".join(("%.4g" % row[k]) if isinstance(row.get(k), float) else str(row.get(k, ""))
                        for k in COLUMNS))
        sys.stdout.flush()
    if args.tsv:
        with open(args.tsv, "w") as out:
            out.write("\t".join(COLUMNS) + "\n")
            for row in rows:
                out.write("\t".join(repr(float(row[k])) if isinstance(row.get(k), float)
                                    else str(row.get(k, "")) for k in COLUMNS) + "\n")


if __name__ == "__main__":
    sys.exit(main())
