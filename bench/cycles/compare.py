#!/usr/bin/env python3
"""aniso against Blender's Cycles on the scenes of bench/cycles/ (docs/benchmarks.md, "Cycles").

    /usr/bin/python3 bench/cycles/compare.py --aniso build/release/bin/aniso [--quick] [--out DIR]

Two parts:
1. Agreement (the environment off, the sphere light alone; Cycles' light as a mesh, whose
   radiance is exactly the scene's): the Lambert sphere's light term against the exact integral
   (a sphere light of radiance L and radius R at distance d, wholly above the horizon, gives the
   irradiance pi L (R / d)^2 cos(theta): the reflected radiance is kd L (R / d)^2 cos(theta)),
   and the GGX highlight's centroid, principal axis and elongation (its luminance's first and
   second moments) in both images.
2. Equal quality (the whole scenes; without --quick): each renderer's RMSE against a high-spp
   reference of its own, at two sample counts, and its CPU time per sample per pixel (user + sys
   of the process, the difference of two runs, so that start-up and scene building cancel); the
   CPU time each needs for the RMSE Cycles reaches at its higher count, from a log-log fit of
   RMSE against spp. CPU time, not wall: the machine may be loaded.

--quick (the ctest entry, tests/CMakeLists.txt): part 1 at low resolution, with bounds; exit 1 if
they fail, 77 (ctest's skip) with the reason when blender is not installed.
"""
import argparse
import json
import math
import os
import resource
import shutil
import subprocess
import sys

try:
    import numpy as np
except ImportError:
    print("SKIP: numpy is not installed for %s (Debian's python3-numpy)" % sys.executable)
    sys.exit(77)

HERE = os.path.dirname(os.path.abspath(__file__))


