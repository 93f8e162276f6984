// export/blender.cpp: --to blender, the Python script that builds the Principled BSDF (or 4.3's
// Metallic BSDF) material.
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

}  // namespace aniso::exporter
