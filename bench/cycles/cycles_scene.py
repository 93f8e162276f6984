# Builds an aniso scene of bench/cycles/ in Blender's Cycles and renders it (docs/benchmarks.md, "Cycles").
#
#   blender -b --factory-startup -P bench/cycles/cycles_scene.py -- SCENE.json OUT.pfm
#           [--spp N] [--width W] [--height H] [--seed S] [--threads T] [--light mesh|point]
#
# The scene is read from the same JSON as `aniso render` reads (one source of truth); only what the
# side-by-side uses is accepted (pinhole camera with up +y, uniform environment, sphere lights, sphere
# objects of GGX without Fresnel or Lambert), anything else is an error naming the key.
#
# Conventions (aniso's docs/scenes.md on the left, Cycles 3.4 on the right):
# - axes: aniso is y-up, Blender z-up: (x, y, z) -> (x, -z, y), a rotation (handedness kept).
# - camera: `fov_deg` is the vertical field of view: sensor_fit VERTICAL, angle = fov.
# - pixels: aniso averages radiance over each pixel's square (a box filter): Cycles' pixel filter
#   BOX of width 1 px (film_filter_type / filter_width).
# - environment `uniform` L: World Background colour (L, L, L), strength 1.
# - sphere light (radiance L, radius r): `--light mesh`: a UV sphere with an Emission shader of
#   strength L (Cycles' emission strength is radiance: a surface of strength 1 renders 1), sampled
#   as a mesh light; `--light point`: a point lamp of radius r and power 4 pi^2 r^2 L (Cycles 3.x
#   kernel/light/light.h evaluates a point lamp's radiance as P / (4 pi) * 1 / (pi r^2), the
#   `M_1_PI_F * 0.25f * invarea` of the point case; 4 pi^2 r^2 L is also the power of a sphere of
#   radiance L), which Cycles 3.4 samples as a disc facing the shading point.
# - GGX (f0 = 1: Schlick's F is 1, no Fresnel): the Anisotropic BSDF (3.4's name for the Glossy
#   BSDF with anisotropy), distribution GGX, white; alphas from roughness r and anisotropy a as
#   include/aniso/export/targets.h, cycles_glossy_alpha (closure.h: alpha_x = r^2 (1 - a),
#   alpha_y = r^2 / (1 - a) for a >= 0, the reverse for a < 0), inverted here. Cycles ignores the
#   anisotropy without a Tangent input: a Tangent node, radial about Blender's z (aniso's y), gives
#   the sphere's dp/du = +y x n (docs/scenes.md, Objects) up to its sign, which GGX does not see.
# - Lambert kd: the Diffuse BSDF with colour kd, roughness 0.
# - sampling: no adaptive sampling, no denoising, no clamping, no Filter Glossy, no light
#   threshold, no caustics filter: Cycles' defaults that bias are all off, as aniso's are.
#
# The image is written as a PFM (rows bottom to top, as Blender stores them) of linear radiance.
import json
import math
import os
import sys

import bpy
import numpy as np
from mathutils import Vector


def fail(msg):
    print("cycles_scene.py: error: " + msg, file=sys.stderr)
    sys.exit(2)


def args():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    if len(argv) < 2:
        fail("usage: blender -b -P cycles_scene.py -- SCENE.json OUT.pfm [--spp N] [--width W] [--height H] "
             "[--seed S] [--threads T] [--light mesh|point]")
    o = {"scene": argv[0], "out": argv[1], "spp": None, "width": None, "height": None, "seed": 1, "threads": 0,
         "light": "mesh"}
    i = 2
    while i < len(argv):
        k = argv[i]
        if i + 1 >= len(argv):
            fail("%s needs a value" % k)
        v = argv[i + 1]
        if k in ("--spp", "--width", "--height", "--seed", "--threads"):
            try:
                o[k[2:]] = int(v)
            except ValueError:
                fail("%s: expected a whole number, got %r" % (k, v))
        elif k == "--light":
            if v not in ("mesh", "point"):
                fail("--light: expected mesh or point, got %r" % v)
            o["light"] = v
        else:
            fail("unknown option %r" % k)
        i += 2
    return o


def vec(v, where):
    if not (isinstance(v, list) and len(v) == 3 and all(isinstance(x, (int, float)) for x in v)):
        fail("%s: expected [x, y, z], got %r" % (where, v))
    return v


