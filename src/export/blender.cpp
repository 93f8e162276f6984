// export/blender.cpp: --to blender, the Python script that builds the Principled BSDF (or 4.3's
// Metallic BSDF) material, and its target model (blender_model: GGX -> the Principled BSDF).
#include "export/target_models.h"
#include "export/writers.h"

#include <fmt/format.h>

namespace aniso::exporter {

std::string write_blender(const std::string& name, const json& p, const std::string& comment) {
  const bool metallic = num(p, "Metallic") > 0.5;
  std::string s = comment;
  s += "#\n# Builds the material for Blender 3.4 and 4.x (Principled BSDF input names differ: checked by\n"
       "# bpy.app.version), assigns it to the active object if there is one, and takes the tangent from\n"
       "# that object's active UV map (dp/du) when it has one.\n";
  s += "import bpy\n\n";
  s += fmt::format("NAME = {}\n", py_string(name));
  s += "V4 = bpy.app.version >= (4, 0, 0)\n\n";
  s += "mat = bpy.data.materials.get(NAME) or bpy.data.materials.new(NAME)\n"
       "mat.use_nodes = True\n"
       "nodes, links = mat.node_tree.nodes, mat.node_tree.links\n"
       "nodes.clear()\n"
       "out = nodes.new(\"ShaderNodeOutputMaterial\")\n"
       "out.location = (300, 0)\n"
       "bsdf = nodes.new(\"ShaderNodeBsdfPrincipled\")\n"
       "bsdf.distribution = \"GGX\"  # single-scattering GGX, as the target model (not MULTI_GGX)\n"
       "links.new(bsdf.outputs[\"BSDF\"], out.inputs[\"Surface\"])\n\n"
       "bsdfs = [bsdf]  # the nodes the tangent goes to\n\n"
       "def put(name, value, node=None):\n"
       "    node = node or bsdf\n"
       "    if name not in node.inputs:\n"
       "        raise KeyError(\"%s of Blender %s has no input %r\" % (node.bl_idname, bpy.app.version_string, name))\n"
       "    node.inputs[name].default_value = value\n\n";
  // The inputs both node setups share: Base Color and Metallic from `from`, the lobe's from p, into
  // `node` ("" for the script's bsdf).
  const auto shared_inputs = [&](const json& from, const std::string& indent, const std::string& node) {
    const glm::dvec3 c = col(from, "Base Color");
    const std::string arg = node.empty() ? "" : ", " + node;
    std::string t = fmt::format("{}put(\"Base Color\", ({:.9g}, {:.9g}, {:.9g}, 1.0){})\n", indent, c.x, c.y, c.z, arg);
    t += fmt::format("{}put(\"Metallic\", {:.9g}{})\n", indent, num(from, "Metallic"), arg);
    for (const char* k : {"Roughness", "Anisotropic", "Anisotropic Rotation"})
      t += fmt::format("{}put(\"{}\", {:.9g}{})\n", indent, k, num(p, k), arg);
    return t;
  };
  s += shared_inputs(p, "", "");
  s += "if V4:\n";
  if (metallic) {
    const glm::dvec3 t = col(p, "Specular Tint");
    s += fmt::format("    put(\"Specular Tint\", ({:.9g}, {:.9g}, {:.9g}, 1.0))  # the F82 edge tint\n", t.x, t.y, t.z);
  } else {
    const glm::dvec3 t = col(p, "Specular Tint");
    s += fmt::format("    put(\"IOR\", {:.9g})\n    put(\"Specular IOR Level\", {:.9g})\n", num(p, "IOR"),
                     num(p, "Specular IOR Level"));
    s += fmt::format("    put(\"Specular Tint\", ({:.9g}, {:.9g}, {:.9g}, 1.0))  # F0 = F0(IOR) Specular Tint: the F0's hue\n",
                     t.x, t.y, t.z);
  }
  s += "else:\n";
  if (metallic) {
    s += fmt::format(
        "    put(\"Specular\", {:.9g})  # 3.4: the ior of the Fresnel curve's shape (no edge tint: Specular Tint is a float)\n",
        num(p, "Specular"));
  } else if (p.contains("Add Shader (3.4)")) {
    // targets.h, BlenderV1Nodes::AddShader: this node the diffuse alone, a metallic one the specular.
    const json& a = p["Add Shader (3.4)"];
    s += "    put(\"Specular\", 0.0)  # this node: the diffuse alone (Specular and Metallic 0: no specular closure)\n"
         "    spec = nodes.new(\"ShaderNodeBsdfPrincipled\")  # the specular: metallic, Base Color = F0 of any colour\n"
         "    spec.location = (0, -700)\n"
         "    spec.distribution = \"GGX\"\n";
    s += shared_inputs(a, "    ", "spec");
    s += fmt::format("    put(\"Specular\", {:.9g}, spec)  # the ior of the Fresnel curve's shape\n", num(a, "Specular"));
    s += "    add = nodes.new(\"ShaderNodeAddShader\")  # Cycles sums the two closures\n"
         "    add.location = (150, 0)\n"
         "    links.new(bsdf.outputs[\"BSDF\"], add.inputs[0])\n"
         "    links.new(spec.outputs[\"BSDF\"], add.inputs[1])\n"
         "    links.new(add.outputs[\"Shader\"], out.inputs[\"Surface\"])\n"
         "    bsdfs.append(spec)\n";
  } else {
    s += fmt::format(
        "    put(\"Specular\", {:.9g})  # F0 = 0.08 Specular (above 1 where F0 is above 0.08: the socket takes it)\n"
        "    put(\"Specular Tint\", {:.9g})  # F0 mixed towards the Base Color's hue\n",
        num(p, "Specular"), num(p, "Specular Tint (3.4)"));
  }
  if (p.contains("Extinction")) {
    // Blender 4.3+: the Metallic BSDF (node_shader_bsdf_metallic.cc: IOR and Extinction are
    // vectors, Anisotropy and Rotation as the Principled BSDF's) replaces the Principled one.
    const glm::dvec3 n = col(p, "IOR"), k = col(p, "Extinction");
    s += "\nif bpy.app.version >= (4, 3, 0):  # the physical conductor: n, k themselves\n"
         "    nodes.remove(bsdf)\n"
         "    bsdf = nodes.new(\"ShaderNodeBsdfMetallic\")\n"
         "    bsdf.distribution = \"GGX\"\n"
         "    bsdf.fresnel_type = \"PHYSICAL_CONDUCTOR\"\n"
         "    links.new(bsdf.outputs[\"BSDF\"], out.inputs[\"Surface\"])\n"
         "    bsdfs = [bsdf]\n";
    s += fmt::format("    put(\"IOR\", ({:.9g}, {:.9g}, {:.9g}))\n", n.x, n.y, n.z);
    s += fmt::format("    put(\"Extinction\", ({:.9g}, {:.9g}, {:.9g}))\n", k.x, k.y, k.z);
    s += fmt::format("    put(\"Roughness\", {:.9g})\n", num(p, "Roughness"));
    s += fmt::format("    put(\"Anisotropy\", {:.9g})\n", num(p, "Anisotropic"));
    s += fmt::format("    put(\"Rotation\", {:.9g})\n", num(p, "Anisotropic Rotation"));
  }
  s += "\nobj = bpy.context.view_layer.objects.active\n"
       "if obj is not None and obj.type == \"MESH\":\n"
       "    uv = obj.data.uv_layers.active\n"
       "    if uv is not None:\n"
       "        tangent = nodes.new(\"ShaderNodeTangent\")\n"
       "        tangent.location = (-300, -300)\n"
       "        tangent.direction_type = \"UV_MAP\"\n"
       "        tangent.uv_map = uv.name\n"
       "        for node in bsdfs:\n"
       "            links.new(tangent.outputs[\"Tangent\"], node.inputs[\"Tangent\"])\n"
       "    if obj.data.materials:\n"
       "        obj.data.materials[0] = mat\n"
       "    else:\n"
       "        obj.data.materials.append(mat)\n";
  return s;
}

// --- the target model: GGX -> the Principled BSDF (Blender 3.4 and 4.x) ----------------------------

namespace {

// Blender 3.4's metallic Principled: the Specular (in [0, 1]) whose interpolated Fresnel with cspec0
// = f0 (cycles_v1_fresnel) is closest to the source's curve (the conductor's, or Schlick's with f0)
// over the cosine: least squares on 64 points, golden-section search.
double v1_metal_specular(const GgxSource& g, const glm::dvec3& f0) {
  const auto cost = [&](double specular) {
    const double ior = cycles_v1_ior(specular);
    double e = 0.0;
    for (int i = 0; i < 64; ++i) {
      const double c = (i + 0.5) / 64.0;
      const glm::dvec3 want = g.conductor ? glm::dvec3(F_Conductor(c, RGBT<double>(g.eta), RGBT<double>(g.k)))
                                          : glm::dvec3(F_Schlick(RGBT<double>(g.f0), c));
      const glm::dvec3 d = cycles_v1_fresnel(c, f0, ior) - want;
      e += glm::dot(d, d);
    }
    return e;
  };
  const double r = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = 1e-4, b = 1.0, x1 = b - r * (b - a), x2 = a + r * (b - a), f1 = cost(x1), f2 = cost(x2);
  for (int i = 0; i < 60; ++i) {
    if (f1 < f2)
      b = x2, x2 = x1, f2 = f1, x1 = b - r * (b - a), f1 = cost(x1);
    else
      a = x1, x1 = x2, f1 = f2, x2 = a + r * (b - a), f2 = cost(x2);
  }
  const double best = (a + b) / 2.0;
  return cost(1.0) < cost(best) ? 1.0 : best;
}

}  // namespace

bool blender_v1_add_shader_candidate(const GgxSource& g) {
  if (g.conductor || no_diffuse(g)) return false;
  const CyclesV1Specular spec = cycles_v1_dielectric_specular(g.f0, g.kd);
  const glm::dvec3 miss = glm::abs(cycles_v1_cspec0(g.kd, 0.0, spec.specular, spec.tint) - glm::clamp(g.f0, 0.0, 1.0));
  return max3(miss) > kBlenderV1ColourMiss;
}

TargetBrdf blender_model(const GgxSource& g, json& p, std::vector<std::string>& notes, double blender_version,
                         BlenderV1Nodes nodes) {
  TargetBrdf m;
  double ax = g.alpha_x, ay = g.alpha_y;
  const glm::dvec3 cond_f0 = source_f0(g);
  // Principled BSDF (closure.h @ 02e6985c; 3.4.1: closure.h:321-325, the same formula):
  // alpha_x = r^2 / aspect >= alpha_y = r^2 aspect, aspect^2 = alpha_y / alpha_x = 1 - 0.9
  // anisotropic, anisotropic <= 1.
  const auto [extra, rough, aniso] = invert_aspect(ax, ay, 0.9, 1.0, "the Principled BSDF", notes);
  const double turn = wrap_turn((g.rotation_deg + extra) / 360.0);
  const glm::dvec2 a = cycles_principled_alpha(rough, aniso);
  // Blender before 3.5: the Principled BSDF v1 (targets.h, "Blender 3.4"): separable Smith G,
  // the interpolated Fresnel, Burley's diffuse; 3.4's bsdf_microfacet_ggx_fresnel_setup
  // saturates both alphas (bsdf_microfacet.h:315-316).
  const bool v1 = blender_version < 3.5;
  m.lobe.alpha_x = v1 ? std::min(a.x, 1.0) : a.x, m.lobe.alpha_y = v1 ? std::min(a.y, 1.0) : a.y;
  m.tangent_turn_deg = extra;
  m.lobe.masking = v1 ? Masking::Separable : Masking::HeightCorrelated;
  p["Roughness"] = rough, p["Anisotropic"] = aniso, p["Anisotropic Rotation"] = turn;
  p["distribution"] = "GGX";
  if (g.conductor || no_diffuse(g)) {
    // Metallic: F0 = min(Base Color, 1), F82-tint with f82 = min(Specular Tint, 1).
    const glm::dvec3 f0 = glm::clamp(cond_f0, 0.0, 1.0);
    glm::dvec3 tint(1.0);
    if (g.conductor) {
      const double c82 = 1.0 / 7.0;
      tint = cycles_tint_for(f0, glm::dvec3(F_Conductor(c82, RGBT<double>(g.eta), RGBT<double>(g.k))));
    }
    // 3.4: cspec0 = Base Color; the curve's shape is the dielectric Fresnel at the Specular
    // input's ior: the Specular in [0, 1] whose curve is closest to the source's (conductor or
    // Schlick) over the cosine.
    const double specular = v1_metal_specular(g, f0);
    p["Base Color"] = j3(f0), p["Metallic"] = 1.0, p["Specular Tint"] = j3(tint), p["Specular"] = specular;
    if (v1) {
      m.name = "Cycles 3.4 Principled BSDF v1, metallic (interpolated Fresnel, separable Smith G)";
      m.lobe.fresnel = FresnelModel::CyclesV1;
      m.lobe.f0 = f0, m.lobe.eta = glm::dvec3(cycles_v1_ior(specular));
      notes.push_back(
          fmt::format("Blender 3.4: F = Base Color (1 - FH) + FH, FH the dielectric Fresnel of the Specular input's ior "
                      "normalised to [F0, 1] (bsdf_util.h:94-105); Specular {:.4g} (ior {:.4g}) gives the curve closest to "
                      "the source's",
                      specular, cycles_v1_ior(specular)));
    } else {
      m.name = "Cycles 4.x Principled BSDF, metallic (F82-tint Fresnel, height-correlated Smith G)";
      m.lobe.fresnel = FresnelModel::F82Tint;
      m.lobe.f0 = f0;
      m.lobe.f82_b = cycles_f82tint_b(f0, tint);
    }
    if (g.conductor && !v1 && blender_version >= 4.3) {
      // Blender 4.3+: the Metallic BSDF with fresnel_type PHYSICAL_CONDUCTOR takes n and k
      // (closure.h, CLOSURE_BSDF_PHYSICAL_CONDUCTOR: the same aspect mapping as the Principled
      // BSDF, bsdf_microfacet_setup_fresnel_conductor with ior = {n, k}): aniso's conductor exactly.
      m.name = "Cycles 4.3+ Metallic BSDF, physical conductor (exact n, k Fresnel, height-correlated Smith G)";
      m.lobe.fresnel = FresnelModel::Conductor;
      m.lobe.eta = g.eta, m.lobe.k = g.k;
      p["IOR"] = j3(g.eta), p["Extinction"] = j3(g.k);
      notes.push_back(
          "Blender 4.3+: a Metallic BSDF with the physical conductor Fresnel (n, k); before 4.3 the "
          "script builds a Principled BSDF with F0 and the F82 tint matching the reflectance at cos = "
          "1/7 instead (--blender-version 4.0 reports that one; 3.4 has no tint)");
    } else if (g.conductor) {
      p["IOR"] = j3(g.eta), p["Extinction"] = j3(g.k);  // the script's 4.3+ branch, whatever is reported
      notes.push_back(
          "the conductor's n, k become F0 and the F82 tint matching its reflectance at cos = 1/7 (the "
          "script uses 4.3's Metallic BSDF with n, k where it exists; Blender 3.4 has no tint: its "
          "Specular Tint is a float, its Specular sets the curve's shape)");
    }
  } else {
    // 4.x: F = mix(F0_from_ior(IOR) Specular Tint, 1, s), s = (F_dielectric(IOR) - F0(IOR)) / (1 -
    // F0(IOR)) (closure.h, "Apply IOR adjustment" and the Specular component: f0 = F0_from_ior(eta)
    // specular_tint, f90 1, exponent -eta; bsdf_microfacet.h, microfacet_fresnel, the
    // GENERALIZED_SCHLICK case with exponent < 0; cycles_dielectric_tint_fresnel): the exact
    // dielectric Fresnel where the tint is white. The IOR and the tint: tinted_dielectric (the F0's
    // hue exactly, every channel in [0, 1]).
    const TintedDielectric td = tinted_dielectric(g.f0);
    const double eta = td.eta, f0 = F_Conductor(1.0, eta, 0.0);
    m.diffuse = g.kd;
    p["Base Color"] = j3(g.kd), p["Metallic"] = 0.0, p["IOR"] = eta, p["Specular IOR Level"] = 0.5;
    p["Specular Tint"] = j3(td.tint);
    // 3.4, one node: cspec0 = 0.08 Specular mix(1, Base Color / its luminance, Specular Tint)
    // (closure.h:317, 327-334), Specular above 1 where F0 is above 0.08 (cycles_v1_dielectric_specular).
    // 3.4, the Add Shader (BlenderV1Nodes): the diffuse node with Specular 0 and a metallic node with
    // Base Color = F0 (bsdf_microfacet_ggx_fresnel_setup saturates cspec0, bsdf_microfacet.h:315)
    // whose Specular shapes the interpolated Fresnel: the curve closest to Schlick's with this F0
    // (v1_metal_specular, as for a metal).
    const bool add_shader = nodes == BlenderV1Nodes::AddShader;
    const CyclesV1Specular spec = cycles_v1_dielectric_specular(g.f0, g.kd);
    const glm::dvec3 metal_f0 = glm::clamp(g.f0, 0.0, 1.0);
    const double metal_specular = add_shader ? v1_metal_specular(g, metal_f0) : 0.0;
    p["Specular"] = add_shader ? 0.0 : spec.specular;
    p["Specular Tint (3.4)"] = add_shader ? 0.0 : spec.tint;
    if (add_shader) p["Add Shader (3.4)"] = {{"Base Color", j3(metal_f0)}, {"Metallic", 1.0}, {"Specular", metal_specular}};
    if (v1 && add_shader) {
      m.name =
          "Cycles 3.4 Add Shader: Principled BSDF v1 diffuse (Burley) + Principled BSDF v1 metallic (Base Color = F0, "
          "interpolated Fresnel, separable Smith G)";
      m.lobe.fresnel = FresnelModel::CyclesV1;
      m.lobe.f0 = metal_f0, m.lobe.eta = glm::dvec3(cycles_v1_ior(metal_specular));
      m.burley_roughness = rough;
      notes.push_back(fmt::format(
          "Blender 3.4: one Principled BSDF cannot write this F0 {} over this Base Color (its dielectric F0 is white mixed "
          "with the Base Color's hue, closure.h:327-334: the closest is {}): the script adds a diffuse-only Principled "
          "BSDF (Specular 0) and a metallic one (Base Color = F0, Specular {:.4g} for the Fresnel curve's shape, ior "
          "{:.4g}) with an Add Shader, which Cycles sums",
          fmt3(g.f0), fmt3(cycles_v1_cspec0(g.kd, 0.0, spec.specular, spec.tint)), metal_specular,
          cycles_v1_ior(metal_specular)));
    } else if (v1) {
      m.name = "Cycles 3.4 Principled BSDF v1, dielectric (exact Fresnel, separable Smith G) + Burley diffuse";
      m.lobe.fresnel = FresnelModel::CyclesV1;
      m.lobe.f0 = cycles_v1_cspec0(g.kd, 0.0, spec.specular, spec.tint);
      m.lobe.eta = glm::dvec3(cycles_v1_ior(spec.specular));
      m.burley_roughness = rough;
      if (spec.specular > 1.0)
        notes.push_back(fmt::format(
            "Blender 3.4: Specular {:.4g} (F0 {:.4g}) is above the slider's 1: the socket takes it (its hard range is "
            "unbounded) and Cycles reads it unclamped (closure.h:317)",
            spec.specular, 0.08 * spec.specular));
      if (const glm::dvec3 d = m.lobe.f0 - glm::clamp(g.f0, 0.0, 1.0); glm::dot(d, d) > 1e-6)
        notes.push_back(fmt::format(
            "Blender 3.4's dielectric F0 is white mixed with the Base Color's hue (Specular Tint {:.3g}, closure.h:327-334): "
            "the source's F0 {} is written as {}, the closest such colour",
            spec.tint, fmt3(g.f0), fmt3(m.lobe.f0)));
    } else {
      m.name = "Cycles 4.x Principled BSDF, dielectric (exact Fresnel times the Specular Tint, height-correlated G) + Lambert";
      m.lobe.fresnel = FresnelModel::CyclesDielectricTint;
      m.lobe.f0 = f0 * td.tint, m.lobe.eta = glm::dvec3(eta);
      notes.push_back(fmt::format(
          "Schlick's F0 {} becomes the dielectric Fresnel of IOR {:.4g} closest to the curve of its largest channel (F0 "
          "{:.4g}), F0 times Specular Tint {} (F0 / its largest channel: the F0's hue)",
          fmt3(g.f0), eta, f0, fmt3(td.tint)));
      notes.push_back(
          "Cycles layers the diffuse under the specular (its weight times 1 - the specular albedo, "
          "closure_layering_weight); the target model adds them as aniso's GGX does");
    }
    if (v1)
      notes.push_back(
          "Blender 3.4: the Fresnel is the dielectric one at ior = 2 / (1 - sqrt(0.08 Specular)) - 1 interpolated from "
          "F0 to 1 (closure.h:317, bsdf_util.h:94-105), the diffuse Burley's with retro-reflection at the same Roughness "
          "(bsdf_principled_diffuse.h:45-86), added to the specular");
  }
  notes.push_back(v1 ? "the target model is Blender 3.4's Principled BSDF v1 (separable Smith G, interpolated Fresnel, "
                       "Burley diffuse), distribution GGX (set by the script; Multiscatter GGX adds the energy of the "
                       "lobe's multiple bounces, which the single-scattering model leaves out)"
                     : "the target model is Blender 4.x's Principled BSDF; Blender 3.4's (Principled v1: separable "
                       "Smith G, interpolated Fresnel, Burley diffuse) is reported in a note");
  return m;
}

}  // namespace aniso::exporter
