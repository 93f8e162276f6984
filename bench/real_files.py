#!/usr/bin/env python3
"""What real measured files show: noise and non-reciprocity, measured with aniso's own reader (the
table of docs/measured.md, "Real measurements").

    PYTHONPATH=build/release/python /usr/bin/python3 bench/real_files.py ../shared/data/rgl-real/*.bsdf

On the samples `aniso fit FILE` fits (aniso.read_measured: the half/difference grid, within 80
degrees, Ngan 2005's range), each weighted as the fits weigh it (its solid angle w, the residual
times cos theta_i: the relative l2cos of docs/fitting.md), f read as pbrt-v4's MeasuredBxDF reads it
(aniso.Material(FILE).eval):

- mirror: an isotropic material is symmetric under the mirror y -> -y of both directions; the
  relative l2cos of f(mirror wi, mirror wo) against f(wi, wo). What it is not is noise.
- swap: the relative l2cos of f(wo, wi) against f(wi, wo) (0 for a reciprocal BRDF).
- floor: the least relative l2cos any reciprocal model can reach on these samples: at each pair
  {(wi, wo), (wo, wi)} the best single value g is the mean of the two values weighted by w cos^2
  theta_i, so floor^2 = sum w [c_a c_b^2 (f_b - f_a) / (c_a^2 + c_b^2)]^2 / sum w (c_a f_a)^2, with
  c_a = cos theta_i, c_b = cos theta_o (every fitted model in aniso is reciprocal).
- albedo: the largest directional albedo (Material.albedo, theta_o 0 to 80 degrees) and where.
- rgb < 0: the colour table's negative entries (out-of-gamut colour and noise; pbrt-v4 clamps the
  interpolated value at 0, bxdfs.cpp:1045, as aniso's reader does), counted in the file itself (a
  minimal reader of Mitsuba's tensor format below, independent of aniso's), the most negative
  relative to the table's largest; clamped: the samples where f is 0 in some channel and not in all.
- notes: what aniso's reader said (rounding noise read as 0, raised sigma), from the warnings.
"""
import argparse
import os
import struct

import numpy as np

import aniso


def relative(a, b, w, c):
    """The relative l2cos of a against b: sqrt(sum w ((a - b) c)^2) / sqrt(sum w (b c)^2)."""
    return float(np.sqrt(np.sum(w[:, None] * ((a - b) * c[:, None]) ** 2) / np.sum(w[:, None] * (b * c[:, None]) ** 2)))


def tensor_field(path, field):
    """One field of a Mitsuba tensor file ("tensor_file\\0", version, field count, then per field its
    name, ndim, dtype, offset and shape; include/mitsuba/core/tensor.h), as float64."""
    dtypes = {1: np.uint8, 2: np.int8, 3: np.uint16, 4: np.int16, 5: np.uint32, 6: np.int32, 7: np.uint64, 8: np.int64,
              9: np.float16, 10: np.float32, 11: np.float64}
    b = open(path, "rb").read()
    assert b[:12] == b"tensor_file\0", path
    o = 18
    for _ in range(struct.unpack_from("<I", b, 14)[0]):
        n = struct.unpack_from("<H", b, o)[0]
        name = b[o + 2:o + 2 + n].decode()
        o += 2 + n
        ndim, dtype, offset = struct.unpack_from("<HBQ", b, o)
        o += 11
        shape = struct.unpack_from("<%dQ" % ndim, b, o)
        o += 8 * ndim
        if name == field:
            return np.frombuffer(b, dtypes[dtype], int(np.prod(shape)), offset).astype(np.float64)
    raise KeyError(field)


def measure(path):
    d = aniso.read_measured(path)
    wi, wo, v, w = (np.asarray(d[k], dtype=np.float64) for k in ("wi", "wo", "value", "weight"))
    keep = (wi[:, 2] >= np.cos(np.radians(80))) & (wo[:, 2] >= np.cos(np.radians(80)))
    wi, wo, v, w = wi[keep], wo[keep], v[keep], w[keep]
    m = aniso.Material(path)
    f = m.eval(wi, wo)
    mirror = np.array([1.0, -1.0, 1.0])
    fm = m.eval(wi * mirror, wo * mirror)
    fs = m.eval(wo, wi)
    ca, cb = wi[:, 2], wo[:, 2]
    num = ca[:, None] * cb[:, None] ** 2 * (fs - f) / (ca[:, None] ** 2 + cb[:, None] ** 2)
    floor = float(np.sqrt(np.sum(w[:, None] * num**2) / np.sum(w[:, None] * (f * ca[:, None]) ** 2)))
    thetas = np.arange(0, 81, 10)
    albedo = np.max(m.albedo(np.radians(thetas).astype(np.float64), samples=1 << 18), axis=1)
    rgb = tensor_field(path, "rgb")
    clamped = np.any(f == 0, axis=1) & np.any(f > 0, axis=1)
    return {"file": os.path.basename(path), "rgb_negative": int(np.sum(rgb < 0)), "rgb_size": int(rgb.size),
            "rgb_most_negative": float(rgb.min() / rgb.max()), "clamped": float(np.mean(clamped)), "samples": int(len(w)), "read_vs_samples": relative(f, v, w, ca),
            "mirror": relative(fm, f, w, ca), "swap": relative(fs, f, w, ca), "floor": floor,
            "albedo_max": float(np.max(albedo)), "albedo_theta": int(thetas[int(np.argmax(albedo))]),
            "warnings": list(d.get("warnings", []))}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+")
    a = ap.parse_args()
    print("| file | rgb < 0 (most negative / largest) | clamped | mirror | swap | reciprocal floor | largest albedo "
          "(theta_o) | reader's notes |")
    print("|---|---|---|---|---|---|---|---|")
    for p in a.files:
        r = measure(p)
        assert r["read_vs_samples"] < 1e-6, r  # the samples are the reader's values
        print(f"| {r['file']} | {r['rgb_negative']} of {r['rgb_size']} ({r['rgb_most_negative']:.2g}) | "
              f"{100 * r['clamped']:.1f} % | {r['mirror']:.2g} | {r['swap']:.3f} | {r['floor']:.3f} | "
              f"{r['albedo_max']:.3f} ({r['albedo_theta']} deg) | {'; '.join(r['warnings']) or 'none'} |", flush=True)


if __name__ == "__main__":
    main()
