#!/usr/bin/env python3
"""aniso's RGL tensor files and `aniso export --to mitsuba3` materials rendered by Mitsuba 3 itself
(docs/rgl.md, "In Mitsuba 3"; docs/export.md, "Rendered in Mitsuba 3").

    /usr/bin/python3 bench/mitsuba3/compare.py --aniso build/release/bin/aniso --mitsuba PATH/TO/mitsuba
        [--out DIR] [--spp N] [--mitsuba-spp N] [--size N] [--cases rgl,exports | a@rgb,b@spectral,...]

Not part of `make test`: Mitsuba 3 cannot be installed on CI (no Debian package; built from its
sources as docs/rgl.md says) and its renders take minutes. The same as bench/pbrt-v4/compare.py
(whose cases, row statistics and picture it imports), for Mitsuba 3: each case is rendered in the
scene of bench/cycles/sphere-lambert.json (a unit sphere, a uniform environment, a sphere light)
by Mitsuba 3 twice (two seeds: its noise), by aniso on the file twice and by aniso on the source.
A case name is MATERIAL@VARIANT: `@spectral` renders with `scalar_spectral` (RGL cases: the
spectral file, `aniso export-rgl`), `@rgb` with `scalar_rgb` (RGL cases: the `--rgb` file); the
`lambert` cases render Mitsuba's own `diffuse` against aniso's Lambert (the scene conversion
alone); `export:` cases render what `aniso export --to mitsuba3` writes (`<include>`d, `<ref>`ed)
against aniso's render of the source, as the pbrt-v4 script does.

The scene conversion, each line from Mitsuba 3's sources (github.com/mitsuba-renderer/mitsuba3
@ v3.8.0, 2ba36148; bench/mitsuba3/build-mitsuba.sh builds it):
- Camera: `perspective` with `to_world` = `<lookat origin target up>`; Transform::look_at
  (include/mitsuba/core/transform.h:177-200) makes the camera frame (left, up, dir), and
  perspective_projection (include/mitsuba/render/sensor.h:234-268) maps camera +x ("left") to
  the image's left edge (its scale by -0.5): a right-handed world renders unmirrored, as aniso's
  (the check: the `lambert` cases, lit from the left). `fov` is the full angle along `fov_axis`
  (parse_fov, src/render/sensor.cpp:142-158, default "x"): written with `fov_axis` "y", aniso's
  vertical `fov_deg` (the images here are square, where the two agree).
- `independent` sampler (src/samplers/independent.cpp:17-23: `sample_count`, `seed`), `path`
  integrator whose `max_depth` counts the camera vertex (src/integrators/path.cpp:19-24: "1 will
  only render directly visible light sources, 2 ... direct-only"): aniso's max_depth + 1 (aniso's
  counts surface vertices, 1 = direct lighting only, docs/scenes.md).
- `hdrfilm` with `pixel_format` rgb, `component_format` float32, `file_format` pfm (rows written
  bottom to top, Bitmap::write_pfm, src/core/bitmap.cpp:2276-2306) and `<rfilter type="box"/>`
  (radius 0.5, src/rfilters/box.cpp:37: each pixel's square, aniso's pixel average). Under
  scalar_spectral the film receives linear sRGB from spectrum_to_srgb (the CIE 1931 functions,
  include/mitsuba/core/spectrum.h:384; src/render/integrator.cpp:500).
- Lights: `constant` (the uniform environment) and an `area` emitter on a `sphere` (black
  `diffuse`), both with `<rgb name="radiance">`: an emitter's RGB becomes a `d65` texture under
  scalar_spectral (Properties::get_texture_impl, src/core/properties.cpp:635, 720), D65's shape
  times the RGB's rgb2spec spectrum, normalised so that an RGB radiance renders as that RGB
  (src/spectra/d65.cpp:80-122); under scalar_rgb the RGB itself (`srgb`). A reflectance's RGB
  (the `diffuse` of the lambert cases) is rgb2spec-upsampled (`srgb`, src/spectra/srgb.cpp) under
  scalar_spectral. The sphere light is sampled in solid angle (its cone, src/shapes/sphere.cpp:
  245-290).
- The sphere: Mitsuba's `sphere` has its pole along object z, uv = (phi / 2pi, theta / pi) and
  dp/du = 2pi (-y, x, 0) = 2pi z x p in object space (src/shapes/sphere.cpp:694-718), pbrt-v4's.
  `<rotate x="1" angle="-90"/>` (transforms compose in the order written, each left-multiplied,
  src/core/parser.cpp:470-508; Transform::rotate is the right-hand rotation,
  include/mitsuba/core/transform.h:144-149) takes object z to world y, so dp/du = y x n, aniso's
  sphere tangent (docs/scenes.md, "Objects"). The shading frame's s is dp/du made orthogonal to n
  and t = n x s (SurfaceInteraction::initialize_sh_frame, include/mitsuba/render/interaction.h:
  278-287): aniso's (tangent, n x tangent, n), in which `measured`, `roughconductor` and
  `principled` evaluate (alpha_u along s).
- `measured` reads the file named by `<string name="filename">` (src/bsdfs/measured.cpp:86); a
  file with `wavelengths` needs a spectral variant, one without an RGB variant
  (measured.cpp:102-117).
"""
import argparse
import importlib.util
import json
import os
import sys
import tempfile

