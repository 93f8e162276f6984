#!/usr/bin/env python3
"""`aniso fit` against the plain least-squares fit (bench/plain_fit.py) on the same files: the
table of docs/fitting.md, "Real measurements".

    /usr/bin/python3 bench/plain_fit.py FILES... --json plain.json      # the yardstick (minutes)
    /usr/bin/python3 bench/fit_table.py plain.json [--json aniso.json]  # aniso's fits, the table

Each row: the file, then per model aniso's relative l2cos over the plain fit's (both over the
samples within 80 degrees, Ngan 2005's range), the ratio (the target: at most 1.1) and aniso's CPU
seconds. Needs aniso's Python module on PYTHONPATH (build/release/python).
"""
import argparse
import json
import sys
import time

import aniso

# bench/plain_fit.py's model names -> aniso.fit's keywords.
MODELS = {"ggx": {"model": "ggx"}, "ggx-f90": {"model": "ggx", "fresnel": "free-f90"}, "ward": {"model": "ward"}, "ashikhmin-shirley": {"model": "ashikhmin-shirley"},
          "lafortune1": {"model": "lafortune", "lobes": 1}, "lafortune3": {"model": "lafortune", "lobes": 3},
          "metal": {"model": "metal"}}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("plain", help="bench/plain_fit.py --json output")
    ap.add_argument("--json", help="write aniso's fits here")
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args()
    plain = json.load(open(a.plain))
    rows, out = {}, []
    for p in plain:
        kw = dict(MODELS[p["model"]])
        t = time.process_time()
        r = aniso.fit(p["file"], progress=False, threads=a.threads, **kw)
        cpu = time.process_time() - t
        fit = r.to_dict()["fit"]
        err = fit["error"]["relative_l2cos"]
        out.append({"file": p["file"], "model": p["model"], "aniso": err, "plain": p["relative_l2cos"], "cpu_seconds": cpu,
                    "energy": fit["energy"], "best_start": fit["best_start"]})
        name = p["file"].split("/")[-1]
        rows.setdefault(name, {})[p["model"]] = out[-1]
        print(f"{name:<30} {p['model']:<18} aniso {err:.4f}  plain {p['relative_l2cos']:.4f}  ratio "
              f"{err / p['relative_l2cos']:.3f}  {cpu:.1f} s CPU", file=sys.stderr, flush=True)
    models = [m for m in MODELS if any(m in r for r in rows.values())]
    print("| file | " + " | ".join(models) + " |")
    print("|---|" + "---|" * len(models))
    for name, r in rows.items():
        cells = []
        for m in models:
            if m not in r:
                cells.append("")
                continue
            x = r[m]
            cells.append(f"{x['aniso']:.3f} / {x['plain']:.3f} ({x['aniso'] / x['plain']:.2f}x, {x['cpu_seconds']:.1f} s)")
        print(f"| {name} | " + " | ".join(cells) + " |")
    worst = max(out, key=lambda x: x["aniso"] / x["plain"])
    print(f"\nworst ratio {worst['aniso'] / worst['plain']:.3f}: {worst['file'].split('/')[-1]} {worst['model']}")
    if a.json:
        json.dump(out, open(a.json, "w"), indent=1)


if __name__ == "__main__":
    sys.exit(main())