def read_pfm(path):
    with open(path, "rb") as f:
        if f.readline().strip() != b"PF":
            raise SystemExit("%s: not a colour PFM" % path)
        w, h = (int(x) for x in f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    # PFM rows run bottom to top: flipped so that row 0 is the image's top, as aniso's pixel (0, 0).
    return data.reshape(h, w, 3)[::-1].astype(np.float64)


def cpu_of(cmd):
    """Runs cmd; returns the CPU seconds (user + sys) of it and its children."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        raise SystemExit("failed (%d): %s\n%s" % (r.returncode, " ".join(cmd), r.stdout[-3000:]))
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


class Renderers:
    def __init__(self, a):
        self.a = a

    def aniso(self, scene, out, spp, size, seed):
        cmd = [self.a.aniso, "render", scene, "-o", out, "--spp", str(spp), "--width", str(size), "--height", str(size),
               "--seed", str(seed), "--threads", str(self.a.threads)]
        return cpu_of(cmd)

    def cycles(self, scene, out, spp, size, seed, light):
        cmd = [self.a.blender, "-b", "--factory-startup", "-noaudio", "-P", os.path.join(HERE, "cycles_scene.py"), "--",
               scene, out, "--spp", str(spp), "--width", str(size), "--height", str(size), "--seed", str(seed),
               "--threads", str(self.a.threads), "--light", light]
        return cpu_of(cmd)


def camera_rays(doc, size):
    """Unit directions through each pixel's centre (rows top to bottom), as aniso's pinhole camera."""
    cam = doc["camera"]
    pos = np.array(cam["position"], float)
    fwd = np.array(cam["look_at"], float) - pos
    fwd /= np.linalg.norm(fwd)
    right = np.cross(fwd, np.array(cam.get("up", [0, 1, 0]), float))
    right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    t = math.tan(math.radians(cam.get("fov_deg", 40)) / 2)
    c = (np.arange(size) + 0.5) / size * 2 - 1
    x, y = np.meshgrid(c * t, -c * t)
    d = fwd + x[..., None] * right + y[..., None] * up
    return pos, d / np.linalg.norm(d, axis=-1, keepdims=True)


def exact_lambert_light_term(doc, size):
    """The exact light term per pixel centre and the mask of pixels where it is exact over the pixel."""
    pos, d = camera_rays(doc, size)
    obj = doc["objects"][0]
    c, r = np.array(obj["center"], float), float(obj["radius"])
    light = doc["lights"][0]
    lc, lr, L = np.array(light["center"], float), float(light["radius"]), float(light["radiance"])
    kd = float(obj["material"]["kd"])
    oc = pos - c
    b = np.einsum("ijk,k->ij", d, oc)
    disc = b * b - (oc @ oc - r * r)
    hit = disc > 0
    t = -b - np.sqrt(np.maximum(disc, 0))
    p = pos + t[..., None] * d
    n = (p - c) / r
    to_l = lc - p
    dist = np.linalg.norm(to_l, axis=-1)
    cos_t = np.einsum("ijk,ijk->ij", n, to_l) / dist
    sin_a = lr / dist
    value = kd * L * sin_a**2 * cos_t
    # Exact where the light is wholly above the horizon (cos > sin alpha, with a margin), and the
    # pixel wholly on the sphere (its neighbours hit too): away from the silhouette and terminator.
    ok = hit & (cos_t > sin_a + 0.05)
    ok[1:-1, 1:-1] &= ok[:-2, 1:-1] & ok[2:, 1:-1] & ok[1:-1, :-2] & ok[1:-1, 2:]
    ok[0, :] = ok[-1, :] = ok[:, 0] = ok[:, -1] = False
    return value, ok


def sphere_mask(doc, size):
    """The pixels whose centre sees the (first) sphere."""
    pos, d = camera_rays(doc, size)
    obj = doc["objects"][0]
    oc = pos - np.array(obj["center"], float)
    b = np.einsum("ijk,k->ij", d, oc)
    return b * b - (oc @ oc - float(obj["radius"]) ** 2) > 0


def highlight_moments(img):
    """Centroid (x, y in pixels), major-axis angle (degrees from +x, image y down) and elongation
    (ratio of the principal standard deviations) of the luminance above 5% of its peak."""
    y = img.mean(axis=2)
    w = np.where(y > 0.05 * y.max(), y, 0.0)
    ys, xs = np.mgrid[0 : y.shape[0], 0 : y.shape[1]] + 0.5
    s = w.sum()
    cx, cy = (w * xs).sum() / s, (w * ys).sum() / s
    cov = np.array([[(w * (xs - cx) ** 2).sum(), (w * (xs - cx) * (ys - cy)).sum()],
                    [(w * (xs - cx) * (ys - cy)).sum(), (w * (ys - cy) ** 2).sum()]]) / s
    ev, vec = np.linalg.eigh(cov)
    angle = math.degrees(math.atan2(vec[1, 1], vec[0, 1])) % 180.0
    return cx, cy, angle, math.sqrt(ev[1] / ev[0])


def scene_variant(name, out_dir, environment):
    with open(os.path.join(HERE, name)) as f:
        doc = json.load(f)
    if not environment:
        doc.pop("environment", None)
    path = os.path.join(out_dir, name.replace(".json", "" if environment else "-light.json").replace(".json", "") + ".json")
    with open(path, "w") as f:
        json.dump(doc, f)
    return path, doc


def agreement(r, a):
    size, spp = (48, 256) if a.quick else (128, 1024)
    print("## Agreement: the sphere light alone, %d x %d, %d spp (Cycles: the light as a mesh)" % (size, size, spp))
    failures = []
    path, doc = scene_variant("sphere-lambert.json", a.out, environment=False)
    exact, ok = exact_lambert_light_term(doc, size)
    imgs = {}
    for who in ("aniso", "cycles"):
        out = os.path.join(a.out, "lambert-light-%s.pfm" % who)
        if who == "aniso":
            r.aniso(path, out, spp, size, 1)
        else:
            r.cycles(path, out, spp, size, 1, "mesh")
        imgs[who] = read_pfm(out)
        ratio = imgs[who].mean(axis=2)[ok].sum() / exact[ok].sum()
        print("Lambert light term / exact integral, %s: %.4f (%d pixels)" % (who, ratio, ok.sum()))
        if abs(ratio - 1) > (0.02 if a.quick else 0.01):
            failures.append("%s Lambert light term %.4f of the exact integral" % (who, ratio))
    path, doc = scene_variant("sphere-ggx.json", a.out, environment=False)
    m = {}
    for who in ("aniso", "cycles"):
        out = os.path.join(a.out, "ggx-light-%s.pfm" % who)
        if who == "aniso":
            r.aniso(path, out, spp, size, 1)
        else:
            r.cycles(path, out, spp, size, 1, "mesh")
        m[who] = highlight_moments(read_pfm(out))
        print("GGX highlight, %s: centroid (%.2f, %.2f) px, axis %.1f deg, elongation %.3f" % ((who,) + m[who]))
    dc = math.hypot(m["aniso"][0] - m["cycles"][0], m["aniso"][1] - m["cycles"][1])
    da = abs((m["aniso"][2] - m["cycles"][2] + 90) % 180 - 90)
    de = m["aniso"][3] / m["cycles"][3]
    print("difference: centroid %.2f px, axis %.1f deg, elongation ratio %.3f" % (dc, da, de))
    if dc > 0.02 * size or da > 5 or abs(de - 1) > 0.1:
        failures.append("GGX highlight differs: centroid %.2f px, axis %.1f deg, elongation ratio %.3f" % (dc, da, de))
    return failures


def equal_quality(r, a):
    size, ref_spp, test_spp = 96, 1024, (16, 64)
    print("\n## Equal quality: %d x %d, %d threads; RMSE against each renderer's own %d-spp reference (other seed)" %
          (size, size, a.threads, ref_spp))
    print("| scene | Cycles' light | Cycles: RMSE at %d spp, CPU s | aniso: spp for that RMSE, CPU s | Cycles / aniso |" % test_spp[1])
    print("|---|---|---|---|---|")
    for name in ("sphere-lambert.json", "sphere-ggx.json"):
        path, doc = scene_variant(name, a.out, environment=True)
        # Lambert: the pixels wholly lit by the light (the exact-integral mask of the agreement part).
        lit = exact_lambert_light_term(doc, size)[1] if "lambert" in name else None
        rest = sphere_mask(doc, size) & ~lit if lit is not None else None
        res = {}
        for who in ("aniso", "point", "mesh"):
            def run(spp, seed):
                out = os.path.join(a.out, "%s-%s-%d.pfm" % (name[:-5], who, spp))
                if who == "aniso":
                    cpu = r.aniso(path, out, spp, size, seed)
                else:
                    cpu = r.cycles(path, out, spp, size, seed, who)
                return cpu, read_pfm(out)
            cpu_ref, ref = run(ref_spp, 7)
            cpus, errs = [], []
            for n in test_spp:
                c, img = run(n, 1)
                cpus.append(c)
                errs.append(math.sqrt(((img - ref) ** 2).mean()))
            # CPU per sample per pixel: the difference of two runs (start-up and scene building cancel).
            per_spp = (cpu_ref - cpus[0]) / (ref_spp - test_spp[0])
            slope = math.log(errs[1] / errs[0]) / math.log(test_spp[1] / test_spp[0])
            res[who] = (per_spp, errs, slope)
            print("  %s %s: %.3g CPU s per spp; RMSE %.4g at %d spp, %.4g at %d (log-log slope %.2f)" %
                  (name[7:-5], who, per_spp, errs[0], test_spp[0], errs[1], test_spp[1], slope), flush=True)
            if lit is not None:
                d2 = ((img - ref) ** 2).mean(axis=2)  # img: the last test count's image
                print("    at %d spp: RMSE %.3g over the %d pixels wholly lit by the light, %.3g over the sphere's %d others" %
                      (test_spp[-1], math.sqrt(d2[lit].mean()), lit.sum(), math.sqrt(d2[rest].mean()), rest.sum()), flush=True)
        pa, ea, sa = res["aniso"]
        for who in ("point", "mesh"):
            target = res[who][1][1]
            spp_a = test_spp[1] * (target / ea[1]) ** (1 / sa)
            cpu_c, cpu_a = res[who][0] * test_spp[1], pa * spp_a
            print("| %s | %s | %.4g, %.3g | %.1f, %.3g | %.1fx |" % (name[7:-5], who, target, cpu_c, spp_a, cpu_a, cpu_c / cpu_a))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--aniso", required=True, help="the aniso executable")
    p.add_argument("--blender", default="blender")
    p.add_argument("--out", default="cycles-compare", help="folder for the scenes and images")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--quick", action="store_true", help="the agreement at low resolution, with bounds (ctest)")
    a = p.parse_args()
    if shutil.which(a.blender) is None:
        print("SKIP: %s is not installed: Cycles cannot be run (scripts/install-deps.sh installs it)" % a.blender)
        return 77
    os.makedirs(a.out, exist_ok=True)
    r = Renderers(a)
    failures = agreement(r, a)
    if not a.quick:
        equal_quality(r, a)
    for f in failures:
        print("FAIL: " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
