#!/usr/bin/env python3
"""Tabulates the delivered subdivisions of a check_real_meshes.py run, from its JSON reports.

Usage: subdivision_table.py OUT_DIR

One Markdown row per component delivered as a subdivision of its input (after edge flips whose
input faces would turn over, sides split for the Poincare disk's drawing, or a Poincare disk in
charts): mesh (component), topology and geometry, edge flips during the flow, input faces that
would have turned over, rim splits, charts, the subdivision's size against the input's, the
subdivision's seconds against the flow's, the delivered faces turned over and collapsed (the
tool's own count), and the status check_real_meshes.py gave the whole mesh.
"""
import json
import os
import sys


def main():
    out = sys.argv[1]
    status = {}
    with open(os.path.join(out, "results.tsv")) as f:
        next(f)
        for line in f:
            cells = line.rstrip("\n").split("\t")
            status[cells[0]] = cells[2]
    print("| mesh (component) | topology, geometry | flips | input faces that would turn | "
          "rim splits | charts | subdivision: vertices (new), faces (input) | "
          "subdivision s / flow s | delivered faces turned, collapsed | mesh's result |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    rows = 0
    for name in sorted(status):
        path = os.path.join(out, name + ".json")
        if not os.path.exists(path):
            continue
        report = json.load(open(path))
        components = report.get("components", [report])
        for k, c in enumerate(components):
            layout = c.get("layout") or {}
            sub = layout.get("common_subdivision")
            if not sub:
                continue
            label = name + (" (%d)" % k if len(components) > 1 else "")
            mesh = c["mesh"]
            print("| %s | %s, %s | %d | %d | %d | %s | %d (%d), %d (%d) | %.3f / %.2f | %d, %d | %s |" % (
                label, mesh["topology"], c["geometry"], c["edge_flips"],
                layout.get("input_faces_turned_over", 0), sub.get("disk_splits", 0),
                layout.get("charts", 1), sub["vertices"], sub["new_vertices"], sub["faces"],
                mesh["faces"], sub["seconds"], c["seconds"]["flows"], layout["flipped_faces"],
                layout["collapsed_faces"], status[name]))
            rows += 1
    print("\n%d components delivered as a subdivision" % rows)


if __name__ == "__main__":
    sys.exit(main())
