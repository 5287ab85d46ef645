#!/usr/bin/env python3
"""Measures delivered layouts, whatever tool wrote them, with geometry written here.

Usage: measure_layouts.py FILE [FILE ...] [--tsv OUT] [--disk-texcoords]
                          [--atlas [--atlas-fit] [--atlas-res N]]

FILE is a PLY that ricci-flow wrote, or an OBJ with a texture coordinate per face corner
(f v/vt), as Boundary First Flattening and CEPS write them. Per file:

* faces, and faces not counter-clockwise (turned over, or of zero area) in the layout's model
  (plane: straight sides; Poincare disk: as hyperbolic triangles, whose sides are geodesics;
  sphere: seen from outside); PLY only: texture_flipped, faces with a planar or disk layout whose
  texture coordinates (texcoord_double, as a texture draws them: straight) are turned over;
* the quasi-conformal ratio of each face's affine map from 3D to its layout (singular values'
  ratio): median, p95, max over the faces where it is finite; degenerate: the faces where it is
  not (zero area in 3D or in the layout); qc_log_mean, the mean of its log over those faces, and
  qc_area_median, its median over the surface (each face weighted by its 3D area, the degenerate
  ones at infinity): measures of a map that depend less than the median on how finely the tool
  cut its cells;
* PLY only: the angle sum at every interior vertex of the delivered mesh, its corner angles
  measured in the layout's model (Euclidean angles in the plane, hyperbolic angles between the
  geodesic sides in the Poincare disk, spherical ones on the unit sphere), against 2 pi - Kbar
  (Kbar: ricci_target; 0 at the vertices of a subdivision); the largest error, over all interior
  vertices and over those the layout cuts open (corners at more than one position); and over the
  resolved ones (resolved_angle_error, resolved_vertices): interior vertices whose faces all have
  nonzero 3D area and angles that double precision resolves in the model -- one rounding of a
  corner's coordinates (unit round-off times the coordinates' size; in the Poincare disk, 2 / (1 -
  |z|^2) times that in the hyperbolic metric) turns no side by more than 1e-10 rad (over the
  face's shortest side). Near the disk's rim a face 1e-9 wide is not resolved: no double
  coordinates draw its angles to 1e-8.

The layout of a ricci-flow PLY: layout_corners per face corner where the file has them (the
model's coordinates, in each face's chart), else layout_x/y/z per vertex; the model per face from
ricci_layout (1 plane, 2 Poincare disk, 3 sphere).

--atlas adds columns (after the ones above, same line, same TSV) measuring the texture atlas: the
texture coordinates per face corner, in [0, 1]^2 (OBJ: vt per corner, polygons fanned; PLY: the
face property texcoord_double, else texcoord, else layout_corners when every face is in the plane):

* atlas_D: the area distortion's spread: with A_f the 3D and a_f the UV area of face f, each
  normalized to sum 1 (faces with A_f = 0 or a_f = 0 left out and counted in atlas_uv_degenerate),
  s_f = log(a_f / A_f) / 2, D = sqrt(sum_f A_f (s_f - s_mean)^2), s_mean = sum_f A_f s_f;
* atlas_qc_median, atlas_qc_p95, atlas_qc_max: the quasi-conformal ratio of the atlas's faces
  (as qc_* above, of the atlas rather than of the layout's model);
* atlas_flipped: faces oriented against the majority of the faces with nonzero UV area;
* atlas_overlap: on a raster of N x N texels (--atlas-res, 2048) of [0, 1]^2, the share of the
  covered texels that more than one face covers; a texel is covered by the faces containing its
  centre, points on a side (or corner) going to exactly one of the faces sharing it (the fill
  rule of the point moved by (eps, eps^2): exact, no tolerance);
* atlas_seam: the summed 3D length of the seam edges over sqrt(3D area); a seam edge: an edge of
  the mesh (vertices welded by exact 3D position) whose faces disagree on the texture coordinates
  at either of its ends (by more than 1e-6 of the atlas's extent); boundary edges are no seams;
  atlas_seam_edges: their number;
* atlas_charts: connected components of the faces across edges that are no seam;
* atlas_util_square: the UV area over the area of [0, 1]^2; atlas_util_bbox: over the area of the
  UV bounding box; atlas_outside: the share of corners outside [0, 1]^2 (before --atlas-fit);
* --atlas-fit: first move and scale each file's texture coordinates uniformly so that their
  bounding box fits [0, 1]^2 (longer side 1) -- for tools that do not pack into the unit square;
  changes only atlas_overlap's resolution and atlas_util_square.
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
ATLAS_FIT = False  # --atlas-fit
ATLAS_RES = 2048  # --atlas-res


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
    """Per face: > 0 when counter-clockwise in the model (plane: straight; disk: the hyperbolic
    triangle; sphere: seen from outside), 0 where its corners are on a line (or coincide)."""
    if model == SPHERE:
        return np.einsum("ij,ij->i", np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]),
                         t[:, 0] + t[:, 1] + t[:, 2])
    if model == DISK:
        # The Moebius map taking the first corner to 0 makes the sides from it straight rays: the
        # sign of the angle from the second corner to the third there. In extended precision, as
        # corner_angle: the Klein model's 2 z / (1 + |z|^2) turned faces 1e-12 wide its way
        # (OpenFOAM's motorbike: 23 of its faces squeezed in the Poincare disk).
        zp, zq, zr = (x[:, 0].astype(np.longdouble) + 1j * x[:, 1].astype(np.longdouble)
                      for x in (t[:, 0], t[:, 1], t[:, 2]))
        wq = (zq - zp) / (1 - np.conj(zp) * zq)
        wr = (zr - zp) / (1 - np.conj(zp) * zr)
        return (np.conj(wq) * wr).imag.astype(float)
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


UNIT_ROUNDOFF = 2.0 ** -52
RESOLVED_TURN = 1e-10


def resolved_faces(faces, corners, model, surface):
    """Per face: nonzero 3D area, and one rounding of its corners turns its sides by <= 1e-10."""
    p, q, r = (corners[:, k].astype(np.longdouble) for k in range(3))
    if model == DISK:
        z = [x[:, 0] + 1j * x[:, 1] for x in (p, q, r)]
        side = np.min([2 * np.arctanh(np.minimum(np.abs((b - a) / (1 - np.conj(a) * b)), 1))
                       for a, b in ((z[0], z[1]), (z[1], z[2]), (z[2], z[0]))], axis=0)
        size = np.max([2 / (1 - np.minimum(np.abs(a) ** 2, 1)) for a in z], axis=0)
    else:
        side = np.min([np.linalg.norm(b - a, axis=1) for a, b in ((p, q), (q, r), (r, p))], axis=0)
        size = np.max([np.abs(x).max(axis=1) for x in (p, q, r)], axis=0)
        if model == SPHERE:
            size = np.ones_like(size)
    with np.errstate(divide="ignore", invalid="ignore"):
        turn = (UNIT_ROUNDOFF * size / side).astype(float)
    area = np.linalg.norm(np.cross(surface[faces[:, 1]] - surface[faces[:, 0]],
                                   surface[faces[:, 2]] - surface[faces[:, 0]]), axis=1)
    return (turn <= RESOLVED_TURN) & (area > 0)


def angle_sums(faces, corners, model, kbar, num_vertices, resolved=None):
    """(largest error, interior vertices checked, largest error at cut vertices, cut vertices,
    largest error at resolved vertices, resolved vertices): resolved, per face, as
    resolved_faces."""
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
    unresolved = np.zeros(num_vertices, dtype=bool)
    if resolved is not None:
        unresolved[faces[~resolved].ravel()] = True
    fine = check & ~unresolved
    worst_fine = float(error[fine].max()) if fine.any() else float("nan")
    return worst, int(check.sum()), worst_cut, int(on_cut.sum()), worst_fine, int(fine.sum())


def measure_ply(path, atlas=False):
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
        row = {"file": path, "faces": len(faces), "models": "none"}
        if atlas:
            row.update(atlas_ply(surface, faces, f, None, None))
        return row
    if model is None:  # files without ricci_layout: the plane where z = 0, else the sphere
        model = np.where(np.all(corners[:, :, 2] == 0, axis=1), PLANE, SPHERE)
    kbar = np.array(v["ricci_target"], dtype=float)
    if "ricci_input_face" in v:  # a subdivision's new vertices are flat
        kbar[np.asarray(v["ricci_input_face"]) >= 0] = 0
    row = {"file": path, "faces": len(faces)}
    names = {PLANE: "plane", DISK: "poincare-disk", SPHERE: "sphere"}
    row["models"] = ",".join(names[m] for m in sorted(set(model.tolist())) if m in names)
    qc, area, flipped = [], [], 0
    worst = worst_cut = worst_fine = float("nan")
    checked = checked_cut = checked_fine = 0
    for m in (PLANE, DISK, SPHERE):
        sel = model == m
        if not sel.any():
            continue
        t = corners[sel]
        flipped += int(np.sum(~(orientation(m, t) > 0)))
        qc.append(quasi_conformal(surface[faces[sel]], t))
        area.append(triangle_areas(surface[faces[sel]]))
        # Angle sums per model; a vertex's faces all lie in one component, so in one model.
        kb = kbar.copy()
        kb[np.setdiff1d(np.arange(n), faces[sel].ravel())] = np.nan
        w, k, wc, kc, wf, kf = angle_sums(faces[sel], t, m, kb, n,
                                          resolved_faces(faces[sel], t, m, surface))
        worst = np.nanmax([worst, w]) if k else worst
        worst_cut = np.nanmax([worst_cut, wc]) if kc else worst_cut
        worst_fine = np.nanmax([worst_fine, wf]) if kf else worst_fine
        checked, checked_cut, checked_fine = checked + k, checked_cut + kc, checked_fine + kf
    row.update(summary(np.concatenate(qc), flipped, np.concatenate(area)))
    if "texcoord_double" in f and len(f["texcoord_double"]) == len(faces):
        uv = np.array(f["texcoord_double"], dtype=float).reshape(-1, 3, 2)
        drawn = uv[(model == PLANE) | (model == DISK)]
        a, b = drawn[:, 1] - drawn[:, 0], drawn[:, 2] - drawn[:, 0]
        row["texture_flipped"] = int(np.sum(~(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] > 0)))
    row.update({"angle_error": worst, "interior_vertices": checked, "cut_angle_error": worst_cut,
                "cut_vertices": checked_cut, "resolved_angle_error": worst_fine,
                "resolved_vertices": checked_fine})
    if atlas:
        row.update(atlas_ply(surface, faces, f, model, corners))
    return row


def atlas_ply(surface, faces, f, model, corners):
    """The atlas columns of a PLY: its wedge texture coordinates, else its plane layout."""
    for key in ("texcoord_double", "texcoord"):
        if key in f and len(f[key]) == len(faces):
            uv = np.array(f[key], dtype=float).reshape(-1, 3, 2)
            return measure_atlas(surface, faces, uv)
    if model is not None and np.all(model == PLANE):
        return measure_atlas(surface, faces, corners[:, :, :2])
    return {}


def summary(qc, flipped, area=None):
    finite = qc[np.isfinite(qc)]
    row = {"flipped": flipped, "degenerate": int(len(qc) - len(finite)),
           "qc_median": float(np.median(finite)) if len(finite) else float("nan"),
           "qc_p95": float(np.percentile(finite, 95)) if len(finite) else float("nan"),
           "qc_max": float(finite.max()) if len(finite) else float("nan")}
    if area is not None:
        row["qc_log_mean"] = float(np.mean(np.log(finite))) if len(finite) else float("nan")
        # The median over the surface rather than over the faces: by 3D area, QC not finite
        # counting as infinite.
        order = np.argsort(np.where(np.isfinite(qc), qc, np.inf), kind="stable")
        weight = np.cumsum(area[order])
        at = np.searchsorted(weight, weight[-1] / 2) if len(qc) and weight[-1] > 0 else None
        row["qc_area_median"] = float(qc[order][at]) if at is not None else float("nan")
    return row


def measure_obj(path, atlas=False):
    v, faces, uv = read_obj(path)
    corners = np.concatenate([uv, np.zeros(uv.shape[:2] + (1,))], axis=2)
    row = {"file": path, "faces": len(faces), "models": "plane"}
    row.update(summary(quasi_conformal(v[faces], corners), int(np.sum(~(orientation(
        PLANE, corners) > 0))), triangle_areas(v[faces])))
    if atlas:
        row.update(measure_atlas(v, faces, uv))
    return row


def triangle_areas(t):
    """Areas of triangles (m, 3, 3), or signed areas of triangles (m, 3, 2)."""
    a, b = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    if t.shape[2] == 2:
        return (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]) / 2
    return np.linalg.norm(np.cross(a, b), axis=1) / 2


def components(n, pairs):
    """Labels 0.. of the connected components of n nodes joined by pairs (k, 2)."""
    try:
        from scipy.sparse import coo_matrix
        from scipy.sparse.csgraph import connected_components
        g = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
        return connected_components(g, directed=False)[1]
    except ImportError:  # union-find
        parent = list(range(n))

        def root(i):
            while parent[i] != i:
                parent[i] = parent[parent[i]]
                i = parent[i]
            return i

        for a, b in pairs.tolist():
            ra, rb = root(a), root(b)
            if ra != rb:
                parent[ra] = rb
        return np.unique([root(i) for i in range(n)], return_inverse=True)[1]


def seams(surface, faces, uv, tol):
    """(seam length, seam edges, charts): edges by welded 3D position; an interior edge is a seam
    when its two faces' texture coordinates differ (by more than tol) at either end."""
    weld = np.unique(surface, axis=0, return_inverse=True)[1].reshape(-1)[faces]
    m = len(faces)
    a, b = weld.ravel(), weld[:, [1, 2, 0]].ravel()  # half-edge c: corner c -> corner c + 1
    ua, ub = uv.reshape(-1, 2), uv[:, [1, 2, 0]].reshape(-1, 2)
    swap = a > b
    lo, hi = np.where(swap, b, a), np.where(swap, a, b)
    ulo, uhi = np.where(swap[:, None], ub, ua), np.where(swap[:, None], ua, ub)
    face = np.repeat(np.arange(m), 3)
    keep = lo != hi  # faces with a repeated vertex: no edge there
    lo, hi, ulo, uhi, face = lo[keep], hi[keep], ulo[keep], uhi[keep], face[keep]
    order = np.lexsort((hi, lo))
    lo, hi, ulo, uhi, face = lo[order], hi[order], ulo[order], uhi[order], face[order]
    # Consecutive half-edges of one edge: joined unless their coordinates differ.
    same = (lo[1:] == lo[:-1]) & (hi[1:] == hi[:-1])
    agree = same & (np.abs(ulo[1:] - ulo[:-1]).max(axis=1) <= tol) & (
        np.abs(uhi[1:] - uhi[:-1]).max(axis=1) <= tol)
    start = np.r_[True, ~same]
    edge = np.cumsum(start) - 1  # edge id per half-edge
    sides = np.bincount(edge)
    # An edge with two or more sides is a seam when any consecutive pair disagrees.
    cut = np.zeros(len(sides), dtype=bool)
    np.logical_or.at(cut, edge[1:][same & ~agree], True)
    seam = cut & (sides >= 2)
    first = np.flatnonzero(start)
    length = np.linalg.norm(surface_welded_diff(surface, faces, weld, lo[first], hi[first]), axis=1)
    pairs = np.stack([face[:-1][agree], face[1:][agree]], axis=1)
    labels = components(m, pairs)
    return float(length[seam].sum()), int(seam.sum()), int(labels.max() + 1) if m else 0


