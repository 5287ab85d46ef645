"""Batches of real mesh files on a distributed.LocalCluster with two workers, broken files among
them: one row per mesh in the order given, each row agreeing with the command line tool run on
that file alone, failures that never stop the others, the table written as CSV, and an atlas's
columns as its report gives them."""
import csv
import json
import math
import os
import subprocess
import sys

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
REAL = os.path.join(ROOT, "third_party", "real-meshes")
REAL_MESHES = ["admesh-block.stl", "bouncy-farmer.obj", "bouncy-rabbit.obj",
               "matgeom-apple.ply", "netgen-part1.stl", "chess-knight.obj", "lib3mf-helix.stl",
               "gltron-recognizer-quad.obj", "geomview-mushroom.off", "mujoco-mug.obj",
               "kivy-monkey.obj", "meshcat-slotted-disk.stl"]


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    folder = tmp_path_factory.mktemp("broken")
    garbage = folder / "garbage.obj"
    garbage.write_text("this is not a mesh\n")
    moebius = folder / "moebius.off"  # a Moebius strip: not orientable, refused
    n = 6
    lines = ["OFF", "%d %d 0" % (2 * n, 2 * n)]
    import math
    for i in range(n):
        t = 2 * math.pi * i / n
        for s in (-1, 1):
            w = 0.3 * s
            lines.append("%r %r %r" % ((1 + w * math.cos(t / 2)) * math.cos(t),
                                      (1 + w * math.cos(t / 2)) * math.sin(t), w * math.sin(t / 2)))
    for i in range(n):
        a, b = 2 * i, 2 * i + 1
        c, d = (2 * i + 2, 2 * i + 3) if i + 1 < n else (1, 0)  # the half twist
        lines += ["3 %d %d %d" % (a, c, b), "3 %d %d %d" % (b, c, d)]
    moebius.write_text("\n".join(lines) + "\n")
    paths = [os.path.join(REAL, m) for m in REAL_MESHES]
    missing = [p for p in paths if not os.path.exists(p)]
    assert not missing, "run scripts/setup.sh (it fetches the real meshes): %s" % missing
    return paths + [str(garbage), str(moebius), str(folder / "missing.stl")]


def tool(path, out):
    script = os.path.join(os.path.dirname(sys.executable), "ricci-flow")
    done = subprocess.run([script, path, "-o", out, "--quiet"], capture_output=True, text=True)
    return done.returncode, done.stderr.strip().replace("ricci-flow: error: ", "")


def test_batch_on_a_local_cluster_with_two_workers(meshes, tmp_path):
    from distributed import Client, LocalCluster

    from ricci_flow import batch
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        table = batch.run(meshes, tmp_path / "out", client=client, progress=False)
    assert list(table["mesh"]) == [os.path.basename(p) for p in meshes]
    for path, row in zip(meshes, table.to_dict("records")):
        code, message = tool(path, str(tmp_path / "alone.ply"))
        assert row["status"] == ("ok" if code == 0 else "failed"), (path, row, message)
        if code == 0:
            assert os.path.getsize(row["output"]) > 0
            assert row["flipped_faces"] == 0 and row["iterations"] >= 0
        else:
            assert row["message"] == message, path
        for column in batch.COLUMNS:  # no atlas asked for
            if column.startswith("atlas_"):
                assert row[column] is None or math.isnan(row[column]), (path, column)
    by_name = {r["mesh"]: r for r in table.to_dict("records")}
    assert by_name["garbage.obj"]["status"] == "failed"
    assert "not orientable" in by_name["moebius.off"]["message"]
    assert "cannot open" in by_name["missing.stl"]["message"]
    assert (table["status"] == "ok").sum() >= 10
    with open(tmp_path / "out" / "results.csv") as f:
        rows = list(csv.DictReader(f))
    assert [r["mesh"] for r in rows] == list(table["mesh"])
    assert [r["status"] for r in rows] == list(table["status"])


def test_batch_from_the_shell(meshes, tmp_path):
    script = os.path.join(os.path.dirname(sys.executable), "ricci-flow-batch")
    chosen = meshes[:3] + meshes[-1:]
    done = subprocess.run([script] + chosen + ["-o", str(tmp_path), "--workers", "2", "--",
                                               "--flips", "always"],
                          capture_output=True, text=True)
    assert done.returncode == 1, done.stderr  # the missing file failed
    assert "3 of 4 meshes ok" in done.stdout
    assert "4 of 4 meshes done" in done.stderr
    assert "Traceback" not in done.stderr, done.stderr  # Dask's progress feed's, at shutdown
    with open(tmp_path / "results.csv") as f:
        rows = list(csv.DictReader(f))
    assert [r["status"] for r in rows] == ["ok", "ok", "ok", "failed"]


def test_an_atlas_batch_has_the_atlas_columns_of_each_report(tmp_path):
    # A part alone (the farmer) and a file of 9 parts in one texture (the rabbit).
    from ricci_flow import batch
    chosen = [os.path.join(REAL, m) for m in ("bouncy-farmer.obj", "bouncy-rabbit.obj")]
    table = batch.run(chosen, tmp_path, workers=1, progress=False, target="atlas")
    assert list(table["status"]) == ["ok", "ok"], list(table["message"])
    for row in table.to_dict("records"):
        with open(os.path.splitext(row["output"])[0] + ".json") as f:
            report = json.load(f)
        parts = report.get("components") or [report]
        atlases = [p["layout"]["atlas"] for p in parts]
        texture = report.get("texture")
        assert (texture is not None) == (len(parts) > 1), row["mesh"]
        assert row["atlas_cones"] == sum(len(a["cones"]) for a in atlases)
        assert row["atlas_charts"] == sum(a["charts"] for a in atlases) >= len(parts)
        whole = texture or atlases[0]
        assert row["atlas_distortion"] == whole["distortion"] <= 0.2
        assert row["atlas_utilization"] == whole["utilization"]
        assert 0 < row["atlas_utilization"] <= 1
        assert row["atlas_bound_reached"]
        assert row["atlas_charts_below_a_texel"] == 0
        assert row["atlas_overlapping_faces"] == 0
    with open(tmp_path / "results.csv") as f:
        rows = list(csv.DictReader(f))
    assert [float(r["atlas_distortion"]) for r in rows] == list(table["atlas_distortion"])
