#!/usr/bin/env python3
# Real measurements exported to Blender and rendered in Cycles 3.4 (docs/export.md, "Real
# measurements"): three files of the RGL material database in ../shared/data/rgl-real/ (a vinyl
# film, a chrome-look film, a flake film), `aniso export --to blender --blender-version 3.4
# --preview M.pfm`, the script run on a sphere in Cycles in the preview's scene (a uniform
# environment and a sun: blender_export_render.py builds it), compared with aniso's render of the
# SOURCE file (the preview's left sphere): the relative difference of the sphere's mean luminance
# and of its lit region's (the pixels where the sun is within 60 degrees of the normal).
#
#   blender_export_real.py --aniso build/release/bin/aniso --out DIR [--data DIR] [--spp N]
#
# and the chromaticity of the sphere's mean RGB (each channel over the sum of the three: the largest
# difference over the channels, as aniso's image check reports it), which the luminance cannot see.
#
# Exit 0 within the bounds (25 % on the mean, 40 % on the lit region: issue 39's target; 0.08 in
# chromaticity: a sphere written grey for a blue source, the light blue film's single Principled BSDF
# v1, is 0.15 off), 1 when not, 77 (skipped, with the reason) without blender, numpy or the data folder.
import argparse
import json
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_export_render as ber  # noqa: E402  (exits 77 itself without numpy)

np = ber.np

# The eight files are all TeckWrap vinyl films (the folder's README); which looks like what, by what
# aniso fit measures (docs/measured.md, "Real measurements"): aurora_white a plain gloss vinyl (a white
# diffuse 0.42 under a clear gloss, F0 0.08, alpha 0.055), chm_light_blue a chrome look (a mirror-sharp
# peak, alpha 0.012, with a blue F0 of 0.32), cc_nothern_aurora a flake film (the RD series: a dark
# diffuse, a gloss of alpha 0.05 and a broader lobe that three Lafortune lobes take up).
FILES = {
    "vinyl film (aurora_white)": "aurora_white_rgb.bsdf",
    "chrome-look film (chm_light_blue)": "chm_light_blue_rgb.bsdf",
    "flake film (cc_nothern_aurora)": "cc_nothern_aurora_rgb.bsdf",
}
MAX_MEAN, MAX_LIT = 0.25, 0.40  # issue 39's target: Cycles 3.4 against aniso's render of the source
MAX_CHROMATICITY = 0.08  # the colour: see above


def masks(n):
    ys, xs = np.mgrid[0:n, 0:n]
    x = (xs + 0.5) / n * 2 - 1
    y = 1 - (ys + 0.5) / n * 2
    r2 = x * x + y * y
    disc = r2 < 0.98**2  # inside the silhouette, where both renderers cover the pixel whole
    sx, sy, sz = (np.array(ber.SUN) / np.linalg.norm(ber.SUN)).tolist()
    lit = disc & (x * sx + y * sy + np.sqrt(np.clip(1 - r2, 0, 1)) * sz >= 0.5)
    return disc, lit


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--aniso", required=True)
    ap.add_argument("--out", required=True)
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--data", default=os.path.join(here, "..", "..", "shared", "data", "rgl-real"))
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--size", type=int, default=96)
    ap.add_argument("--json", help="write the numbers here")
    a = ap.parse_args()
    blender = shutil.which("blender")
    if not blender:
        print("SKIPPED: blender is not installed (Debian 12: apt-get install blender, 3.4.1)")
        return 77
    missing = [f for f in FILES.values() if not os.path.exists(os.path.join(a.data, f))]
    if missing:
        print("SKIPPED: the RGL files %s are not in %s (../shared/data/rgl-real, see its README)" % (missing, a.data))
        return 77
    os.makedirs(a.out, exist_ok=True)
    cfg = {"materials": {}, "lights": [[d if d == "env" else list(d), e] for d, e in ber.LIGHTS], "spp": a.spp,
           "size": a.size}
    checks = {}
    for label, f in FILES.items():
        name = f[:-len("_rgb.bsdf")]
        script = os.path.join(a.out, name + ".py")
        pfm = os.path.join(a.out, name + "-aniso.pfm")
        r = subprocess.run([a.aniso, "export", "--to", "blender", "--material", os.path.join(a.data, f),
                            "--blender-version", "3.4", "--grid", "3", "-o", script, "--preview", pfm, "--preview-size",
                            str(a.size)], capture_output=True, text=True)
        if r.returncode != 0:
            print("aniso export failed:\n" + r.stdout + r.stderr)
            return 1
        checks[label] = [l.strip() for l in r.stdout.splitlines() if "image check" in l or "note: Blender 3.4: the source's F0" in l]
        cfg["materials"][name] = {"script": script, "out": os.path.join(a.out, name + "-cycles"), "aniso": pfm,
                                  "label": label}
    driver = os.path.join(a.out, "driver.py")
    with open(driver, "w") as fh:
        fh.write(ber.DRIVER)
    r = subprocess.run([blender, "-b", "--factory-startup", "-P", driver, "--", json.dumps(cfg)], capture_output=True,
                       text=True)
    if r.returncode != 0 or "Traceback" in r.stderr:
        print("blender failed:\n" + r.stdout[-3000:] + r.stderr[-3000:])
        return 1
    ok, out = True, {}
    for name, m in cfg["materials"].items():
        both = ber.read_pfm(m["aniso"])
        n = both.shape[0]
        src_rgb = both[:, :n, :]  # the left sphere: aniso's render of the source file
        cyc_rgb = sum(ber.read_pfm(m["out"] + ".light%d.pfm" % li) for li in range(len(ber.LIGHTS)))
        src, cyc = src_rgb.mean(axis=2), cyc_rgb.mean(axis=2)
        disc, lit = masks(n)
        d_mean = abs(cyc[disc].mean() / src[disc].mean() - 1)
        d_lit = abs(cyc[lit].mean() / src[lit].mean() - 1)
        rgb_src, rgb_cyc = src_rgb[disc].mean(axis=0), cyc_rgb[disc].mean(axis=0)
        d_chroma = float(np.abs(rgb_cyc / rgb_cyc.sum() - rgb_src / rgb_src.sum()).max())
        out[m["label"]] = {"mean": d_mean, "lit": d_lit, "cycles_mean": float(cyc[disc].mean()),
                           "source_mean": float(src[disc].mean()), "cycles_rgb": rgb_cyc.tolist(),
                           "source_rgb": rgb_src.tolist(), "chromaticity": d_chroma}
        print("%-40s Cycles 3.4 against aniso's render of the source: mean %.1f %%, lit region %.1f %%, colour "
              "%.3f / %.3f / %.3f (the source's %.3f / %.3f / %.3f), chromaticity %.3f" %
              ((m["label"], 100 * d_mean, 100 * d_lit) + tuple(rgb_cyc) + tuple(rgb_src) + (d_chroma,)))
        for c in checks[m["label"]]:
            print("    aniso's own check: " + c)
        if d_mean > MAX_MEAN or d_lit > MAX_LIT or d_chroma > MAX_CHROMATICITY:
            print("  FAILED: bounds %g %% on the mean, %g %% on the lit region, %g in chromaticity" %
                  (100 * MAX_MEAN, 100 * MAX_LIT, MAX_CHROMATICITY))
            ok = False
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(out, fh, indent=1)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
