#!/usr/bin/python3
"""The table of docs/performance.md from aniso_bench JSON runs.

Usage: scripts/perf_table.py RUN1.json [RUN2.json ...] [--clock-ghz 2.3] [--lanes 16] [--cores 2]

Every rate is per second of wall-clock time (the scalar benchmarks' CPU-time rate is rescaled by
cpu_time / real_time). Each JSON file is one `aniso_bench --benchmark_repetitions=N --benchmark_out=RUN.json
--benchmark_out_format=json` run. Per run, the median over its repetitions of every benchmark's
items_per_second; the ratios batch / scalar and batch_mt / batch are taken within a run (the machine
is shared: runs differ, a run's benchmarks are close in time); the table gives the median over runs
of the rates and of the ratios. Fraction of peak = rate x flops per evaluation / peak, with peak =
cores x lanes x 2 FMA units x 2 flops per FMA x clock (one core for batch/, all for batch_mt/).
"""
import json
import statistics
import sys

# Floating-point operations per f evaluation, float, counted by hand from the kernels
# (docs/performance.md, "Flops per evaluation"): add, sub, mul, div, sqrt and compare-free selects
# count 1 each, an FMA 2; exp ~20, log ~18 (Highway's polynomials), pow = log + mul + exp ~40.
FLOPS = {
    "lambert": 0,
    "phong": 52,
    "ward/vector/ward": 41, "ward/vector/duer": 40, "ward/vector/balanced": 47,
    "ward/angle/ward": 100, "ward/angle/duer": 99, "ward/angle/balanced": 106,
    "ward/approx/ward": 50, "ward/approx/duer": 49, "ward/approx/balanced": 56,
    "ashikhmin-shirley": 109,
    "lafortune/matte-steel": 426,
    "ggx": 71,
    "metal/gold": 146,
    "metal/brushed-gold": 280,
    "material/ward/vector/ward": 41,
    "material/lambert": 0,
}


def medians(path):
    with open(path) as f:
        data = json.load(f)
    out = {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name") == "median" and "items_per_second" in b:
            rate = b["items_per_second"]
            if not b["run_name"].startswith(("batch/", "batch_mt/")):
                # The scalar benchmarks' items_per_second is per CPU second: rescale it to the
                # wall clock (cpu_time / real_time) like the batch benchmarks' own counter.
                rate *= b["cpu_time"] / b["real_time"]
            out[b["run_name"]] = rate
    return out


def main(argv):
    clock, lanes, cores = 2.3, 16, 2
    files = []
    i = 0
    while i < len(argv):
        if argv[i] == "--clock-ghz":
            clock = float(argv[i + 1]); i += 2
        elif argv[i] == "--lanes":
            lanes = int(argv[i + 1]); i += 2
        elif argv[i] == "--cores":
            cores = int(argv[i + 1]); i += 2
        else:
            files.append(argv[i]); i += 1
    runs = [medians(p) for p in files]
    peak_core = lanes * 2 * 2 * clock * 1e9
    print(f"peak: {peak_core / 1e9:.1f} GFLOP/s per core, {cores * peak_core / 1e9:.1f} GFLOP/s on {cores} cores "
          f"({lanes} lanes x 2 FMA x 2 flops x {clock} GHz); {len(runs)} run(s)\n")
    for prefix, title in (("f/", "f (evaluate)"), ("pdf/", "pdf"), ("sample/", "sample")):
        print(f"### {title}\n")
        print("| name | scalar M/s | batch M/s | batch_mt M/s | batch / scalar | batch_mt / batch | flops | batch % peak | batch_mt % peak |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
        names = sorted({k[len(prefix):] for r in runs for k in r if k.startswith(prefix)},
                       key=lambda n: list(FLOPS).index(n) if n in FLOPS else 99)
        for name in names:
            bpre = "" if prefix == "f/" else prefix
            s = [r[prefix + name] for r in runs if prefix + name in r]
            b = [r["batch/" + bpre + name] for r in runs if "batch/" + bpre + name in r]
            m = [r["batch_mt/" + bpre + name] for r in runs if "batch_mt/" + bpre + name in r]
            rb = [r["batch/" + bpre + name] / r[prefix + name] for r in runs
                  if prefix + name in r and "batch/" + bpre + name in r]
            rm = [r["batch_mt/" + bpre + name] / r["batch/" + bpre + name] for r in runs
                  if "batch_mt/" + bpre + name in r and "batch/" + bpre + name in r]
            if not (s and b and m):
                continue
            med = statistics.median
            flops = FLOPS.get(name) if prefix == "f/" else None
            if flops is not None:
                fb = f"{100 * med(b) * flops / peak_core:.1f}"
                fm = f"{100 * med(m) * flops / (cores * peak_core):.1f}"
                fl = str(flops)
            else:
                fb = fm = fl = "-"
            print(f"| `{name}` | {med(s) / 1e6:.1f} | {med(b) / 1e6:.1f} | {med(m) / 1e6:.1f} | {med(rb):.2f} | "
                  f"{med(rm):.2f} | {fl} | {fb} | {fm} |")
        print()


if __name__ == "__main__":
    main(sys.argv[1:])
