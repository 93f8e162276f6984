#!/usr/bin/env python3
"""Writes the hand-made part of the seed corpus, fuzz/corpus/<target>/ (docs/testing.md).

Run from the repository root: python3 fuzz/make_seeds.py. Standard library only. Files are named
<what>.<ext>; the reproducers of defects found by review are named defect-*. Files that fuzzing found (named
crash-*, regression-*) are added by hand and never rewritten here. The image and tangent-map seeds
start with the target's selector byte (fuzz_image.cpp, fuzz_tangent_map.cpp).
Not written here: image/render-16x16.exr is byte 2 followed by the output of
`aniso render --material gold --width 16 --height 16 --spp 1 -o x.exr` (OpenEXR, ZIP); nor
rgl/iso-rgb.bsdf and rgl/aniso-spectral.bsdf, written by `aniso export-rgl` (--material gold --rgb,
and an anisotropic GGX; --resolution 4 --theta-i 2 --phi-i 3 --ndf 8), and rgl/truncated.bsdf,
header-only.bsdf, huge-field-count.bsdf and bad-magic.bsdf cut from iso-rgb.bsdf by hand."""
import os
import struct
import zlib

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")


def put(target, name, data):
    d = os.path.join(ROOT, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


# --- material ---------------------------------------------------------------------------------
materials = {
    "lambert": '{"model": "lambert", "kd": [0.2, 0.5, 0.8]}',
    "phong": '{"model": "phong", "kd": 0.1, "ks": 0.5, "exponent": 80, "normalized": true}',
    "ward": '{"model": "ward", "kd": 0.05, "ks": [0.6, 0.5, 0.4], "alpha_x": 0.05, "alpha_y": 0.3, "normalization": "balanced"}',
    "ward-angle": '{"model": "ward", "alpha": 0.2, "form": "angle", "normalization": "ward"}',
    "ashikhmin-shirley": '{"model": "ashikhmin-shirley", "rd": 0.1, "rs": 0.2, "n_u": 10, "n_v": 1000}',
    "ashikhmin-shirley-n": '{"model": "ashikhmin-shirley", "n": 40}',
    "lafortune": '{"model": "lafortune", "rho_d": 0.1, "lobes": [{"cx": -1, "cy": -1, "cz": 1, "n": 12, "scale": 1}, {"cxy": -0.5, "cz": 0.9, "n": 4}]}',
    "ggx": '{"model": "ggx", "alpha_x": 0.1, "alpha_y": 0.4, "f0": [0.9, 0.7, 0.3]}',
    "metal-ggx": '{"model": "metal", "metal": "gold", "lobe": {"model": "ggx", "alpha": 0.1}}',
    "metal-ward-dd": '{"model": "metal", "metal": "iron", "lobe": {"model": "ward", "alpha_x": 0.03, "alpha_y": 0.3, "normalization": "balanced"}, "directional_diffuse": {"cx": -1, "cy": -1, "cz": 1, "n": 5}}',
    "metal-as": '{"model": "metal", "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.2], "lobe": {"model": "ashikhmin-shirley", "n_u": 10, "n_v": 300}}',
    "empty": "{}",
    "not-object": "[1, 2, 3]",
    # Issue 13, high: the kernel computed max|C|^n before the scale (inf / NaN).
    "defect-lafortune-scale-1e-300": '{"model": "lafortune", "lobes": [{"cz": 100, "n": 160, "scale": 1e-300}]}',
    "defect-lafortune-scale-0": '{"model": "lafortune", "lobes": [{"cz": 100, "n": 160, "scale": 0}]}',
    "defect-lafortune-float-n37": '{"model": "lafortune", "lobes": [{"cz": 100, "n": 37, "scale": 1e-300}]}',
    # Issue 13, low.
    "defect-eta1-k0": '{"model": "metal", "eta": 1, "k": 0, "lobe": {"model": "ggx", "alpha": 0.3}}',
    "defect-duplicate-kd-2-first": '{"model": "lambert", "kd": 2, "kd": 0.5}',
    "defect-duplicate-kd-2-last": '{"model": "lambert", "kd": 0.5, "kd": 2}',
    "defect-duplicate-model": '{"model": "ward", "model": "lambert"}',
    "defect-tiny-1e-400": '{"model": "lambert", "kd": 1e-400}',
    "defect-minus-zero": '{"model": "lambert", "kd": -0.0}',
    "defect-key-nul": '{"model": "lambert", "k\\u0000d": 0.5}',
    "defect-key-control": '{"model": "lambert", "\\u001b[31mkd": 0.5}',
    "defect-number-overflow": '{"model": "lambert", "kd": 1e999}',
    # Issue 11: half of an anisotropic pair.
    "defect-half-pair": '{"model": "ashikhmin-shirley", "rd": 0.1, "rs": 0.2, "n_u": 10}',
    "defect-duplicate-alpha": '{"alpha_x": 0.1, "alpha_x": 0.5}',
}
for name, text in materials.items():
    put("material", name + ".json", text)
# Issue 13, high: 200,000 levels of nesting crashed with SIGSEGV (400 KB).
put("material", "defect-deep-nesting.json", '{"model": "lambert", "zz": ' + "[" * 200000 + "]" * 200000 + "}")

# --- eval_line: first byte even = vector lines, odd = --angles lines ----------------------------
vec = {
    "basic": "0 0 1 0 0 1\n0.3 0.1 0.9 -0.2 0.4 0.8\n0 0 -1 0 0 1\n# comment\n\n",
    "defect-grazing-1e-170": "1 0 1e-170 -1 0 1e-170\n",
    "defect-mirror-1e-120": "1 0 1e-120 -1 0 1e-120\n1 0 1e-100 -1 0 1e-100\n",
    "defect-float-1e-15": "1 0 1e-15 1 0 1e-15\n1 0 1e-12 1 0 1e-12\n",
    "defect-subnormal-1e-310": "1 0 1e-310 -1 0 1e-310\n1e-310 0 1 0 0 1\n",
    "defect-huge-1e200": "1e200 1e200 1e200 0 0 1\n",
    "defect-form-feed": "\f\n\v\n \t\r\n0 0 1 0 0 1\n",
    "defect-octal": "010 0 1 0 0 1\n",
    "defect-nan-inf": "nan 0 1 0 0 1\ninf 0 1 0 0 1\n0x1p3 0 1 0 0 1\n",
    "zero-vector": "0 0 0 0 0 1\n",
    "too-many": "0 0 1 0 0 1 7\n",
    "too-few": "0 0 1 0 0\n",
    "minus-zero": "-0 -0 1 -0 0 1\n",
    "integers": "18446744073709551616\n-1\n1.5\n010\n",
    "nul-byte": "0 0 1 \0\n0 0 1\n0 0 1 0 0 1\n",
    "opposite-grazing": "0.9519527964440391 -0.30624479316777603 2.6982672065979276e-10 -0.9519527964455237 0.3062447931631613 2.7586451918744186e-11\n",
}
for name, text in vec.items():
    put("eval_line", name + ".txt", "0" + text)
ang = {
    "angles-basic": "30 0 30 180\n0 0 0 0\n",
    "angles-horizon": "90 0 90 180\n89.9999999 0 89.9999999 180\n",
    "angles-out-of-range": "91 0 30 0\n-1 0 30 0\n",
    "angles-huge-phi": "30 1e300 30 -1e300\n",
}
for name, text in ang.items():
    put("eval_line", name + ".txt", "1" + text)

# --- scene: relative names resolve in the fuzz target's scratch directory (fuzz_scene.cpp) ------
cam = '"camera": {"position": [0, 2, 3], "look_at": [0, 0, 0], "fov_deg": 40}'
scenes = {
    "spheres": '{%s, "lights": [{"type": "point", "position": [1, 3, 2], "intensity": 10}], "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "brushed-gold", "tangent": {"field": "noise", "scale": 3, "strength": 0.6}}]}' % cam,
    "sky-disc": '{%s, "environment": {"type": "sky", "zenith": 0.15, "horizon": 0.3, "ground": 0.04, "resolution": 16}, "lights": [{"type": "sphere", "center": [0, 3, -2.5], "radius": 0.7, "radiance": 60}], "objects": [{"shape": "disc", "center": [0, 0, 0], "normal": [0, 1, 0], "radius": 1.5, "material": "gold", "tangent": {"field": "concentric"}}]}' % cam,
    "rectangle-map": '{%s, "environment": {"type": "uniform", "radiance": 0.2}, "lights": [{"type": "directional", "to_light": [0.3, 1, 0.2], "irradiance": 3}], "objects": [{"shape": "rectangle", "center": [0, 0, 0], "normal": [0, 1, 0], "u": [1, 0, 0], "size": [2, 2], "material": {"model": "ward", "alpha_x": 0.05, "alpha_y": 0.3}, "tangent": {"map": "map.pfm", "encoding": "xy"}}]}' % cam,
    "mesh-uv": '{%s, "environment": {"type": "map", "file": "env.hdr", "scale": 1, "rotation_deg": 90}, "objects": [{"shape": "mesh", "file": "mesh.obj", "scale": 1, "rotate_deg": [0, 45, 0], "material": "matte-steel", "tangent": {"field": "uv"}}]}' % cam,
    "torus-pfm-env": '{%s, "film": {"width": 32, "height": 16, "spp": 2}, "integrator": {"max_depth": 4, "strategy": "bsdf"}, "environment": {"type": "map", "file": "env.pfm"}, "objects": [{"shape": "torus", "center": [0, 0, 0], "major_radius": 1, "minor_radius": 0.3, "material": "brushed-silver", "tangent": {"field": "swirl", "swirl_deg": 30}}]}' % cam,
    "bad-key": '{%s, "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "clay", "colour": 1}]}' % cam,
    "missing-file": '{%s, "objects": [{"shape": "mesh", "file": "nope.obj", "material": "clay"}]}' % cam,
    "directory-as-file": '{%s, "objects": [{"shape": "mesh", "file": ".", "material": "clay"}]}' % cam,
    "rectangle-1e39": '{%s, "objects": [{"shape": "rectangle", "center": [0, 0, 0], "normal": [0, 1, 0], "u": [1, 0, 0], "size": [1e39, 1], "material": "clay"}]}' % cam,
    "name-number": '{%s, "name": 5, "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "clay"}]}' % cam,
    "bounds-exact": '{%s, "name": "exact bounds", "environment": {"type": "sky", "sun_radius_deg": 0.05, "resolution": 16}, "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1e15, "material": "clay"}]}' % cam,
}
for name, text in scenes.items():
    put("scene", name + ".json", text)


# --- images: selector byte = extension index (0 png, 1 hdr, 2 exr, 3 pfm, 4 jpg) | 0x80 linear ---
def png(w, h, rows, color_type=2, bit_depth=8):
    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)
    raw = b"".join(b"\x00" + r for r in rows)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, bit_depth, color_type, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


