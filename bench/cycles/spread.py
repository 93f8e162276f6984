#!/usr/bin/env python3
"""Per-pixel noise of aniso on the Cycles side-by-side's Lambert scene, without a reference
(docs/benchmarks.md, "Cycles", the sphere-light table).

    /usr/bin/python3 bench/cycles/spread.py --aniso build/release/bin/aniso [VARIANT ...]

Renders the scene (96 x 96) with 8 seeds at 16 and 64 spp and prints, per variant, the RMS over
pixels of each pixel's standard deviation over the seeds, over the pixels wholly lit by the light
(compare.py's exact-integral mask) and over the sphere's other pixels. A variant is a list of
words separated by spaces: `noenv` (the environment removed), `nolight` (the light removed) or
any `aniso render` option written `--name=value` (e.g. `--strategy=light`, `--sampler=independent`).
Default variant: the scene as it is.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare import exact_lambert_light_term, read_pfm, sphere_mask  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--aniso", required=True)
    p.add_argument("--scene", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "sphere-lambert.json"))
    p.add_argument("--size", type=int, default=96)
    p.add_argument("--seeds", type=int, default=8)
    p.add_argument("variants", nargs="*", default=["default"])
    a = p.parse_args()
    with open(a.scene) as f:
        doc = json.load(f)
    lit = exact_lambert_light_term(doc, a.size)[1]
    rest = sphere_mask(doc, a.size) & ~lit
    with tempfile.TemporaryDirectory() as tmp:
        for v in a.variants:
            extra, d = [], json.loads(json.dumps(doc))
            for tok in v.split():
                if tok == "noenv":
                    d.pop("environment", None)
                elif tok == "nolight":
                    d.pop("lights", None)
                elif tok.startswith("--"):
                    extra += tok.split("=", 1)
                elif tok != "default":
                    raise SystemExit("unknown variant word %r (noenv, nolight, --option=value)" % tok)
            scene = os.path.join(tmp, "scene.json")
            with open(scene, "w") as f:
                json.dump(d, f)
            line = "%-36s" % v
            for spp in (16, 64):
                imgs = []
                for s in range(a.seeds):
                    out = os.path.join(tmp, "img.pfm")
                    subprocess.run([a.aniso, "render", scene, "-o", out, "--spp", str(spp), "--width", str(a.size),
                                    "--height", str(a.size), "--seed", str(100 + s), "--threads", "2"] + extra,
                                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                    imgs.append(read_pfm(out).mean(axis=2))
                sd = np.array(imgs).std(axis=0, ddof=1)
                line += " | %d spp: lit %.3g, others %.3g" % (spp, math.sqrt((sd[lit] ** 2).mean()),
                                                              math.sqrt((sd[rest] ** 2).mean()))
            print(line, flush=True)


if __name__ == "__main__":
    main()