if importlib.util.find_spec("numpy") is None:  # the imported script's statistics need it
    print("SKIP: numpy is not installed for %s (Debian's python3-numpy)" % sys.executable)
    sys.exit(77)

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
_spec = importlib.util.spec_from_file_location("pbrt_v4_compare", os.path.join(ROOT, "bench", "pbrt-v4", "compare.py"))
pbrt = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(pbrt)  # its CASES, run, print_row, picture; and bench/cycles' read_pfm
read_pfm = pbrt.read_pfm

# Materials beyond bench/pbrt-v4/compare.py's CASES (same form: name -> (aniso material, what)).
MATERIALS = dict(pbrt.CASES)
MATERIALS["lambert"] = (MATERIALS["lambert"][0], "the scene conversion (Mitsuba's own diffuse)")
# The pbrt-v4 exports' descriptions, for what Mitsuba 3 is given.
MATERIALS["export:gold"] = (MATERIALS["export:gold"][0], "export: roughconductor, Mitsuba's named Au (exact path)")
MATERIALS["export:ggx-aniso-metal"] = (MATERIALS["export:ggx-aniso-metal"][0],
                                       "export: roughconductor, Mitsuba's named Cu, anisotropic (exact path)")
MATERIALS["export:brushed-gold"] = (MATERIALS["export:brushed-gold"][0],
                                    "export: fitted roughconductor, Mitsuba's named Au (Ward lobe + directional diffuse source)")
MATERIALS.update({
    "export:nickel-aniso": ({"model": "metal", "metal": "nickel", "lobe": {"model": "ggx", "alpha_x": 0.08, "alpha_y": 0.3}},
                            "export: roughconductor, rgb eta / k (nickel is no named Mitsuba conductor; exact path)"),
    "export:ggx-diffuse-u": ({"model": "ggx", "kd": [0.2, 0.1, 0.05], "f0": 0.04, "alpha_x": 0.3, "alpha_y": 0.08},
                             "export: principled for a GGX with diffuse (larger alpha along dp/du: no turn)"),
    "export:as-diffuse": ({"model": "ashikhmin-shirley", "rd": 0.3, "rs": 0.05, "n_u": 100, "n_v": 10},
                          "export: blendbsdf of diffuse and roughconductor (fitted)"),
    "export:principled-al": ("principled/brushed-aluminium", "export: principled, aniso's principled (metallic 1: exact)"),
    "export:principled-plastic": ("principled/red-plastic", "export: principled, dielectric (exact dielectric Fresnel)"),
})
# The exported principled of a GGX whose larger alpha is across dp/du needs the uv turned by 90
# degrees (the export says so), which a sphere's parameterisation cannot do: ggx-diffuse-u instead.
MATERIALS.pop("export:ggx-diffuse")

