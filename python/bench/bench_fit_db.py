"""Times aniso.fit_many on a generated database (docs/fit-db.md, "Scaling"): `make bench-fit-db`.

The database: --csv CSV files of samples and --merl MERL tables of random analytic materials
(python/bench/fitdb_data.py), fitted with --models, on the local thread pool and on a Dask
LocalCluster of 1, 2 and N worker processes (one thread each; the files sent as bytes, as to a
cluster without a shared file system). Prints a Markdown table: wall time, pairs per second, per
second per worker, and the bytes moved per task (the input file out, the fitted material back).

    PYTHONPATH=build/release/python /usr/bin/python3 python/bench/bench_fit_db.py [--csv 18] [--merl 2]
        [--workers 1,2,4] [--threads 1,2] [--keep DIR]
"""
import argparse
import os
import pathlib
import pickle
import sys
import tempfile
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import fitdb_data  # noqa: E402

import aniso  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--csv", type=int, default=18)
    p.add_argument("--merl", type=int, default=2)
    p.add_argument("--samples", type=int, default=2000, help="samples per CSV file")
    p.add_argument("--models", default="ward,ashikhmin-shirley,ggx,lafortune:3")
    # N: every core, and at least 4 (on a 2-core machine that shows oversubscription).
    p.add_argument("--workers", default=f"1,2,{max(4, os.cpu_count() or 1)}", help="Dask worker processes to time")
    p.add_argument("--threads", default="1,2", help="local thread pool sizes to time")
    p.add_argument("--starts", type=int, default=6)
    p.add_argument("--max-iterations", type=int, default=200)
    p.add_argument("--keep", help="write the database and the last run's DIR here (report.png)")
    a = p.parse_args()
    root = pathlib.Path(a.keep) if a.keep else pathlib.Path(tempfile.mkdtemp(prefix="aniso-bench-fit-db-"))
    db = root / "db"
    t = time.perf_counter()
    paths = fitdb_data.make_database(db, csv_count=a.csv, merl_count=a.merl, seed=2026, samples=a.samples)
    print(f"database: {len(paths)} materials ({a.csv} CSV of {a.samples} samples, {a.merl} MERL tables) in "
          f"{time.perf_counter() - t:.1f} s; models {a.models}; starts {a.starts}, max_iterations {a.max_iterations}; "
          f"{os.cpu_count()} cores", file=sys.stderr)
    options = {"starts": a.starts, "max_iterations": a.max_iterations}
    pairs = len(paths) * len(a.models.split(","))
    results = []

    def timed(label, count, **kw):
        out = root / "out"
        t0 = time.perf_counter()
        rows = aniso.fit_many([str(p) for p in paths], a.models, out=out, force=True, progress=True, dataframe=False,
                              **kw, **options)
        wall = time.perf_counter() - t0
        failed = sum(1 for r in rows if r["status"] != "ok")
        fit_s = sum(float(r["seconds"]) for r in rows if r["status"] == "ok")
        by_kind = {}
        for r in rows:
            if r["status"] == "ok":
                by_kind.setdefault(pathlib.Path(r["input"]).suffix, []).append(float(r["seconds"]))
        kinds = ", ".join(f"{k} {sum(v) / len(v):.2f} s" for k, v in sorted(by_kind.items()))
        results.append((label, count, wall, fit_s, failed, os.getloadavg()[1], kinds))
        print(f"{label}: {wall:.1f} s", file=sys.stderr)
        return rows

    for n in [int(x) for x in a.threads.split(",") if x]:
        rows = timed(f"thread pool, {n} thread{'s' if n > 1 else ''}", n, workers=n)
    for n in [int(x) for x in a.workers.split(",") if x]:
        from distributed import Client, LocalCluster
        with LocalCluster(n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
                          dashboard_address=None) as cluster, Client(cluster) as client:
            client.run(lambda: __import__("aniso"))  # the workers' import is not the fits' time
            rows = timed(f"Dask LocalCluster, {n} worker process{'es' if n > 1 else ''}", n, client=client)

    sizes_in = [os.path.getsize(r["input"]) for r in rows]
    sizes_out = []
    for r in rows:
        if r["status"] == "ok":
            fitted = (root / "out" / r["file"]).read_text()
            sizes_out.append(len(pickle.dumps({"fitted": fitted, "parameters": r["parameters"]})))
    print(f"\n{pairs} pairs ({len(paths)} materials x {len(a.models.split(','))} models)\n")
    # The machine's 5-minute load average at the end of each run: others' work on a shared machine
    # shows there.
    print("| run | workers | wall s | pairs / s | pairs / s / worker | sum of fit times s | mean fit s by input | failed | load (5 min) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for label, workers, wall, fit_s, failed, load, kinds in results:
        print(f"| {label} | {workers} | {wall:.1f} | {pairs / wall:.2f} | {pairs / wall / workers:.2f} | {fit_s:.1f} | {kinds} | "
              f"{failed} | {load:.1f} |")
    print(f"\nbytes per task to the worker (the input file, Dask without --shared-fs): mean {sum(sizes_in) / len(sizes_in):,.0f}, "
          f"CSV {min(sizes_in):,}, MERL {max(sizes_in):,}; back (the fitted material and parameters, pickled): "
          f"mean {sum(sizes_out) / max(1, len(sizes_out)):,.0f}")
    print(f"\nfiles: {root}", file=sys.stderr)


if __name__ == "__main__":
    main()