def to_blender(p):
    """aniso's y-up point -> Blender's z-up point."""
    return Vector((p[0], -p[2], p[1]))


def grey(v, where):
    if isinstance(v, (int, float)):
        return (float(v),) * 3
    if isinstance(v, list) and len(v) == 3:
        return tuple(float(x) for x in v)
    fail("%s: expected a number or [r, g, b], got %r" % (where, v))


def glossy_roughness_anisotropy(ax, ay):
    """The Anisotropic BSDF's (roughness, anisotropy) for GGX alphas along the tangent and bitangent."""
    r2 = math.sqrt(ax * ay)
    a = 1.0 - math.sqrt(ax / ay) if ax <= ay else math.sqrt(ay / ax) - 1.0
    if abs(a) > 0.99:
        fail("alpha_x / alpha_y = %g: Cycles clamps the anisotropy to +-0.99" % (ax / ay))
    return math.sqrt(r2), a


def material(spec, name):
    if not isinstance(spec, dict):
        fail("%s: expected an inline material object" % name)
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    model = spec.get("model")
    if model == "ggx":
        if spec.get("f0") != 1 or spec.get("kd", 0) != 0:
            fail("%s: GGX needs f0 = 1 and no kd here (the Anisotropic BSDF has no Fresnel)" % name)
        ax = float(spec.get("alpha_x", spec.get("alpha", 0.2)))
        ay = float(spec.get("alpha_y", spec.get("alpha", 0.2)))
        rough, aniso = glossy_roughness_anisotropy(ax, ay)
        b = nt.nodes.new("ShaderNodeBsdfAnisotropic")
        b.distribution = "GGX"
        b.inputs["Color"].default_value = (1, 1, 1, 1)
        b.inputs["Roughness"].default_value = rough
        b.inputs["Anisotropy"].default_value = aniso
        b.inputs["Rotation"].default_value = 0.0
        t = nt.nodes.new("ShaderNodeTangent")
        t.direction_type = "RADIAL"
        t.axis = "Z"
        nt.links.new(t.outputs["Tangent"], b.inputs["Tangent"])
    elif model == "lambert":
        b = nt.nodes.new("ShaderNodeBsdfDiffuse")
        b.inputs["Color"].default_value = grey(spec.get("kd", 0.5), name + ".kd") + (1,)
        b.inputs["Roughness"].default_value = 0.0
    else:
        fail("%s: model %r: the side-by-side has ggx and lambert" % (name, model))
    nt.links.new(b.outputs["BSDF"], out.inputs["Surface"])
    return m


def uv_sphere(center, radius, segments, rings):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=segments, ring_count=rings, radius=radius,
                                         location=to_blender(center))
    ob = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    return ob


