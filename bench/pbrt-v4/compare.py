#!/usr/bin/env python3
"""aniso's RGL tensor files (.bsdf) rendered by pbrt-v4 itself (docs/rgl.md, "In pbrt-v4").

    /usr/bin/python3 bench/pbrt-v4/compare.py --aniso build/release/bin/aniso --pbrt PATH/TO/pbrt
        [--out DIR] [--spp N] [--size N] [--cases a,b,...]

pbrt-v4 is not a Debian package: build it from its sources (docs/rgl.md says how it was done here)
and pass its `pbrt` executable. For each case the material is written with `aniso export-rgl`
(spectral: the only kind pbrt-v4 reads), and the same scene (bench/cycles/sphere-lambert.json's
unit sphere, camera, uniform environment and sphere light) is rendered three ways: pbrt-v4 with
`Material "measured"` on the file, aniso with the file as a material (its pbrt-v4-faithful reader,
`RglT`) and aniso with the source material. The first pair says whether pbrt-v4 reads and renders
the file as aniso does (format, frame, spectral colour); the second what the file itself costs in
accuracy (docs/rgl.md, "Accuracy"). The `lambert` case renders pbrt-v4's own `diffuse` material
against aniso's Lambert: it checks the scene conversion alone (camera, lights, film). The
`export:` cases render what `aniso export --to pbrt-v4` writes (pbrt-v4's own `conductor`, `mix`
and `diffuse`; docs/export.md) against aniso's render of the source: there "file" is the source.

The scene conversion, each line from pbrt-v4's sources (github.com/mmp/pbrt-v4 @ 5f7a6068):
- Axes: pbrt-v4's camera space is left-handed (cameras.h, CameraTransform; the pbrt-v4 file
  format's documented convention); `Scale -1 1 1` before `LookAt` mirrors it so that aniso's
  right-handed y-up world renders unmirrored (the check: the `lambert` case, lit from the left).
- `Camera "perspective" "float fov"`: the angle of the shorter image axis (cameras.cpp:364-383,
  the screen window spans [-1, 1] on the shorter axis): the images here are square, so aniso's
  vertical `fov_deg`.
- `PixelFilter "box"` with radius 0.5: each pixel's square, aniso's pixel average (filters.h,
  BoxFilter).
- `Film "rgb"`, `.pfm` (util/image.cpp:1008-1009, rows written bottom to top, 1789), sensor
  "cie1931" with ISO 100 and exposure 1: imaging ratio 1 (film.cpp, PixelSensor::Create), linear
  sRGB.
- Lights given as `"rgb L"`: an RGBIlluminantSpectrum scaled by 1 / SpectrumToPhotometric of the
  colour space's illuminant (lights.cpp:266 for area lights' `L`, 1556 for a uniform infinite
  light), so that an RGB radiance renders as that RGB: the uniform environment as `LightSource
  "infinite"`, the sphere light as `AreaLightSource "diffuse"` on a `Shape "sphere"` (black
  `diffuse` material), sampled in solid angle (shapes.h, Sphere::Sample(ctx, u)).
- The sphere: pbrt-v4's `Sphere` has its pole along object z and dp/du = (-phi_max y, phi_max x, 0)
  (shapes.h, Sphere::InteractionFromIntersection): z x p. `Rotate -90 1 0 0` takes object z to
  world y, so dp/du = y x n, aniso's sphere tangent (docs/scenes.md, "Objects"). MeasuredBxDF's
  frame is Frame::FromXZ(dp/du, n) (bsdf.h, BSDF::BSDF), x along dp/du, as aniso's.
- `Sampler "independent"`: pbrt-v4's default samplers are as unbiased; this one reads none of the
  tables a source build may lack (see docs/rgl.md).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

try:
    import numpy as np
except ImportError:
    print("SKIP: numpy is not installed for %s (Debian's python3-numpy)" % sys.executable)
    sys.exit(77)

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "bench", "cycles"))
from compare import read_pfm  # noqa: E402  (bench/cycles/compare.py: rows top to bottom, as aniso's)

# name -> (aniso material, what it shows)
CASES = {
    "lambert": ({"model": "lambert", "kd": 0.5}, "the scene conversion (pbrt-v4's own diffuse)"),
    "ggx-aniso": ({"model": "ggx", "f0": 1, "alpha_x": 0.05, "alpha_y": 0.3},
                  "anisotropic GGX, exact D (full phi_i grid)"),
    "ggx-rotated": ({"model": "ggx", "f0": [0.9, 0.6, 0.3], "kd": [0.1, 0.2, 0.3], "alpha_x": 0.08, "alpha_y": 0.3,
                     "rotation_deg": 30}, "coloured anisotropic GGX with diffuse, tangent rotated 30 degrees"),
    "gold": ("gold", "metal with measured n, k spectra (isotropic GGX 0.1)"),
    "brushed-gold": ("brushed-gold", "anisotropic Ward metal + directional diffuse (D by power iteration)"),
    "ward-iso": ({"model": "ward", "kd": 0.1, "ks": 0.3, "alpha": 0.15}, "isotropic Ward (power iteration)"),
    # `aniso export --to pbrt-v4` (docs/export.md): pbrt-v4's own materials, against aniso's source.
    "export:gold": ("gold", "export: conductor, pbrt-v4's named Au spectra (exact path)"),
    "export:ggx-aniso-metal": ({"model": "metal", "metal": "copper", "lobe": {"model": "ggx", "alpha_x": 0.08, "alpha_y": 0.3}},
                               "export: conductor, copper's eta / k, anisotropic (exact path)"),
    "export:ggx-diffuse": ({"model": "ggx", "kd": [0.2, 0.1, 0.05], "f0": 0.04, "alpha_x": 0.08, "alpha_y": 0.3},
                           "export: mix of diffuse and conductor (exact path)"),
    "export:brushed-gold": ("brushed-gold", "export: fitted conductor (Ward lobe + directional diffuse source)"),
}


def run(cmd, log):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    with open(log, "a") as f:
        f.write("$ " + " ".join(cmd) + "\n" + r.stdout + "\n")
    if r.returncode != 0:
        raise SystemExit("failed (%d): %s\n%s" % (r.returncode, " ".join(cmd), r.stdout[-2000:]))
    return r.stdout


def pbrt_scene(scene, size, spp, material_lines, out_pfm, world_lines=()):
    cam = scene["camera"]
    env = scene["environment"]
    if env.get("type") != "uniform":
        raise SystemExit("only a uniform environment is converted")
    lines = [
        "# written by bench/pbrt-v4/compare.py from an aniso scene (its docstring has each convention)",
        "Scale -1 1 1",
        "LookAt %g %g %g  %g %g %g  %g %g %g" % tuple(cam["position"] + cam["look_at"] + cam.get("up", [0, 1, 0])),
        'Camera "perspective" "float fov" [ %g ]' % cam["fov_deg"],
        'Sampler "independent" "integer pixelsamples" [ %d ]' % spp,
        'Integrator "path" "integer maxdepth" [ %d ]' % scene.get("integrator", {}).get("max_depth", 8),
        'PixelFilter "box" "float xradius" [ 0.5 ] "float yradius" [ 0.5 ]',
        'Film "rgb" "integer xresolution" [ %d ] "integer yresolution" [ %d ] "string filename" [ "%s" ]'
        % (size, size, out_pfm),
        "WorldBegin",
        'LightSource "infinite" "rgb L" [ %g %g %g ]' % ((env["radiance"],) * 3),
    ] + list(world_lines)
    for l in scene["lights"]:
        if l["type"] != "sphere":
            raise SystemExit("only sphere lights are converted")
        lines += ["AttributeBegin", "  Translate %g %g %g" % tuple(l["center"]),
                  '  AreaLightSource "diffuse" "rgb L" [ %g %g %g ]' % ((l["radiance"],) * 3),
                  '  Material "diffuse" "rgb reflectance" [ 0 0 0 ]',
                  '  Shape "sphere" "float radius" [ %g ]' % l["radius"], "AttributeEnd"]
    for o in scene["objects"]:
        if o["shape"] != "sphere":
            raise SystemExit("only spheres are converted")
        lines += ["AttributeBegin", "  Translate %g %g %g" % tuple(o["center"]), "  Rotate -90 1 0 0"]
        lines += ["  " + m for m in material_lines]
        lines += ['  Shape "sphere" "float radius" [ %g ]' % o["radius"], "AttributeEnd"]
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--aniso", required=True)
    ap.add_argument("--pbrt", required=True)
    ap.add_argument("--out", default=None, help="keep the files here (default: a temporary directory)")
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--pbrt-spp", type=int, default=None, help="pbrt-v4's samples per pixel (default: --spp)")
    ap.add_argument("--size", type=int, default=96)
    ap.add_argument("--cases", default=",".join(CASES))
    a = ap.parse_args()
    out = a.out or tempfile.mkdtemp(prefix="aniso-pbrt-")
    os.makedirs(out, exist_ok=True)
    log = os.path.join(out, "log.txt")
    with open(os.path.join(ROOT, "bench", "cycles", "sphere-lambert.json")) as f:
        base = json.load(f)
    # Relative to the mean of aniso's image of the file, over the sphere's pixels: the RMS difference
    # pbrt-v4 - aniso, pbrt-v4's and aniso's own per-pixel noise, and the part of the difference
    # beyond both noises (sqrt(d^2 - n_pbrt^2 - n_aniso^2)).
    print("%-13s %9s %9s %9s %9s %9s %9s %9s %9s   %s" % ("case", "mean pbrt", "mean file", "mean src", "pbrt/file",
                                                         "RMS diff", "pbrt nse", "aniso nse", "system.", "what"))
    rows = []
    for name in a.cases.split(","):
        material, what = CASES[name]
        scene = json.loads(json.dumps(base))
        scene["film"] = {"width": a.size, "height": a.size, "spp": a.spp}
        mat_json = os.path.join(out, name.replace(":", "-") + ".json")
        with open(mat_json, "w") as f:
            json.dump(material, f)
        src = material if isinstance(material, str) else mat_json
        pbrt_world = []
        if name == "lambert":
            pbrt_material = ['Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]']
            file_material = material
        elif name.startswith("export:"):
            exported = os.path.join(out, name.replace(":", "-") + ".pbrt")
            run([a.aniso, "export", "--to", "pbrt-v4", "--material", src, "-o", exported], log)
            with open(exported) as f:
                pbrt_world = f.read().splitlines()
            named = [l.split('"')[1] for l in pbrt_world if l.startswith("MakeNamedMaterial")]
            pbrt_material = ['NamedMaterial "%s"' % named[-1]]  # the last one: a mix names its parts first
            file_material = material
        else:
            bsdf = os.path.join(out, name + ".bsdf")  # rgl cases: names without ':'

            run([a.aniso, "export-rgl", "--material", src, "-o", bsdf, "--spectral"], log)
            pbrt_material = ['Material "measured" "string filename" [ "%s" ]' % bsdf]
            file_material = {"model": "rgl", "file": bsdf}
        images = {}
        for kind, mat, seed in (("file", file_material, 7), ("file2", file_material, 8), ("src", material, 7)):
            scene["objects"][0]["material"] = mat
            sj = os.path.join(out, "%s-aniso-%s.json" % (name.replace(":", "-"), kind))
            with open(sj, "w") as f:
                json.dump(scene, f)
            pfm = os.path.join(out, "%s-aniso-%s.pfm" % (name.replace(":", "-"), kind))
            run([a.aniso, "render", sj, "-o", pfm, "--seed", str(seed)], log)
            images[kind] = read_pfm(pfm)
        for kind, seed in (("pbrt", 7), ("pbrt2", 8)):
            pfm = os.path.join(out, "%s-%s.pfm" % (name.replace(":", "-"), kind))
            pscene = os.path.join(out, "%s-%s.pbrt" % (name.replace(":", "-"), kind))
            with open(pscene, "w") as f:
                f.write(pbrt_scene(scene, a.size, a.pbrt_spp or a.spp, pbrt_material, pfm, pbrt_world))
            run([a.pbrt, "--seed", str(seed), pscene], log)
            images[kind] = read_pfm(pfm)
        rows.append((name, images))
        print_row(name, what, images, "pbrt", base["environment"]["radiance"])
    picture(rows, os.path.join(out, "pbrt-v4-vs-aniso.png"))
    print("files in %s" % out)


def print_row(name, what, images, key, env_radiance):
    """One case's line: the means over the sphere's pixels (renderer `key`, aniso on the file, aniso on
    the source), their ratio, the RMS difference, both renderers' noise and the systematic remainder,
    relative to the mean of aniso's image of the file; then the ratio per channel. images holds
    key, key + "2" (a second seed), "file", "file2" (a second seed) and "src"."""
    # The sphere's pixels only (the environment around it is the same constant in both).
    mask = images["src"].sum(axis=2) != 3 * env_radiance
    p, p2, fl, fl2, s = (images[k][mask] for k in (key, key + "2", "file", "file2", "src"))
    mean = np.mean(fl)

    def rms(x):
        return float(np.sqrt(np.mean(x**2)))

    # Each renderer's own noise (one image): two seeds differ by sqrt(2) of it. What the
    # renderer / aniso difference has beyond both noises is the systematic part.
    noise_p, noise_a = rms(p2 - p) / np.sqrt(2), rms(fl2 - fl) / np.sqrt(2)
    d = rms(p - fl)
    systematic = np.sqrt(max(0.0, d**2 - noise_p**2 - noise_a**2))
    print("%-13s %9.5f %9.5f %9.5f %9.4f %9.4f %9.4f %9.4f %9.4f   %s" % (
        name, p.mean(), fl.mean(), s.mean(), p.mean() / mean, d / mean, noise_p / mean, noise_a / mean,
        systematic / mean, what))
    print("%-13s per channel %s / file: %s" % ("", key, " ".join("%.4f" % x for x in p.mean(axis=0) / fl.mean(axis=0))))
    sys.stdout.flush()


def picture(rows, path, key="pbrt", label="pbrt-v4"):
    """One row per case: the renderer (images[key], labelled label) on the file, aniso on the file,
    aniso on the source material, and 4 |renderer - aniso file| (exposure 1, clamp, sRGB). Where
    every case's file is its source (the `export:` and `lambert` cases render the source material
    itself: images["file"] is images["src"]), the two aniso columns would be the same picture and
    one is shown."""
    from PIL import Image, ImageDraw

    same = all(name.startswith("export:") or name.startswith("lambert") for name, _ in rows)
    labels = (label, "aniso: source", "4 |diff|") if same else (label, "aniso: file", "aniso: source", "4 |diff|")
    tiles = []
    for name, im in rows:
        row = [im[key], im["file"]] + ([] if same else [im["src"]]) + [4 * np.abs(im[key] - im["file"])]
        tiles.append(np.concatenate(row, axis=1))
    img = np.concatenate(tiles, axis=0)
    img = np.clip(img, 0, 1)
    img = np.where(img <= 0.0031308, 12.92 * img, 1.055 * img ** (1 / 2.4) - 0.055)
    pil = Image.fromarray((img * 255 + 0.5).astype(np.uint8))
    d = ImageDraw.Draw(pil)
    size = rows[0][1][key].shape[0]
    for r, (name, _) in enumerate(rows):
        for c, text in enumerate(labels):
            d.text((c * size + 3, r * size + 2), text, fill=(255, 255, 0))
        d.text((3, (r + 1) * size - 12), name, fill=(255, 255, 0))
    pil.save(path)


if __name__ == "__main__":
    main()
