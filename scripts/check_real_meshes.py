#!/usr/bin/env python3
"""Runs ricci-flow with its defaults on every real mesh and checks each result on its own.

Usage: check_real_meshes.py RICCI_FLOW OUT_DIR [--timeout SECONDS] [MESH ...]

Meshes default to those listed in meshes/real-meshes.tsv (fetched by scripts/real_meshes.sh into
third_party/real-meshes/) and CGAL's set. A result counts as valid when ricci-flow exited 0 and the
written PLY, read here by a reader of this script's own, has every face laid out with positive
orientation: in the texture (per vertex or per face corner), on the unit sphere (layout_x/y/z), in
the Poincare disk. Prints one row per mesh and a summary; writes OUT_DIR/results.tsv, and each
run's JSON report beside its PLY.
"""
import argparse
import os
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import measure_layouts  # noqa: E402  (the one PLY reader of the scripts)


def read_ply(path):
    """Vertex properties (dict of arrays), faces (list of index lists), face texcoords or None:
    the double-precision wedge coordinates where the file has them (float ones can turn thin
    faces over by rounding alone)."""
    vertex, face = measure_layouts.read_ply(path)
    faces = [[int(x) for x in t] for t in face.get("vertex_indices", [])]
    return vertex, faces, face.get("texcoord_double") or face.get("texcoord") or None


def signed_areas_2d(a, b, c):
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])


def unresolved(corners):
    """Faces whose orientation the double corners do not determine: |u x v| within 64 roundings
    of the corners' magnitude times |u| + |v| (counted as collapsed, not turned)."""
    c = np.asarray(corners, dtype=float)
    if c.shape[2] == 2:
        c = np.concatenate([c, np.zeros(c.shape[:2] + (1,))], axis=2)
    u, w = c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]
    magnitude = np.abs(c).max(axis=(1, 2)) * np.sqrt(3)
    noise = 64 * np.finfo(float).eps * magnitude * (np.linalg.norm(u, axis=1) +
                                                     np.linalg.norm(w, axis=1))
    return np.linalg.norm(np.cross(u, w), axis=1) <= noise


def check(ply_path):
    """(faces, flipped, collapsed, kind) of a result, measured here."""
    v, faces, wedges = read_ply(ply_path)
    f = np.array(faces)
    if "layout_x" in v and np.any(np.isfinite(v["layout_x"])):
        # The double-precision layout where there is one per vertex: the plane (z = 0) or the
        # unit sphere.
        p = np.stack([v["layout_x"], v["layout_y"], v["layout_z"]], axis=1)
        f = f[np.all(np.isfinite(p[f]).reshape(len(f), -1), axis=1)]
        # Per face: in the plane when its corners have z = 0, else on the sphere (components of
        # both kinds can share one file).
        planar = np.all(p[f][:, :, 2] == 0, axis=1)
        area = np.where(planar, signed_areas_2d(p[f[:, 0]], p[f[:, 1]], p[f[:, 2]]),
                        # det(p0, p1, p2) from differences: exact in sign for small triangles
                        np.einsum("ij,ij->i", np.cross(p[f[:, 1]] - p[f[:, 0]],
                                                       p[f[:, 2]] - p[f[:, 0]]),
                                  p[f[:, 0]] + p[f[:, 1]] + p[f[:, 2]]))
        kind = "plane" if planar.all() else ("sphere" if not planar.any() else "plane and sphere")
        fuzzy = unresolved(p[f])
    elif wedges is not None:
        t = np.array(wedges).reshape(-1, 3, 2)
        laid = np.abs(t).sum(axis=(1, 2)) > 0  # faces of sphere components carry zeros
        area = signed_areas_2d(t[laid, 0], t[laid, 1], t[laid, 2])
        fuzzy = unresolved(t[laid])
        kind = "wedge uv"
    else:
        return len(faces), 0, 0, "no layout"
    # The tool's own rule for a collapsed face: under 1e-12 of the mean layout triangle.
    scale = max(np.abs(area).mean(), 1e-300)
    flipped = int(np.sum((area <= 0) & ~fuzzy))
    collapsed = int(np.sum(((area > 0) & (area <= 1e-12 * scale)) | ((area <= 0) & fuzzy)))
    return len(faces), flipped, collapsed, kind


def default_meshes():
    meshes = []
    tsv = os.path.join(ROOT, "meshes", "real-meshes.tsv")
    folder = os.path.join(ROOT, "third_party", "real-meshes")
    for line in open(tsv).read().splitlines()[1:]:
        name, _source, _path, fmt, _licence, category, _note = line.split("\t")
        found = [f for f in os.listdir(folder) if os.path.splitext(f)[0] == name]
        meshes.append((os.path.join(folder, found[0] if found else name + "." + fmt), category))
    return meshes


def parse_arguments():
    """TOOL OUT_DIR [--timeout S] [MESH ...], with OUT_DIR made."""
    parser = argparse.ArgumentParser()
    parser.add_argument("tool")
    parser.add_argument("out")
    parser.add_argument("--timeout", type=float, default=120)
    parser.add_argument("meshes", nargs="*")
    args = parser.parse_intermixed_args()
    os.makedirs(args.out, exist_ok=True)
    return args


def main():
    args = parse_arguments()
    meshes = [(m, "") for m in args.meshes] or default_meshes()
    rows = []
    for path, category in meshes:
        name = os.path.basename(path)
        out = os.path.join(args.out, name + ".ply")
        report = os.path.join(args.out, name + ".json")
        for old in (out, report):
            if os.path.exists(old):
                os.remove(old)
        start = time.time()
        try:
            r = subprocess.run([args.tool, path, "-o", out, "--report", report, "--quiet"], capture_output=True,
                               text=True, timeout=args.timeout)
            code, message = r.returncode, r.stderr.strip().replace("\n", " ")
        except subprocess.TimeoutExpired:
            code, message = -1, "timeout after %.0f s" % args.timeout
        seconds = time.time() - start
        if code == 0:
            faces, flipped, collapsed, kind = check(out)
            status = "valid" if flipped == 0 and collapsed == 0 else (
                "FLIPPED" if flipped else "COLLAPSED")
            detail = "%d faces, %s, %d flipped, %d collapsed" % (faces, kind, flipped, collapsed)
        else:
            status = "refused" if code in (1, 2) else "failed"
            detail = message.replace("ricci-flow: error: ", "")
        rows.append((name, category, status, "%.1f" % seconds, detail))
        print("%-40s %-22s %-8s %6s s  %s" % (name, category, status, rows[-1][3], detail[:160]),
              flush=True)
    with open(os.path.join(args.out, "results.tsv"), "w") as f:
        f.write("mesh\tcategory\tstatus\tseconds\tdetail\n")
        for row in rows:
            f.write("\t".join(row) + "\n")
    counts = {}
    for row in rows:
        counts[row[2]] = counts.get(row[2], 0) + 1
    print(" ".join("%s %d" % kv for kv in sorted(counts.items())), "of", len(rows))


if __name__ == "__main__":
    sys.exit(main())
