#!/usr/bin/env python3
# The Blender export checked by rendering in Blender (docs/export.md, "Rendered in Blender 3.4").
#
#   blender_export_render.py --aniso build/release/bin/aniso --out DIR [--spp N]
#
# For each material (two anisotropic GGX metals, sharp and rough, and a GGX dielectric with a
# diffuse part, all exact exports): `aniso export --to blender --blender-version 3.4 --preview
# M.pfm` writes the script and aniso's rendering of the written target model (Blender 3.4's
# Principled BSDF v1, targets.h) on the preview scene (export.h, write_preview and ImageCheck): an
# orthographic view along -z of a unit sphere whose tangent runs around the vertical axis, a
# uniform white environment and one sun, nothing else. Blender builds the same scene (the sphere a
# UV sphere, whose UV tangent the exported script connects; the sun a sun lamp of angle 0 with
# strength = the irradiance; the environment the world's background colour), runs the exported
# script on the sphere and renders it with Cycles, the sun and the environment apart (no
# light-selection noise) and without shadow rays (a convex sphere shadows nothing that n.l does
# not). The two images are compared on
# the pixels well inside the silhouette: the ratio of the lit integrals, the highlight's centroid
# and axis (the pixels above half the peak), the relative RMSE.
#
# Exit 0 when they agree within the bounds below, 1 when not, 77 (skipped, with the reason)
# without blender or without numpy.
import argparse
import json
import math
import os
import shutil
import subprocess
import sys

try:
    import numpy as np
except ImportError:
    print("SKIPPED: numpy is not installed (Debian's /usr/bin/python3 has it)")
    sys.exit(77)

# The preview's scene (include/aniso/export/export.h, ImageCheck): the sun's direction in the view
# frame (x right, y up, z towards the viewer) and irradiance at normal incidence (kCheckSunIrradiance);
# the environment's radiance (kCheckEnvironment) as ("env", L).
LIGHTS = [((-0.5, 0.6, 1.0), 2.5), ("env", 0.25)]
SUN = LIGHTS[0][0]

MATERIALS = {
    "metal": {"model": "ggx", "alpha_x": 0.25, "alpha_y": 0.06, "f0": [0.95, 0.64, 0.54], "kd": 0.0},
    "dielectric": {"model": "ggx", "alpha_x": 0.08, "alpha_y": 0.3, "f0": 0.05, "kd": [0.5, 0.25, 0.1]},
    # Rough: where 3.4's separable masking and interpolated Fresnel differ from 4.x's (the 4.x model
    # is 0.8 % off in the lit integral here, relative RMSE 0.020; the 3.4 model 0.0025).
    "rough-metal": {"model": "ggx", "alpha_x": 0.7, "alpha_y": 0.3, "f0": [0.9, 0.6, 0.3], "kd": 0.0},
}

# Bounds (measured on 2026-12-02 at 128 px and the --spp default; docs/export.md gives the values).
MAX_RATIO_DIFF = 0.02  # |lit integral ratio - 1|
MAX_CENTROID_PX = 1.0  # highlight centroid distance
MAX_AXIS_DEG = 5.0  # highlight axis angle (elongated highlights only)
MAX_REL_RMSE = 0.08  # RMSE over the mean