def build(scene_doc, o):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    film = scene_doc.get("film", {})
    sc.render.resolution_x = o["width"] or int(film.get("width", 640))
    sc.render.resolution_y = o["height"] or int(film.get("height", 360))
    sc.render.resolution_percentage = 100
    sc.render.engine = "CYCLES"
    cy = sc.cycles
    cy.device = "CPU"
    cy.samples = o["spp"] or int(film.get("spp", 64))
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.seed = o["seed"]
    cy.use_animated_seed = False
    depth = int(scene_doc.get("integrator", {}).get("max_depth", 8))
    cy.max_bounces = cy.diffuse_bounces = cy.glossy_bounces = depth
    cy.transmission_bounces = cy.volume_bounces = cy.transparent_max_bounces = depth
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.blur_glossy = 0.0
    cy.light_sampling_threshold = 0.0
    cy.caustics_reflective = cy.caustics_refractive = True
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 1.0
    if o["threads"] > 0:
        sc.render.threads_mode = "FIXED"
        sc.render.threads = o["threads"]
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.view_settings.exposure = 0.0
    sc.view_settings.gamma = 1.0

    cam = scene_doc.get("camera") or fail("camera: required")
    up = vec(cam.get("up", [0, 1, 0]), "camera.up")
    if up[0] != 0 or up[2] != 0 or up[1] <= 0:
        fail("camera.up: the script takes [0, 1, 0] (Blender's z), got %r" % (up,))
    cd = bpy.data.cameras.new("camera")
    cd.sensor_fit = "VERTICAL"
    cd.angle = math.radians(float(cam.get("fov_deg", 40)))
    cd.clip_start = 1e-3
    cd.clip_end = 1e4
    co = bpy.data.objects.new("camera", cd)
    sc.collection.objects.link(co)
    pos = to_blender(vec(cam["position"], "camera.position"))
    look = to_blender(vec(cam["look_at"], "camera.look_at"))
    co.location = pos
    co.rotation_euler = (look - pos).to_track_quat("-Z", "Y").to_euler()
    sc.camera = co

    world = bpy.data.worlds.new("world")
    sc.world = world
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    env = scene_doc.get("environment")
    if env is None:
        bg.inputs["Color"].default_value = (0, 0, 0, 1)
    elif env.get("type") == "uniform":
        bg.inputs["Color"].default_value = grey(env.get("radiance"), "environment.radiance") + (1,)
    else:
        fail("environment.type %r: the side-by-side takes uniform" % env.get("type"))
    bg.inputs["Strength"].default_value = 1.0

    for i, light in enumerate(scene_doc.get("lights", [])):
        where = "lights[%d]" % i
        if light.get("type") != "sphere":
            fail("%s.type %r: the side-by-side takes sphere lights" % (where, light.get("type")))
        c = vec(light["center"], where + ".center")
        r = float(light["radius"])
        L = grey(light["radiance"], where + ".radiance")
        if o["light"] == "mesh":
            # 256 x 128 quads: the polygon's projected area is 1 - 4e-4 of the sphere's (about
            # ((pi / 256)^2 + (pi / 128)^2) / 2 short; 64 x 32 would dim the light by 0.6 %).
            ob = uv_sphere(c, r, 256, 128)
            m = bpy.data.materials.new("light%d" % i)
            m.use_nodes = True
            em = m.node_tree.nodes.new("ShaderNodeEmission")
            em.inputs["Color"].default_value = L + (1,)
            em.inputs["Strength"].default_value = 1.0
            for n in list(m.node_tree.nodes):
                if n.bl_idname == "ShaderNodeBsdfPrincipled":
                    m.node_tree.nodes.remove(n)
            m.node_tree.links.new(em.outputs["Emission"], m.node_tree.nodes["Material Output"].inputs["Surface"])
            ob.data.materials.append(m)
        else:
            ld = bpy.data.lights.new("light%d" % i, type="POINT")
            peak = max(L)
            ld.color = tuple(x / peak for x in L) if peak > 0 else (1, 1, 1)
            ld.energy = 4.0 * math.pi**2 * r * r * peak
            ld.shadow_soft_size = r
            ld.cycles.max_bounces = depth
            lo = bpy.data.objects.new("light%d" % i, ld)
            lo.location = to_blender(c)
            sc.collection.objects.link(lo)

    for i, obj in enumerate(scene_doc.get("objects", [])):
        where = "objects[%d]" % i
        if obj.get("shape") != "sphere":
            fail("%s.shape %r: the side-by-side takes spheres" % (where, obj.get("shape")))
        if "tangent" in obj:
            fail("%s.tangent: the side-by-side takes the sphere's natural tangent" % where)
        # 256 x 128 quads: the polygon's silhouette is within 8e-5 radii of the sphere's (1 - cos(pi / 256)).
        ob = uv_sphere(vec(obj["center"], where + ".center"), float(obj["radius"]), 256, 128)
        ob.data.materials.append(material(obj.get("material"), where + ".material"))


def write_pfm(path, rgb_bottom_up, w, h):
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        f.write(np.ascontiguousarray(rgb_bottom_up, dtype="<f4").tobytes())


def main():
    o = args()
    try:
        with open(o["scene"]) as f:
            doc = json.load(f)
    except (OSError, ValueError) as e:
        fail("%s: %s" % (o["scene"], e))
    build(doc, o)
    sc = bpy.context.scene
    exr = o["out"] + ".exr"
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    sc.render.image_settings.exr_codec = "NONE"
    sc.render.filepath = exr
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(exr)
    w, h = img.size
    px = np.array(img.pixels[:], dtype=np.float32).reshape(h, w, 4)[:, :, :3]
    write_pfm(o["out"], px, w, h)
    os.remove(exr)


main()
