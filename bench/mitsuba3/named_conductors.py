#!/usr/bin/env python3
"""What Mitsuba 3 makes of its named conductors' spectra against aniso's RGB metals: the
normal-incidence reflectance F0 per channel, as ratios to aniso's (docs/export.md, "Rendered in
Mitsuba 3", explains the `export:` cases' colours with it). Not part of `make test`.

    /usr/bin/python3 bench/mitsuba3/named_conductors.py --mitsuba-data /work/mitsuba/build/data [Au=gold Cu=copper ...]

Three reductions of Mitsuba's `data/ior/<symbol>.eta.spd` / `.k.spd`:
- RGB variants: ior_from_file (include/mitsuba/render/ior.h:100-126) reduces eta and k separately to
  linear sRGB with spectrum_list_to_srgb(bounded = false, d65 = false) (src/core/spectrum.cpp:86-135:
  the CIE 1931 functions under illuminant E, divided by the integral of y-bar, times the XYZ to
  sRGB matrix; no white balance), and the BSDF evaluates the Fresnel per channel of those;
- spectral variants: the Fresnel per wavelength, lit by the D65 shape (an emitter's <rgb>,
  src/core/properties.cpp:635) and reduced with the CIE 1931 functions to sRGB, whose white is D65;
- aniso's rule (scripts/reduce_ior.py): the reflectance per wavelength under E, white-balanced.
The CIE functions are reduce_ior.py's analytic fit (Wyman, Sloan & Shirley 2013); D65 is
Mitsuba's own table (include/mitsuba/core/spectrum.h:138, 5 nm from 360 to 830 nm).
"""
import argparse
import os
import re
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import reduce_ior  # noqa: E402

XYZ_TO_SRGB = np.array([[3.2404542, -1.5371385, -0.4985314], [-0.9692660, 1.8760108, 0.0415560],
                        [0.0556434, -0.2040259, 1.0572252]])


def spd(path):
    rows = [l.split() for l in open(path) if l.strip() and not l.lstrip().startswith("#")]
    a = np.array([[float(x) for x in r[:2]] for r in rows])
    return a[:, 0], a[:, 1]


def f0(eta, k):
    return ((eta - 1) ** 2 + k**2) / ((eta + 1) ** 2 + k**2)


def aniso_f0(name):
    for line in open(os.path.join(ROOT, "src", "data", "metal_table.inc")):
        if line.startswith('{"%s",' % name):
            groups = re.findall(r"\{([^{}]*)\}", line)
            return np.array([float(x) for x in groups[2].split(",")])  # eta, k, F0, R45, R80
    raise SystemExit("no metal %r in src/data/metal_table.inc" % name)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mitsuba-data", required=True, help="Mitsuba's data folder (data/ior/*.spd)")
    ap.add_argument("--mitsuba-src", default=None, help="Mitsuba's sources, for its D65 table (default: DATA/../../src)")
    ap.add_argument("pairs", nargs="*", default=["Au=gold", "Cu=copper"])
    a = ap.parse_args()
    src = a.mitsuba_src or os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(a.mitsuba_data))), "src")
    body = open(os.path.join(src, "include", "mitsuba", "core", "spectrum.h")).read()
    body = body.split("const float d65_table[MI_CIE_SAMPLES] = {")[1].split("};")[0]
    d65 = np.array([float(x.rstrip("f")) for x in re.findall(r"[-0-9.e+]+f?", body)])
    lam = np.linspace(360.0, 830.0, len(d65))  # MI_CIE_MIN .. MI_CIE_MAX
    cmf = reduce_ior.cie1931_cmf(lam)
    fine = np.linspace(360.0, 830.0, 1000)  # spectrum_list_to_srgb's 1000 steps
    cmf_fine = reduce_ior.cie1931_cmf(fine)

    def mitsuba_rgb(w, v):
        inside = (fine >= w[0]) & (fine <= w[-1])
        return XYZ_TO_SRGB @ ((cmf_fine * np.interp(fine, w, v) * inside).sum(1) / cmf_fine[1].sum())

    def reduce(r, ill):
        return (XYZ_TO_SRGB @ (cmf * r * ill).sum(1)) / (XYZ_TO_SRGB @ (cmf * ill).sum(1))

    for pair in a.pairs:
        sym, name = pair.split("=")
        we, e = spd(os.path.join(a.mitsuba_data, "ior", sym + ".eta.spd"))
        wk, k = spd(os.path.join(a.mitsuba_data, "ior", sym + ".k.spd"))
        r = f0(np.interp(lam, we, e), np.interp(lam, wk, k))
        ref = aniso_f0(name)
        rows = [("RGB variants (eta, k reduced apart)", f0(mitsuba_rgb(we, e), mitsuba_rgb(wk, k))),
                ("spectral variants (D65)", reduce(r, d65)),
                ("aniso's rule (E, white-balanced)", reduce(r, np.ones_like(lam)))]
        print("%s (%s): aniso's F0 %s" % (sym, name, " ".join("%.4f" % x for x in ref)))
        for what, v in rows:
            print("  %-38s F0 %s  / aniso %s" % (what, " ".join("%.4f" % x for x in v),
                                                 " ".join("%.3f" % x for x in v / ref)))


if __name__ == "__main__":
    main()
