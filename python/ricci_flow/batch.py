"""Many mesh files through the flow on Dask (distributed): locally by default, on any cluster when
a client is given.

    from ricci_flow import batch
    table = batch.run(["a.obj", "b.stl"], "out/")         # a local cluster of 2 workers
    table = batch.run(paths, "out/", client=Client("tcp://scheduler:8786"), target="disk")

Each mesh is one task: the command line tool's run on the file with the options (same names as
ricci_flow.uniformize), writing out/NAME.ply and out/NAME.json (the report). A mesh that fails
never stops the others: its row says `failed` and why. The table (one row per mesh: status,
message, topology, iterations, edge flips, seconds, quality; with target="atlas" the atlas's
cones, charts, D, whether the bound was reached, utilization, charts below a texel and
overlapping faces) is returned as a pandas DataFrame and
written to out/results.csv (or .parquet). On a cluster, out_dir must be a folder every worker can
write (a shared file system); Slurm, PBS or Kubernetes clusters come from dask-jobqueue or
dask-kubernetes, whose Client is passed as `client`.

From the shell: ricci-flow-batch MESH... -o OUT_DIR [--workers N] [--table FILE] [-- FLAGS...]
"""
import argparse
import json
import os
import sys
import tempfile
import time

from . import _flags, _ricci_flow

COLUMNS = ["mesh", "status", "message", "topology", "components", "vertices", "faces",
           "iterations", "edge_flips", "seconds", "max_curvature_error", "flipped_faces",
           "quasi_conformal_median", "quasi_conformal_p95", "atlas_cones", "atlas_charts",
           "atlas_distortion", "atlas_bound_reached", "atlas_utilization",
           "atlas_charts_below_a_texel", "atlas_overlapping_faces", "output"]


def output_stems(paths, out_dir):
    """Per path, out_dir/NAME without extension: the file's stem, made unique with the file's
    extension and then a number where stems repeat (a.obj, a.stl, x/a.obj)."""
    stems = [os.path.splitext(os.path.basename(p))[0] for p in paths]
    if len(set(stems)) < len(stems):
        stems = [os.path.basename(p).replace(".", "-") for p in paths]
    seen = {}
    unique = []
    for stem in stems:
        seen[stem] = seen.get(stem, 0) + 1
        unique.append(stem if seen[stem] == 1 else "%s-%d" % (stem, seen[stem]))
    return [os.path.join(out_dir, stem) for stem in unique]


def _summarize(report, row):
    """The row's columns from the tool's JSON report."""
    parts = report.get("components") or [report]
    row["components"] = len(parts)
    row["topology"] = ", ".join(p.get("mesh", {}).get("topology", "?") for p in parts)
    row["vertices"] = sum(p.get("mesh", {}).get("vertices", 0) for p in parts)
    row["faces"] = sum(p.get("mesh", {}).get("faces", 0) for p in parts)
    row["iterations"] = sum(p.get("iterations") or 0 for p in parts)
    row["edge_flips"] = sum(p.get("edge_flips") or 0 for p in parts)
    errors = [(p.get("errors") or {}).get("max_abs_curvature_error") for p in parts]
    errors = [e for e in errors if e is not None]
    row["max_curvature_error"] = max(errors) if errors else None
    layouts = [p.get("layout") or {} for p in parts]
    row["flipped_faces"] = sum(lay.get("flipped_faces") or 0 for lay in layouts)
    qc = [lay.get("quasi_conformal") or {} for lay in layouts]
    medians = [q["median"] for q in qc if q.get("median") is not None]
    p95 = [q["p95"] for q in qc if q.get("p95") is not None]
    row["quasi_conformal_median"] = max(medians) if medians else None
    row["quasi_conformal_p95"] = max(p95) if p95 else None
    atlases = [lay["atlas"] for lay in layouts if lay.get("atlas")]
    if atlases:  # --target atlas: the texture of all the parts, else the one part's
        texture = report.get("texture") or atlases[0]
        row["atlas_cones"] = sum(len(a.get("cones") or []) for a in atlases)
        row["atlas_charts"] = sum(a.get("charts") or 0 for a in atlases)
        row["atlas_distortion"] = texture.get("distortion")
        row["atlas_bound_reached"] = all(a.get("bound_reached") for a in atlases)
        row["atlas_utilization"] = texture.get("utilization")
        row["atlas_charts_below_a_texel"] = texture.get(
            "below_a_texel", texture.get("charts_below_a_texel"))
        row["atlas_overlapping_faces"] = sum(a.get("overlapping_faces") or 0 for a in atlases)