DRIVER = r'''
import bpy, math, sys, json
import numpy as np
from mathutils import Vector
cfg = json.loads(sys.argv[sys.argv.index("--") + 1])

def to_blender(p):  # aniso's y-up view frame -> Blender's z-up
    return Vector((p[0], -p[2], p[1]))

for name, m in cfg["materials"].items():
    for li in range(len(cfg["lights"])):
        bpy.ops.wm.read_factory_settings(use_empty=True)
        sc = bpy.context.scene
        sc.render.engine = "CYCLES"
        cy = sc.cycles
        cy.device = "CPU"
        cy.samples = cfg["spp"]
        cy.use_adaptive_sampling = False
        cy.use_denoising = False
        cy.seed = 1
        cy.pixel_filter_type = "BOX"
        cy.filter_width = 1.0
        cy.sample_clamp_direct = cy.sample_clamp_indirect = 0.0
        cy.blur_glossy = 0.0
        cy.max_bounces = 0  # direct light only, as the preview
        sc.render.resolution_x = sc.render.resolution_y = cfg["size"]
        sc.render.resolution_percentage = 100
        sc.view_settings.view_transform = "Standard"
        world = bpy.data.worlds.new("world")
        sc.world = world
        world.use_nodes = True
        d, e = cfg["lights"][li]
        env = e if d == "env" else 0.0
        world.node_tree.nodes["Background"].inputs["Color"].default_value = (env, env, env, 1)
        cd = bpy.data.cameras.new("camera")
        cd.type = "ORTHO"
        cd.ortho_scale = 2.0
        co = bpy.data.objects.new("camera", cd)
        sc.collection.objects.link(co)
        co.location = to_blender((0, 0, 5))
        co.rotation_euler = (-to_blender((0, 0, 1))).to_track_quat("-Z", "Y").to_euler()
        sc.camera = co
        if d != "env":
            ld = bpy.data.lights.new("sun", type="SUN")
            ld.energy = e  # W/m^2: the irradiance at normal incidence
            ld.angle = 0.0
            ld.cycles.cast_shadow = False
            lo = bpy.data.objects.new("sun", ld)
            lo.rotation_euler = to_blender(Vector(d).normalized()).to_track_quat("Z", "Y").to_euler()
            sc.collection.objects.link(lo)
        else:
            cy.samples = cfg["spp"] * cfg.get("env_spp_factor", 4)  # the environment is sampled, the sun is not
        bpy.ops.mesh.primitive_uv_sphere_add(segments=256, ring_count=128, radius=1.0)
        bpy.ops.object.shade_smooth()
        exec(open(m["script"]).read(), {"__name__": "exported"})
        mat = bpy.context.view_layer.objects.active.data.materials[0]
        p = [n for n in mat.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled"][0]
        print("ANISO_NODE", name, p.distribution, [l.from_node.bl_idname for l in p.inputs["Tangent"].links])
        sc.render.image_settings.file_format = "OPEN_EXR"
        sc.render.image_settings.color_depth = "32"
        exr = m["out"] + ".light%d.exr" % li
        sc.render.filepath = exr
        bpy.ops.render.render(write_still=True)
        img = bpy.data.images.load(exr)
        w, h = img.size
        px = np.array(img.pixels[:], dtype=np.float32).reshape(h, w, 4)[:, :, :3]
        with open(exr[:-4] + ".pfm", "wb") as o:  # rows bottom to top, as the format wants
            o.write(b"PF\n%d %d\n-1.0\n" % (w, h))
            o.write(np.ascontiguousarray(px, dtype="<f4").tobytes())
'''


def read_pfm(path):
    with open(path, "rb") as f:
        if f.readline().strip() != b"PF":
            raise ValueError(path + ": not a colour PFM")
        w, h = (int(x) for x in f.readline().split())
        scale = float(f.readline())
        a = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4").reshape(h, w, 3)
    return a[::-1].astype(np.float64)  # rows top to bottom


