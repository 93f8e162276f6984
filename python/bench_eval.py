#!/usr/bin/env python3
"""Evaluating a million direction pairs from Python vs the same batch evaluation from C++.

For each material: N random pairs above the horizon (float64, (N, 3) C-contiguous, the layout a
NumPy user holds); Material.eval on them as float32 and as float64, and
aniso_batch_eval_cpp (python/batch_eval_cpp.cpp) timing batch::evaluate (Threads::All, SIMD)
on the same pairs already in the batch API's structure of arrays. Reports the best and the median
of REPS wall-clock times and the ratio Python / C++ (issue 9: at most 1.5). `make bench-python`
runs it.

    PYTHONPATH=build/release/python /usr/bin/python3 python/bench_eval.py [--n 1000000] [--reps 15]
"""
import argparse
import os
import pathlib
import platform
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


def time_calls(fn, reps):
    fn()  # warm-up: first-touch of the output, TBB's threads
    t = []
    for _ in range(reps):
        start = time.perf_counter()
        fn()
        t.append(time.perf_counter() - start)
    t.sort()
    return t[0], t[len(t) // 2]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1_000_000)
    ap.add_argument("--reps", type=int, default=15)
    ap.add_argument("--cpp", default=os.environ.get("ANISO_BATCH_EVAL_CPP",
                                                    str(HERE.parent / "build/release/bin/aniso_batch_eval_cpp")))
    args = ap.parse_args()
    wi, wo = pairs(args.n)
    wi32, wo32 = wi.astype(np.float32), wo.astype(np.float32)
    with tempfile.TemporaryDirectory() as tmp:
        path = pathlib.Path(tmp) / "pairs.bin"
        np.concatenate([wi, wo], axis=1).tofile(path)
        print(f"# {args.n} pairs, best / median of {args.reps}, SIMD target {aniso.simd_target()}, "
              f"{os.cpu_count()} CPUs, {platform.processor() or platform.machine()}, load {os.getloadavg()[0]:.1f}")
        print("| material | dtype | C++ batch ms (best / median) | Python ms (best / median) | Python / C++ (best / median) |")
        print("|---|---|---:|---:|---:|")
        for name in MATERIALS:
            spec = SPECS.get(name, name)
            m = aniso.Material(spec)
            out = subprocess.run([args.cpp, "time", str(path), spec, str(args.reps)], capture_output=True, text=True, check=True)
            f_best, f_med, d_best, d_med = map(float, out.stdout.split()[:4])
            for dtype, (a, b), (c_best, c_med) in [("float32", (wi32, wo32), (f_best, f_med)), ("float64", (wi, wo), (d_best, d_med))]:
                p_best, p_med = time_calls(lambda: m.eval(a, b), args.reps)
                print(f"| `{name}` | {dtype} | {1e3 * c_best:.2f} / {1e3 * c_med:.2f} | {1e3 * p_best:.2f} / {1e3 * p_med:.2f} "
                      f"| {p_best / c_best:.2f} / {p_med / c_med:.2f} |")
                sys.stdout.flush()


if __name__ == "__main__":
    main()