def process(path, stem, flags=()):
    """One mesh: the tool's run with the flags, writing stem.ply and stem.json; the table's row
    (never raises)."""
    row = dict.fromkeys(COLUMNS)
    row.update(mesh=os.path.basename(path), output=stem + ".ply")
    for old in (stem + ".ply", stem + ".json"):
        if os.path.exists(old):
            os.remove(old)
    start = time.perf_counter()
    try:
        message = _ricci_flow.run_file(["ricci-flow", os.fspath(path), "-o", stem + ".ply",
                                        "--report", stem + ".json", "--quiet"] + list(flags))
    except Exception as e:  # usage errors, and anything unexpected: this mesh's row only
        message = str(e) or type(e).__name__
    row["seconds"] = round(time.perf_counter() - start, 4)
    row["status"] = "failed" if message else "ok"
    row["message"] = message
    if message:
        row["output"] = None
    try:
        with open(stem + ".json") as f:
            _summarize(json.load(f), row)
    except (OSError, ValueError):
        pass  # no report: the mesh was not read
    return row


def _run(paths, out_dir, client, workers, table, progress, flags):
    import pandas
    from dask.distributed import Client, LocalCluster, as_completed

    paths = [os.path.abspath(os.fspath(p)) for p in paths]
    out_dir = os.path.abspath(os.fspath(out_dir))
    os.makedirs(out_dir, exist_ok=True)
    cluster = None
    if client is None:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
    try:
        futures = client.map(process, paths, output_stems(paths, out_dir), flags=list(flags),
                             pure=False)
        if progress:
            # Counted here, not by Dask's progress bar: its feed from the scheduler, cancelled when
            # the cluster closes, logged a CancelledError traceback in about half the runs.
            for done, _ in enumerate(as_completed(futures), 1):
                print("\r%d of %d meshes done" % (done, len(futures)), end="", file=sys.stderr,
                      flush=True)
            print(file=sys.stderr)
        rows = []
        for path, future in zip(paths, futures):
            try:
                rows.append(future.result())
            except Exception as e:  # the worker died: this mesh's task is lost, not the others
                row = dict.fromkeys(COLUMNS)
                row.update(mesh=os.path.basename(path), status="failed",
                           message="task failed: %s" % (str(e) or type(e).__name__))
                rows.append(row)
    finally:
        if cluster is not None:
            client.close()
            cluster.close()
    frame = pandas.DataFrame(rows, columns=COLUMNS)
    if table:
        path = os.path.join(out_dir, table)
        if path.endswith(".parquet"):
            frame.to_parquet(path, index=False)
        else:
            frame.to_csv(path, index=False)
    return frame


def run(paths, out_dir, client=None, workers=2, table="results.csv", progress=True, **options):
    """Maps the flow over the mesh files with Dask; returns the results table (a DataFrame, one
    row per mesh, in the order of paths) and writes it to out_dir/table (.csv or .parquet).

    client: a dask.distributed Client; None starts a LocalCluster of `workers` processes (one
    thread each) for this call. options: as ricci_flow.uniformize's."""
    os.makedirs(os.fspath(out_dir), exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="ricci-flow-batch-", dir=out_dir) as folder:
        return _run(paths, out_dir, client, workers, table, progress, _flags(options, folder))


def main(argv=None):
    """ricci-flow-batch MESH... -o OUT_DIR [--workers N] [--scheduler ADDRESS] [--table FILE]
    [-- FLAGS...]: the flow over many files; prints how many succeeded; exit 1 if any failed."""
    argv = list(sys.argv[1:] if argv is None else argv)
    tool_flags = []
    if "--" in argv:
        tool_flags = argv[argv.index("--") + 1:]
        argv = argv[:argv.index("--")]
    parser = argparse.ArgumentParser(
        prog="ricci-flow-batch",
        description="Runs ricci-flow on many meshes with Dask; flags after -- go to ricci-flow.")
    parser.add_argument("meshes", nargs="+")
    parser.add_argument("-o", "--output", required=True, help="folder for results and table")
    parser.add_argument("--workers", type=int, default=2, help="local worker processes [2]")
    parser.add_argument("--scheduler", help="address of a running Dask scheduler instead")
    parser.add_argument("--table", default="results.csv", help="table file name [results.csv]")
    args = parser.parse_args(argv)
    client = None
    if args.scheduler:
        from dask.distributed import Client
        client = Client(args.scheduler)
    frame = _run(args.meshes, args.output, client, args.workers, args.table, True, tool_flags)
    ok = int((frame["status"] == "ok").sum())
    print("%d of %d meshes ok; table: %s" % (ok, len(frame), os.path.join(args.output, args.table)))
    return 0 if ok == len(frame) else 1


if __name__ == "__main__":
    sys.exit(main())