rgb_png = png(2, 2, [bytes([255, 0, 0, 0, 255, 0]), bytes([0, 0, 255, 128, 128, 128])])
grey_png = png(2, 1, [bytes([0, 200])], color_type=0)
rgba16_png = png(1, 1, [struct.pack(">HHHH", 65535, 32768, 0, 65535)], color_type=6, bit_depth=16)
hdr = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n\x80\x80\x80\x81\x80\x40\x20\x82"
pfm = b"PF\n2 1\n-1.0\n" + struct.pack("<6f", 0.5, 0.5, 0.5, 1.0, 0.0, 0.25)
pfm_grey = b"Pf\n1 2\n-1.0\n" + struct.pack("<2f", 0.25, 4.0)
pfm_big_endian = b"PF\n1 1\n1.0\n" + struct.pack(">3f", 1.0, 2.0, 3.0)
pfm_nan = b"PF\n1 1\n-1.0\n" + struct.pack("<3f", float("nan"), 0, 0)
pfm_huge_header = b"PF\n100000 100000\n-1.0\n" + struct.pack("<3f", 1, 1, 1)
for name, sel, data in [("rgb.png", 0, rgb_png), ("grey.png", 0, grey_png), ("rgba16.png", 0, rgba16_png),
                        ("rgb-linear.png", 0x80, rgb_png), ("two.hdr", 1, hdr), ("rgb.pfm", 3, pfm),
                        ("grey.pfm", 3, pfm_grey), ("big-endian.pfm", 3, pfm_big_endian), ("nan.pfm", 3, pfm_nan),
                        ("huge-header.pfm", 3, pfm_huge_header), ("png-as-jpg.jpg", 4, rgb_png),
                        ("truncated.png", 0, rgb_png[:40])]:
    put("image", name, bytes([sel]) + data)


