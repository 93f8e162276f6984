#!/usr/bin/env python3
"""Evaluating a million direction pairs from Python vs the same batch evaluation from C++.

For each material: N random pairs above the horizon (float64, (N, 3) C-contiguous, the layout a
NumPy user holds); Material.eval on them as float32 and as float64, and
aniso_batch_eval_cpp (python/bench/batch_eval_cpp.cpp) timing batch::evaluate (Threads::All, SIMD)
on the same pairs already in the batch API's structure of arrays (the target's "C++"), and
batch::evaluate_interleaved on them as (N, 3) rows ("C++ rows": what the bindings call for C-ordered
arrays, so Python / C++ rows is the bindings' own overhead). Times are process CPU time (every
thread's: what the work costs, even while other programs share the cores) and wall-clock time.
In each round the C++ program runs (best of REPS calls) and then Python (best of REPS calls: C-ordered (N, 3) input and a new C-ordered
output per call, as a NumPy user would hold them; and "columns": Fortran-ordered input and out=,
which the bindings hand to the batch API in place); a round's ratio compares them, and the table gives the median over rounds (the
machine is shared: seconds apart is comparable, minutes apart is not). The target
(docs/python.md): Python at most 1.5 times C++. `make bench-python`
runs it.

    PYTHONPATH=build/release/python /usr/bin/python3 python/bench/bench_eval.py [--n 1000000] [--reps 15]
"""
import argparse
import os
import pathlib
import subprocess
import sys
import tempfile
import time

import numpy as np

import aniso

HERE = pathlib.Path(__file__).resolve().parent
MATERIALS = ["lambert", "ward", "ashikhmin-shirley", "matte-steel", "ggx", "gold", "brushed-gold"]
SPECS = {  # the bench materials of bench/bench_eval.cpp where a preset name is not one
    "lambert": '{"model": "lambert", "kd": 0.5}',
    "ward": '{"model": "ward", "kd": 0.1, "ks": 0.4, "alpha_x": 0.1, "alpha_y": 0.3}',
    "ashikhmin-shirley": '{"model": "ashikhmin-shirley", "n_u": 100, "n_v": 10}',
    "ggx": '{"model": "ggx", "alpha_x": 0.1, "alpha_y": 0.3}',
}


def pairs(n, seed=1):
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(2 * n, 3))
    v[:, 2] = np.abs(v[:, 2]) + 1e-3
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    return np.ascontiguousarray(v[:n]), np.ascontiguousarray(v[n:])


def best_time(fn, reps):
    """(best wall-clock seconds, best process CPU seconds) of reps calls after a warm-up call."""
    fn()  # warm-up: first touch of the output, oneTBB's threads
    wall = cpu = float("inf")
    for _ in range(reps):
        c, w = time.process_time(), time.perf_counter()
        fn()
        wall, cpu = min(wall, time.perf_counter() - w), min(cpu, time.process_time() - c)
    return wall, cpu


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1_000_000)
    ap.add_argument("--rounds", type=int, default=5, help="rounds of C++ then Python (ratios are taken within a round)")
    ap.add_argument("--reps", type=int, default=5, help="calls per round; a round keeps the best")
    ap.add_argument("--materials", nargs="*", default=MATERIALS)
    ap.add_argument("--cpp", default=os.environ.get("ANISO_BATCH_EVAL_CPP",
                                                    str(HERE.parents[1] / "build/release/bin/aniso_batch_eval_cpp")))
    args = ap.parse_args()
    wi, wo = pairs(args.n)
    wi32, wo32 = wi.astype(np.float32), wo.astype(np.float32)
    with tempfile.TemporaryDirectory() as tmp:
        path = pathlib.Path(tmp) / "pairs.bin"
        np.concatenate([wi, wo], axis=1).tofile(path)
        print(f"# {args.n} pairs; per round the best of {args.reps} calls, medians over {args.rounds} rounds; "
              f"SIMD target {aniso.simd_target()}, {len(os.sched_getaffinity(0))} of {os.cpu_count()} CPUs, "
              f"load average {os.getloadavg()[0]:.1f} at the start")
        print("| material | dtype | C++ ms CPU (wall) | C++ rows ms CPU | Python ms CPU (wall) | columns ms CPU (wall) "
              "| Python / C++ CPU (wall) | columns / C++ CPU (wall) | Python / C++ rows CPU |")
        print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
        for name in args.materials:
            spec = SPECS.get(name, name)
            m = aniso.Material(spec)
            rows = {"float32": [], "float64": []}
            for _ in range(args.rounds):
                out = subprocess.run([args.cpp, "time", str(path), spec, str(args.reps)], capture_output=True, text=True,
                                     check=True)
                f_wall, f_cpu, d_wall, d_cpu, fi_wall, fi_cpu, di_wall, di_cpu = map(float, out.stdout.split()[:8])
                for dtype, (a, b), (c_wall, c_cpu), i_cpu in [("float32", (wi32, wo32), (f_wall, f_cpu), fi_cpu),
                                                              ("float64", (wi, wo), (d_wall, d_cpu), di_cpu)]:
                    # Column-major in and out: the batch API reads and writes the arrays in place.
                    fa, fb, buf = np.asfortranarray(a), np.asfortranarray(b), np.empty((args.n, 3), a.dtype, order="F")
                    p_wall, p_cpu = best_time(lambda: m.eval(a, b), args.reps)
                    q_wall, q_cpu = best_time(lambda: m.eval(fa, fb, out=buf), args.reps)
                    rows[dtype].append((c_cpu, c_wall, p_cpu, p_wall, q_cpu, q_wall, i_cpu))
            for dtype, r in rows.items():
                r = np.array(r)
                med = np.median(r, axis=0)
                ratio = lambda i, j: np.median(r[:, i] / r[:, j])
                print(f"| `{name}` | {dtype} | {1e3 * med[0]:.2f} ({1e3 * med[1]:.2f}) | {1e3 * med[6]:.2f} "
                      f"| {1e3 * med[2]:.2f} ({1e3 * med[3]:.2f}) "
                      f"| {1e3 * med[4]:.2f} ({1e3 * med[5]:.2f}) | {ratio(2, 0):.2f} ({ratio(3, 1):.2f}) "
                      f"| {ratio(4, 0):.2f} ({ratio(5, 1):.2f}) | {ratio(2, 6):.2f} |")
                sys.stdout.flush()
        print(f"# load average {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
