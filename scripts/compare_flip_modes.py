#!/usr/bin/env python3
"""Runs ricci-flow's defaults on each mesh with --flips never, always and when-needed and
compares them: whether each converged to the target asked for ("instead" where a component was
given another target or scheme: the automatic target's free boundary for a circle domain not
reached, the tangential scheme where Yamabe gave no map), the whole process's wall time, the
flows' time, edge flips, Newton iterations, the iteration the when-needed run began flipping at,
and the largest difference of u between when-needed and never (where both converged without
flips).

  scripts/compare_flip_modes.py TOOL OUT_DIR [--timeout S] [MESH ...]

Without meshes: the real-mesh set (meshes/real-meshes.tsv) and CGAL's scans. Writes
OUT_DIR/flip-modes.tsv and prints a summary.
"""
import json
import os
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_real_meshes import ROOT, default_meshes, parse_arguments, read_ply  # noqa: E402

MODES = ("never", "always", "when-needed")
CGAL_SCANS = ("lion-head", "bunny00", "elk", "mannequin-devil", "femur", "camel", "cow",
              "elephant", "hand", "head", "homer", "bear", "dino", "knot1", "eight", "bull")


def cgal_meshes():
    folder = os.path.join(ROOT, "third_party", "cgal-data", "data", "meshes")
    return [os.path.join(folder, n + ".off") for n in CGAL_SCANS
            if os.path.exists(os.path.join(folder, n + ".off"))]


def run(tool, path, mode, out_dir, timeout):
    stem = os.path.join(out_dir, os.path.basename(path) + "." + mode)
    for suffix in (".ply", ".json"):
        if os.path.exists(stem + suffix):
            os.remove(stem + suffix)
    start = time.time()
    try:
        r = subprocess.run([tool, path, "-o", stem + ".ply", "--report", stem + ".json",
                            "--flips", mode, "--quiet"], capture_output=True, text=True,
                           timeout=timeout)
        code = r.returncode
    except subprocess.TimeoutExpired:
        code = -1
    row = {"code": code, "seconds": time.time() - start, "u": None}
    if os.path.exists(stem + ".json"):
        report = json.load(open(stem + ".json"))
        parts = report.get("components") or [report]
        row["converged"] = all(p.get("converged") for p in parts)
        # Components given another target or scheme than the one asked for (the automatic
        # target's free boundary where the circle domain was not reached, the tangential scheme
        # where Yamabe gave no map): what was asked for was not reached.
        row["instead"] = sum(1 for p in parts
                             if p.get("target_instead") or p.get("scheme_instead"))
        row["flips"] = sum(p.get("edge_flips") or 0 for p in parts)
        row["iterations"] = sum(p.get("iterations") or 0 for p in parts)
        row["flows"] = sum((p.get("seconds") or {}).get("flows") or 0 for p in parts)
        starts = [p.get("flips_from_iteration") for p in parts
                  if p.get("flips_from_iteration") is not None]
        row["from"] = ",".join(str(s) for s in starts) if starts else "-"
    if code == 0 and os.path.exists(stem + ".ply"):
        row["u"] = np.asarray(read_ply(stem + ".ply")[0]["ricci_u"])
    return row


def main():
    args = parse_arguments()
    meshes = args.meshes or [m for m, _ in default_meshes()] + cgal_meshes()
    lines = ["mesh\t" + "\t".join("%s_%s" % (m, c) for m in MODES
                                  for c in ("status", "seconds", "flips", "iterations")) +
             "\tflips_from\tdefault_vs_never_u\tdefault_over_always"]
    for path in meshes:
        rows = {m: run(args.tool, path, m, args.out, args.timeout) for m in MODES}
        cells = [os.path.basename(path)]
        for m in MODES:
            r = rows[m]
            status = "ok" if r["code"] == 0 else ("timeout" if r["code"] == -1 else "refused")
            if status == "ok" and r.get("instead"):
                status = "instead"
            cells += [status, "%.2f" % r["seconds"], str(r.get("flips", "-")),
                      str(r.get("iterations", "-"))]
        w, n, a = rows["when-needed"], rows["never"], rows["always"]
        cells.append(w.get("from", "-"))
        diff = "-"
        if w["u"] is not None and n["u"] is not None and w.get("flips") == 0:
            k = min(len(w["u"]), len(n["u"]))
            # NaN where a vertex is in no face, in both.
            diff = "%.1e" % float(np.nanmax(np.abs(w["u"][:k] - n["u"][:k]))) if k else "-"
        cells.append(diff)
        ratio = "-"
        converged = {m: rows[m]["code"] == 0 and not rows[m].get("instead") for m in MODES}
        if converged["when-needed"] and converged["always"] and not converged["never"]:
            ratio = "%.2f" % (w["seconds"] / a["seconds"])
        cells.append(ratio)
        lines.append("\t".join(cells))
        print("  ".join(cells), flush=True)
    with open(os.path.join(args.out, "flip-modes.tsv"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    sys.exit(main())
