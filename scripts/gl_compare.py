#!/usr/bin/env python3
"""CPU against GL: renders a scene with the path tracer (--max-depth 1) and with --backend gl, and
writes one PNG of both side by side with 10 x |GL - CPU| as a third panel (docs/scenes.md, "GL
backend"). Linear radiance is read from PFM, tone-mapped with a clamp and the sRGB curve.

    scripts/gl_compare.py build/release/bin/aniso examples/gl-direct.json out.png [--width W --height H --spp N]
"""
import argparse
import os
import struct
import subprocess
import tempfile
import zlib

import numpy as np


def read_pfm(path):
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4").reshape(h, w, 3)
    return data[::-1].astype(np.float64)  # PFM rows run bottom to top


def srgb(x):
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def write_png(path, rgb8):
    h, w, _ = rgb8.shape
    raw = b"".join(b"\0" + rgb8[y].tobytes() for y in range(h))
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("aniso")
    ap.add_argument("scene")
    ap.add_argument("out")
    ap.add_argument("--width", default="320")
    ap.add_argument("--height", default="180")
    ap.add_argument("--spp", default="256", help="CPU samples per pixel")
    ap.add_argument("--gl-spp", default="64", help="GL sub-samples per pixel (a square: 64 = 8 x 8)")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        cpu, gl = os.path.join(d, "cpu.pfm"), os.path.join(d, "gl.pfm")
        size = ["--width", a.width, "--height", a.height]
        subprocess.run([a.aniso, "render", a.scene, "-o", cpu, "--max-depth", "1", "--spp", a.spp] + size, check=True)
        subprocess.run([a.aniso, "render", a.scene, "-o", gl, "--backend", "gl", "--spp", a.gl_spp] + size, check=True)
        c, g = read_pfm(cpu), read_pfm(gl)
    gap = np.ones((c.shape[0], 4, 3))
    panel = np.concatenate([srgb(c), gap, srgb(g), gap, srgb(10.0 * np.abs(g - c))], axis=1)
    write_png(a.out, np.round(255.0 * panel).astype(np.uint8))
    print(f"{a.out}: CPU | GL | 10 x |GL - CPU|; largest |GL - CPU| {np.abs(g - c).max():.4g}, peak {c.max():.4g}")


if __name__ == "__main__":
    main()