RGL = ["lambert", "ggx-aniso", "ggx-rotated", "gold", "brushed-gold", "ward-iso"]
EXPORTS = ["export:gold", "export:ggx-aniso-metal", "export:nickel-aniso", "export:ggx-diffuse-u", "export:as-diffuse",
           "export:principled-al", "export:principled-plastic", "export:brushed-gold"]
# The two runs of the docs (`--cases rgl`, `--cases exports`): docs/rgl.md "In Mitsuba 3" and
# docs/export.md "Rendered in Mitsuba 3".
GROUPS = {
    "rgl": [m + "@spectral" for m in RGL] + [m + "@rgb" for m in RGL],
    "exports": ["lambert@rgb", "export:gold@rgb", "export:gold@spectral", "export:ggx-aniso-metal@rgb",
                "export:ggx-aniso-metal@spectral", "export:nickel-aniso@rgb", "export:nickel-aniso@spectral"] +
               [m + "@rgb" for m in EXPORTS[3:]],
}


def mitsuba_scene(scene, size, spp, seed, material_xml, includes=()):
    cam = scene["camera"]
    env = scene["environment"]
    if env.get("type") != "uniform":
        raise SystemExit("only a uniform environment is converted")

    def v(x):
        return ", ".join("%g" % c for c in x)

    lines = ['<?xml version="1.0" encoding="utf-8"?>',
             "<!-- written by bench/mitsuba3/compare.py from an aniso scene (its docstring has each convention) -->",
             '<scene version="3.0.0">']
    lines += ['    <include filename="%s"/>' % i for i in includes]
    lines += [
        '    <integrator type="path"><integer name="max_depth" value="%d"/></integrator>'
        % (scene.get("integrator", {}).get("max_depth", 8) + 1),
        '    <sensor type="perspective">',
        '        <float name="fov" value="%g"/>' % cam["fov_deg"],
        '        <string name="fov_axis" value="y"/>',
        '        <transform name="to_world"><lookat origin="%s" target="%s" up="%s"/></transform>'
        % (v(cam["position"]), v(cam["look_at"]), v(cam.get("up", [0, 1, 0]))),
        '        <sampler type="independent"><integer name="sample_count" value="%d"/>'
        '<integer name="seed" value="%d"/></sampler>' % (spp, seed),
        '        <film type="hdrfilm">',
        '            <integer name="width" value="%d"/><integer name="height" value="%d"/>' % (size, size),
        '            <string name="file_format" value="pfm"/><string name="pixel_format" value="rgb"/>',
        '            <string name="component_format" value="float32"/>',
        '            <rfilter type="box"/>',
        "        </film>",
        "    </sensor>",
        '    <emitter type="constant"><rgb name="radiance" value="%g"/></emitter>' % env["radiance"],
    ]
    for l in scene["lights"]:
        if l["type"] != "sphere":
            raise SystemExit("only sphere lights are converted")
        lines += ['    <shape type="sphere">',
                  '        <point name="center" value="%s"/><float name="radius" value="%g"/>' % (v(l["center"]), l["radius"]),
                  '        <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>',
                  '        <emitter type="area"><rgb name="radiance" value="%g"/></emitter>' % l["radiance"],
                  "    </shape>"]
    for o in scene["objects"]:
        if o["shape"] != "sphere":
            raise SystemExit("only spheres are converted")
        lines += ['    <shape type="sphere">',
                  '        <transform name="to_world"><scale value="%g"/><rotate x="1" angle="-90"/>'
                  '<translate value="%s"/></transform>' % (o["radius"], v(o["center"])),
                  "        " + material_xml,
                  "    </shape>"]
    return "\n".join(lines + ["</scene>"]) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--aniso", required=True)
    ap.add_argument("--mitsuba", required=True, help="Mitsuba 3's `mitsuba` executable (scalar_rgb and scalar_spectral)")
    ap.add_argument("--out", default=None, help="keep the files here (default: a temporary directory)")
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--mitsuba-spp", type=int, default=None, help="Mitsuba 3's samples per pixel (default: --spp)")
    ap.add_argument("--size", type=int, default=96)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--cases", default="rgl,exports", help="MATERIAL@VARIANT or a group (rgl, exports), comma-separated")
    ap.add_argument("--picture", default="mitsuba3-vs-aniso.png", help="file name of the picture in --out")
    a = ap.parse_args()
    out = a.out or tempfile.mkdtemp(prefix="aniso-mitsuba-")
    os.makedirs(out, exist_ok=True)
    log = os.path.join(out, "log.txt")
    with open(os.path.join(ROOT, "bench", "cycles", "sphere-lambert.json")) as f:
        base = json.load(f)
    print("%-13s %9s %9s %9s %9s %9s %9s %9s %9s   %s" % ("case", "mean mi", "mean file", "mean src", "mi/file",
                                                         "RMS diff", "mi nse", "aniso nse", "system.", "what"))
    rows = []
    cases = [c for g in a.cases.split(",") for c in GROUPS.get(g, [g])]
    for case in cases:
        name, _, kind = case.partition("@")
        if kind not in ("spectral", "rgb") or name not in MATERIALS:
            raise SystemExit("unknown case %r: MATERIAL@spectral or MATERIAL@rgb, MATERIAL one of %s"
                             % (case, ", ".join(MATERIALS)))
        variant = "scalar_" + kind
        material, what = MATERIALS[name]
        stem = case.replace(":", "-").replace("@", "-")
        scene = json.loads(json.dumps(base))
        scene["film"] = {"width": a.size, "height": a.size, "spp": a.spp}
        mat_json = os.path.join(out, stem + ".json")
        with open(mat_json, "w") as f:
            json.dump(material, f)
        src = material if isinstance(material, str) else mat_json
        includes = []
        if name == "lambert":
            mi_material = '<bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>'
            file_material = material
        elif name.startswith("export:"):
            exported = os.path.join(out, stem + ".xml")
            pbrt.run([a.aniso, "export", "--to", "mitsuba3", "--material", src, "-o", exported], log)
            with open(exported) as f:
                ids = [l.split('id="')[1].split('"')[0] for l in f if "<bsdf " in l and 'id="' in l]
            includes = [exported]
            mi_material = '<ref id="%s"/>' % ids[0]  # the outermost bsdf: a blendbsdf nests its parts unnamed
            file_material = material
        else:
            bsdf = os.path.join(out, stem + ".bsdf")
            pbrt.run([a.aniso, "export-rgl", "--material", src, "-o", bsdf] + (["--spectral"] if kind == "spectral" else ["--rgb"]),
                     log)
            mi_material = '<bsdf type="measured"><string name="filename" value="%s"/></bsdf>' % bsdf
            file_material = {"model": "rgl", "file": bsdf}
        images = {}
        for k, mat, seed in (("file", file_material, 7), ("file2", file_material, 8), ("src", material, 7)):
            scene["objects"][0]["material"] = mat
            sj = os.path.join(out, "%s-aniso-%s.json" % (stem, k))
            with open(sj, "w") as f:
                json.dump(scene, f)
            pfm = os.path.join(out, "%s-aniso-%s.pfm" % (stem, k))
            pbrt.run([a.aniso, "render", sj, "-o", pfm, "--seed", str(seed), "--threads", str(a.threads)], log)
            images[k] = read_pfm(pfm)
        for k, seed in (("mi", 7), ("mi2", 8)):
            pfm = os.path.join(out, "%s-%s.pfm" % (stem, k))
            xml = os.path.join(out, "%s-%s.xml" % (stem, k))
            with open(xml, "w") as f:
                f.write(mitsuba_scene(scene, a.size, a.mitsuba_spp or a.spp, seed, mi_material, includes))
            pbrt.run([a.mitsuba, "-m", variant, "-t", str(a.threads), "-o", pfm, xml], log)
            images[k] = read_pfm(pfm)
        rows.append((case, images))
        pbrt.print_row(case, what, images, "mi", base["environment"]["radiance"])
    pbrt.picture(rows, os.path.join(out, a.picture), key="mi", label="Mitsuba 3")
    print("files in %s" % out)


if __name__ == "__main__":
    main()