# Radiance RLE scanlines (rows of 8 to 32767 pixels): 2, 2, the row length (big endian), then each
# of R, G, B, E as runs (count > 128: the next byte count - 128 times) and literals (count <= 128).
def rle_component(values):
    out, i = bytearray(), 0
    while i < len(values):
        j = i
        while j < len(values) and j - i < 127 and values[j] == values[i]:
            j += 1
        if j - i >= 3:
            out += bytes([128 + j - i, values[i]])
            i = j
            continue
        j = i + 1
        while j < len(values) and j - i < 128 and not (j + 2 < len(values) and values[j] == values[j + 1] == values[j + 2]):
            j += 1
        out += bytes([j - i]) + bytes(values[i:j])
        i = j
    return bytes(out)


def rle_hdr(w, h):
    data = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w)
    for y in range(h):
        px = [((x * 7 + y) % 256, 128 if x < w // 2 else (x * 3) % 256, 200, 128 + (x + y) % 4) for x in range(w)]
        data += b"\x02\x02" + struct.pack(">H", w) + b"".join(rle_component([p[k] for p in px]) for k in range(4))
    return data


rle = rle_hdr(64, 4)
flat = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 40 +X 4\n" + bytes([128, 64, 32, 129]) * 160
for name, data in [("rle-64x4.hdr", rle), ("rle-512x2.hdr", rle_hdr(512, 2)), ("rle-truncated.hdr", rle[:len(rle) - 40]),
                   ("rle-truncated-49-bytes.hdr", b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 8\n\x02\x02\x00\x08"),
                   ("rle-run-past-end.hdr", rle[:rle.index(b"\x02\x02\x00\x40") + 4] + b"\xff\x01" + rle[-20:]),
                   ("flat-truncated.hdr", flat[:len(flat) // 10])]:
    put("image", name, b"\x01" + data)

# --- tangent maps: selector bit 0 = PFM (else PNG), bit 1 = "xy" encoding (else "angle") --------
angle_png = png(2, 2, [bytes([0, 0, 0, 128, 128, 128]), bytes([64, 64, 64, 255, 255, 255])])
xy_png = png(2, 1, [bytes([255, 128, 0, 128, 255, 0])])
xy_zero_png = png(1, 1, [bytes([128, 128, 0])])
xy_pfm = b"PF\n2 1\n-1.0\n" + struct.pack("<6f", 1.0, 0.5, 0.0, 0.5, 1.0, 0.0)
opposite_pfm = b"PF\n2 1\n-1.0\n" + struct.pack("<6f", 1.0, 0.5, 0.0, 0.0, 0.5, 0.0)
for name, sel, data in [("angle.png", 0, angle_png), ("xy.png", 2, xy_png), ("xy-zero.png", 2, xy_zero_png),
                        ("xy.pfm", 3, xy_pfm), ("opposite.pfm", 3, opposite_pfm), ("angle.pfm", 1, pfm)]:
    put("tangent_map", name, bytes([sel]) + data)
with open(os.path.join(os.path.dirname(ROOT), "..", "examples", "assets", "checker_tangents.png"), "rb") as f:
    put("tangent_map", "checker-tangents.png", b"\x00" + f.read())

# --- obj: selector bit 0 = UV tangents ------------------------------------------------------------
quad = "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 1 0\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n"
objs = {
    "quad-uv": ("\x01", quad),
    "quad": ("\x00", quad),
    "positions-only": ("\x00", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    "quad-polygon": ("\x01", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n"),
    "negative-index": ("\x00", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n"),
    "bad-index": ("\x00", "v 0 0 0\nf 1 2 3\n"),
    "degenerate-uv": ("\x01", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 0 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n"),
    "zero-normal": ("\x00", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 0\nf 1//1 2//1 3//1\n"),
    "nan-vertex": ("\x00", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    "no-faces": ("\x00", "v 0 0 0\n"),
    "not-a-number": ("\x00", "v hello -1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    "inf-vertex": ("\x00", "v inf -1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    "short-vertex": ("\x00", "v -1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    "nan-normal": ("\x00", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn nan 0 1\nf 1//1 2//1 3//1\n"),
    "colors-and-w": ("\x00", "v 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0 # c\nvt 0.5\nf 1 2 3\n"),
}
for name, (sel, text) in objs.items():
    put("obj", name + ".obj", sel + text)

# --- samples: selector bit 0 = Cornell (else CSV) ------------------------------------------------
csv_files = {
    "radians.csv": "theta_i,phi_i,theta_o,phi_o,r,g,b\n0.5,0,0.5,3.14159,0.2,0.3,0.4\n0.1,1,1.2,-2,0,0,0.01\n",
    "degrees-any-order-weight.csv": "r,g,b,theta_o_deg,phi_o_deg,theta_i_deg,phi_i_deg,weight\n0.1,0.1,0.1,30,180,30,0,2\n",
    "extra-column.csv": "theta_i,phi_i,theta_o,phi_o,r,g,b,note\n0.5,0,0.5,3.1,0.2,0.3,0.4,x\n",
    "comments-blank.csv": "# measured\ntheta_i,phi_i,theta_o,phi_o,r,g,b\n\n0.5,0,0.5,3.1,0.2,0.3,0.4\n",
    "missing-column.csv": "theta_i,phi_i,theta_o,r,g,b\n0.5,0,0.5,0.2,0.3,0.4\n",
    "duplicate-column.csv": "theta_i,theta_i,phi_i,theta_o,phi_o,r,g,b\n0.5,0.5,0,0.5,3.1,0.2,0.3,0.4\n",
    "nan.csv": "theta_i,phi_i,theta_o,phi_o,r,g,b\nnan,0,0.5,3.1,0.2,0.3,0.4\n",
    "negative.csv": "theta_i,phi_i,theta_o,phi_o,r,g,b\n0.5,0,0.5,3.1,-0.2,0.3,0.4\n",
    "horizon.csv": "theta_i_deg,phi_i,theta_o,phi_o,r,g,b\n90,0,0.5,3.1,0.2,0.3,0.4\n",
    "short-row.csv": "theta_i,phi_i,theta_o,phi_o,r,g,b\n0.5,0,0.5,3.1,0.2\n",
    "huge-value.csv": "theta_i,phi_i,theta_o,phi_o,r,g,b\n0.5,0,0.5,3.1,1e300,0.3,0.4\n",
    "empty.csv": "",
}
for name, text in csv_files.items():
    put("samples", name, "\x00" + text)
wls = " ".join(str(400 + 10 * i) for i in range(31))
row = "0.872665 0.000000 0.573513 0.000000 " + " ".join("0.00%d" % (1 + i % 9) for i in range(31))
cornell_files = {
    "valid.brdf": "# Cornell-style file\n# num wls\n31\n\n# wls\n" + wls + "\n\n" + row + "\n" + row.replace("0.573513", "1.2") + "\n",
    "wavelength-count.brdf": "3\n400 500 600\n0.5 0 0.5 0 0.1 0.2\n",
    "truncated-row.brdf": "31\n" + wls + "\n0.5 0 0.5 0 0.1 0.2\n",
    "no-rows.brdf": "31\n" + wls + "\n",
    "descending-wls.brdf": "3\n600 500 400\n0.5 0 0.5 0 0.1 0.2 0.3\n",
    "nan.brdf": "31\n" + wls + "\n" + row.replace("0.872665", "nan") + "\n",
    "huge-value.brdf": "31\n" + wls + "\n" + row.replace(" 0.001 ", " 1e300 ", 1) + "\n",
}
for name, text in cornell_files.items():
    put("samples", name, "\x01" + text)

# --- merl: a valid file is 35 MB, so the seeds are headers and short or wrong-sized bodies --------
merl_header = struct.pack("<3i", 90, 90, 180)
put("merl", "header-only.binary", merl_header)
put("merl", "header-and-some-values.binary", merl_header + struct.pack("<4d", 0.5, 0.25, -1.0, 1e300))
put("merl", "wrong-dims.binary", struct.pack("<3i", 90, 90, 360) + struct.pack("<2d", 0.1, 0.2))
put("merl", "negative-dims.binary", struct.pack("<3i", -90, 90, 180))
put("merl", "huge-dims.binary", struct.pack("<3i", 2**31 - 1, 2**31 - 1, 2**31 - 1))
put("merl", "short-header.binary", b"\x5a\x00\x00\x00\x5a\x00")
put("merl", "empty.binary", b"")