def highlight(img, mask):
    lum = img.mean(axis=2) * mask
    w = np.where(lum >= 0.5 * lum.max(), lum, 0.0)
    ys, xs = np.mgrid[0 : img.shape[0], 0 : img.shape[1]]
    s = w.sum()
    cx, cy = (w * xs).sum() / s, (w * ys).sum() / s
    cxx = (w * (xs - cx) ** 2).sum() / s
    cyy = (w * (ys - cy) ** 2).sum() / s
    cxy = (w * (xs - cx) * (ys - cy)).sum() / s
    axis = 0.5 * math.degrees(math.atan2(2 * cxy, cxx - cyy))
    ev = np.linalg.eigvalsh(np.array([[cxx, cxy], [cxy, cyy]]))
    return cx, cy, axis, math.sqrt(ev[1] / max(ev[0], 1e-12))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--aniso", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--spp", type=int, default=8)
    ap.add_argument("--size", type=int, default=128)
    a = ap.parse_args()
    blender = shutil.which("blender")
    if not blender:
        print("SKIPPED: blender is not installed (Debian 12: apt-get install blender, 3.4.1)")
        return 77
    os.makedirs(a.out, exist_ok=True)
    cfg = {"materials": {}, "lights": [[d if d == "env" else list(d), e] for d, e in LIGHTS], "spp": a.spp, "size": a.size}
    for name, m in MATERIALS.items():
        script = os.path.join(a.out, name + ".py")
        pfm = os.path.join(a.out, name + "-aniso.pfm")
        r = subprocess.run([a.aniso, "export", "--to", "blender", "--material", json.dumps(m), "--blender-version",
                            "3.4", "--grid", "2", "-o", script, "--preview", pfm, "--preview-size", str(a.size)],
                           capture_output=True, text=True)
        if r.returncode != 0:
            print("aniso export failed:\n" + r.stdout + r.stderr)
            return 1
        cfg["materials"][name] = {"script": script, "out": os.path.join(a.out, name + "-cycles"), "aniso": pfm}
    driver = os.path.join(a.out, "driver.py")
    with open(driver, "w") as f:
        f.write(DRIVER)
    r = subprocess.run([blender, "-b", "--factory-startup", "-P", driver, "--", json.dumps(cfg)], capture_output=True,
                       text=True)
    for line in r.stdout.splitlines():
        if line.startswith("ANISO_NODE"):
            print(line)
    if r.returncode != 0 or "Traceback" in r.stderr:
        print("blender failed:\n" + r.stdout[-3000:] + r.stderr[-3000:])
        return 1
    ok = True
    for name, m in cfg["materials"].items():
        both = read_pfm(m["aniso"])
        n = both.shape[0]
        ref = both[:, n:, :]  # the right sphere: the written target model
        cyc = sum(read_pfm(m["out"] + ".light%d.pfm" % li) for li in range(len(LIGHTS)))
        ys, xs = np.mgrid[0:n, 0:n]
        x = (xs + 0.5) / n * 2 - 1
        y = 1 - (ys + 0.5) / n * 2
        mask = (x * x + y * y < 0.95**2).astype(np.float64)
        ratio = (cyc * mask[..., None]).sum() / (ref * mask[..., None]).sum()
        rmse = math.sqrt((((cyc - ref) ** 2) * mask[..., None]).sum() / (3 * mask.sum()))
        rel = rmse / ((ref * mask[..., None]).sum() / (3 * mask.sum()))
        hc, ha = highlight(cyc, mask), highlight(ref, mask)
        dc = math.hypot(hc[0] - ha[0], hc[1] - ha[1])
        dax = abs((hc[2] - ha[2] + 90) % 180 - 90)
        elongated = ha[3] > 1.5
        print("%-11s lit integral ratio %.4f, highlight centroid %.2f px apart, axis %.1f deg apart (elongation "
              "%.2f vs %.2f), relative RMSE %.4f" % (name, ratio, dc, dax, hc[3], ha[3], rel))
        good = abs(ratio - 1) <= MAX_RATIO_DIFF and dc <= MAX_CENTROID_PX and rel <= MAX_REL_RMSE
        good = good and (not elongated or dax <= MAX_AXIS_DEG)
        if not good:
            print("  FAILED: bounds ratio 1 +- %g, centroid %g px, axis %g deg, relative RMSE %g" %
                  (MAX_RATIO_DIFF, MAX_CENTROID_PX, MAX_AXIS_DEG, MAX_REL_RMSE))
            ok = False
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