def surface_welded_diff(surface, faces, weld, lo, hi):
    """3D vectors between welded vertices lo and hi (a position per welded index)."""
    pos = np.empty((weld.max() + 1, 3))
    pos[weld.ravel()] = surface[faces.ravel()]
    return pos[hi] - pos[lo]


def raster_counts(uv, res):
    """Per texel of res x res over [0, 1]^2 (flattened, row j = v): how many faces contain its
    centre. Exact edge functions, the same bits on both faces of a side (each side's ends in one
    order), ties on a side going to the face that the centre moved by (eps, eps^2) falls in."""
    p = uv * res  # exact: texel centres at i + 1/2
    area = triangle_areas(p)
    p = p[area != 0]
    neg = triangle_areas(p) < 0
    p[neg] = p[neg][:, [0, 2, 1]]  # counter-clockwise
    lo = np.clip(np.ceil(p.min(axis=1) - 0.5), 0, res).astype(np.int64)
    hi = np.clip(np.floor(p.max(axis=1) - 0.5), -1, res - 1).astype(np.int64)
    size = hi - lo + 1
    ok = (size > 0).all(axis=1)
    p, lo, size = p[ok], lo[ok], size[ok]
    # Buckets of bounding boxes up to powers of two, in chunks of about 4M samples.
    bw = 2 ** np.ceil(np.log2(size)).astype(np.int64)
    key = bw[:, 0] * (4 * res) + bw[:, 1]
    hits = []
    for k in np.unique(key):
        sel = np.flatnonzero(key == k)
        w, h = int(k // (4 * res)), int(k % (4 * res))
        step = max(1, (1 << 22) // (w * h))
        for c in range(0, len(sel), step):
            s = sel[c:c + step]
            t, o, z = p[s], lo[s], size[s]
            gx = np.arange(w)[None, None, :]
            gy = np.arange(h)[None, :, None]
            valid = (gx < z[:, 0, None, None]) & (gy < z[:, 1, None, None])
            ix, iy = o[:, 0, None, None] + gx, o[:, 1, None, None] + gy
            x, y = ix + 0.5, iy + 0.5
            inside = valid
            for e in range(3):
                a, b = t[:, e], t[:, (e + 1) % 3]
                flip = (a[:, 0] > b[:, 0]) | ((a[:, 0] == b[:, 0]) & (a[:, 1] > b[:, 1]))
                ca, cb = np.where(flip[:, None], b, a), np.where(flip[:, None], a, b)
                d = cb - ca
                ec = (d[:, 0, None, None] * (y - ca[:, 1, None, None])
                      - d[:, 1, None, None] * (x - ca[:, 0, None, None]))
                ef = np.where(flip[:, None, None], -ec, ec)
                dx, dy = (b - a)[:, 0, None, None], (b - a)[:, 1, None, None]
                tie = (dy < 0) | ((dy == 0) & (dx > 0))
                inside = inside & ((ef > 0) | ((ef == 0) & tie))
            hits.append((iy * res + ix)[inside])
    idx = np.concatenate(hits) if hits else np.zeros(0, dtype=np.int64)
    return np.bincount(idx, minlength=res * res)


def measure_atlas(surface, faces, uv):
    """The atlas columns of a mesh: positions (n, 3), faces (m, 3), texture coordinates per
    corner (m, 3, 2)."""
    uv = np.asarray(uv, dtype=float)
    finite = np.isfinite(uv).all(axis=(1, 2))
    if not finite.all():  # faces without texture coordinates: left out of the atlas
        faces, uv = faces[finite], uv[finite]
    row = {"atlas_faces": len(faces)}
    if not len(faces):
        return row
    flat = uv.reshape(-1, 2)
    row["atlas_outside"] = float(np.mean(((flat < 0) | (flat > 1)).any(axis=1)))
    low, high = flat.min(axis=0), flat.max(axis=0)
    extent = float((high - low).max())
    if ATLAS_FIT and extent > 0:
        uv = (uv - low) / extent
        low, high, extent = np.zeros(2), (high - low) / extent, 1.0
    big = surface[faces]
    area3, area2 = triangle_areas(big), triangle_areas(uv)
    good = (area3 > 0) & (area2 != 0)
    row["atlas_uv_degenerate"] = int(np.sum(area2 == 0))
    big_a, uv_a = area3[good] / area3[good].sum(), np.abs(area2[good]) / np.abs(area2[good]).sum()
    s = np.log(uv_a / big_a) / 2
    mean = np.sum(big_a * s)
    row["atlas_D"] = float(np.sqrt(np.sum(big_a * (s - mean) ** 2)))
    corners = np.concatenate([uv, np.zeros(uv.shape[:2] + (1,))], axis=2)
    qc = summary(quasi_conformal(big, corners), 0)
    row.update({"atlas_qc_median": qc["qc_median"], "atlas_qc_p95": qc["qc_p95"],
                "atlas_qc_max": qc["qc_max"]})
    positive, negative = int(np.sum(area2 > 0)), int(np.sum(area2 < 0))
    row["atlas_flipped"] = min(positive, negative)
    count = raster_counts(uv, ATLAS_RES)
    covered = int(np.sum(count >= 1))
    row["atlas_overlap"] = float(np.sum(count >= 2) / covered) if covered else float("nan")
    length, edges, charts = seams(surface, faces, uv, 1e-6 * extent)
    row["atlas_seam"] = length / math.sqrt(area3.sum())
    row["atlas_seam_edges"] = edges
    row["atlas_charts"] = charts
    total = float(np.abs(area2).sum())
    row["atlas_util_square"] = total
    box = float(np.prod(high - low))
    row["atlas_util_bbox"] = total / box if box > 0 else float("nan")
    return row


COLUMNS = ("file", "faces", "models", "flipped", "texture_flipped", "degenerate", "qc_median",
           "qc_p95", "qc_max", "qc_log_mean", "qc_area_median", "angle_error", "interior_vertices", "cut_angle_error", "cut_vertices",
           "resolved_angle_error", "resolved_vertices")
ATLAS_COLUMNS = ("atlas_faces", "atlas_D", "atlas_qc_median", "atlas_qc_p95", "atlas_qc_max",
                 "atlas_flipped", "atlas_uv_degenerate", "atlas_overlap", "atlas_seam",
                 "atlas_seam_edges", "atlas_charts", "atlas_util_square", "atlas_util_bbox",
                 "atlas_outside")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("files", nargs="+")
    parser.add_argument("--tsv")
    parser.add_argument("--disk-texcoords", action="store_true",
                        help="PLYs without layout_corners (written before them): texcoord_double "
                        "as (z + 1) / 2 of one Poincare disk")
    parser.add_argument("--atlas", action="store_true",
                        help="add the texture atlas's columns (atlas_*, see the docstring)")
    parser.add_argument("--atlas-fit", action="store_true",
                        help="with --atlas: fit each file's texture coordinates into [0, 1]^2 "
                        "(uniform scale and translation) first")
    parser.add_argument("--atlas-res", type=int, default=2048,
                        help="with --atlas: texels per side of the overlap raster (2048)")
    args = parser.parse_args()
    global DISK_TEXCOORDS, ATLAS_FIT, ATLAS_RES
    DISK_TEXCOORDS = args.disk_texcoords
    ATLAS_FIT, ATLAS_RES = args.atlas_fit, args.atlas_res
    columns = COLUMNS + ATLAS_COLUMNS if args.atlas else COLUMNS
    if args.atlas:
        print("# " + "\t".join(columns))
    rows = []
    for path in args.files:
        measure = measure_obj if path.lower().endswith(".obj") else measure_ply
        row = measure(path, atlas=True) if args.atlas else measure(path)
        rows.append(row)
        print("\t".join(("%.4g" % row[k]) if isinstance(row.get(k), float) else str(row.get(k, ""))
                        for k in columns))
        sys.stdout.flush()
    if args.tsv:
        with open(args.tsv, "w") as out:
            out.write("\t".join(columns) + "\n")
            for row in rows:
                out.write("\t".join(repr(float(row[k])) if isinstance(row.get(k), float)
                                    else str(row.get(k, "")) for k in columns) + "\n")


if __name__ == "__main__":
    sys.exit(main())
