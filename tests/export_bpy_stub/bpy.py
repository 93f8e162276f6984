"""A stand-in for Blender's `bpy`, just large enough to run the scripts `aniso export --to blender`
writes where Blender is not installed (tests/test_export.cpp, ExportCli.BlenderScriptRunsOnABpyStub).
The Principled BSDF's inputs are those of node_declare in
source/blender/nodes/shader/nodes/node_shader_bsdf_principled.cc: 3.x (read at 007b7d03) and 4.x
(the version with panels); a missing name raises KeyError as Blender's collections do.
The Metallic BSDF (4.3 and later) has the inputs of node_shader_bsdf_metallic.cc's node_declare; the
Add Shader its two "Shader" inputs, reached by index (node_shader_add_shader.cc).
ANISO_BPY_VERSION chooses "3.4", "4.2" or "4.3"; ANISO_BPY_UV=0 gives the object no UV map."""
import os

_V = os.environ.get("ANISO_BPY_VERSION", "4.2")
_PRINCIPLED = {
    "3.4": ["Base Color", "Subsurface", "Subsurface Radius", "Subsurface Color", "Subsurface IOR",
            "Subsurface Anisotropy", "Metallic", "Specular", "Specular Tint", "Roughness", "Anisotropic",
            "Anisotropic Rotation", "Sheen", "Sheen Tint", "Clearcoat", "Clearcoat Roughness", "IOR",
            "Transmission", "Transmission Roughness", "Emission", "Emission Strength", "Alpha", "Normal",
            "Clearcoat Normal", "Tangent"],
    "4.2": ["Base Color", "Metallic", "Roughness", "IOR", "Alpha", "Normal", "Subsurface Weight",
            "Subsurface Radius", "Subsurface Scale", "Subsurface IOR", "Subsurface Anisotropy",
            "Specular IOR Level", "Specular Tint", "Anisotropic", "Anisotropic Rotation", "Tangent",
            "Transmission Weight", "Coat Weight", "Coat Roughness", "Coat IOR", "Coat Tint", "Coat Normal",
            "Sheen Weight", "Sheen Roughness", "Sheen Tint", "Emission Color", "Emission Strength"],
}
_PRINCIPLED["4.3"] = _PRINCIPLED["4.2"]
_METALLIC = ["Base Color", "Edge Tint", "IOR", "Extinction", "Roughness", "Anisotropy", "Rotation", "Normal", "Tangent",
             "Weight", "Thin Film Thickness", "Thin Film IOR"]
_VECTOR = {"IOR", "Extinction"}
_COLOR = {"Edge Tint", "Base Color", "Subsurface Color", "Emission", "Emission Color", "Sheen Tint", "Coat Tint"}


class _Socket:
    def __init__(self, name, color=False):
        self.name = name
        self._color = color
        self._value = (0.0, 0.0, 0.0, 1.0) if color else 0.0

    @property
    def default_value(self):
        return self._value

    @default_value.setter
    def default_value(self, v):
        if self._color == "vector":
            if len(v) != 3:
                raise TypeError(f"{self.name}: expected 3 values, got {v!r}")
        elif self._color and len(v) != 4:
            raise TypeError(f"{self.name}: expected 4 values, got {v!r}")
        elif not self._color and not isinstance(v, (int, float)):
            raise TypeError(f"{self.name}: expected a number, got {v!r}")
        self._value = v


class _Sockets(dict):
    def __getitem__(self, k):
        if k not in self:
            raise KeyError(f"bpy_prop_collection[key]: key \"{k}\" not found")
        return dict.__getitem__(self, k)


class _IndexedSockets(list):
    def __getitem__(self, k):
        if not isinstance(k, int):
            raise KeyError(f"bpy_prop_collection[key]: use an index for sockets of the same name, got {k!r}")
        return list.__getitem__(self, k)


class _Node:
    def __init__(self, kind):
        self.bl_idname = kind
        self.location = (0, 0)
        self.inputs, self.outputs = _Sockets(), _Sockets()
        if kind == "ShaderNodeBsdfMetallic":
            if _V != "4.3":
                raise RuntimeError(f"unknown node type {kind} before Blender 4.3")
            for n in _METALLIC:
                self.inputs[n] = _Socket(n, "vector" if n in _VECTOR else n in _COLOR)
            self.outputs["BSDF"] = _Socket("BSDF")
            self.distribution = "MULTI_GGX"
            self.fresnel_type = "F82"
        elif kind == "ShaderNodeBsdfPrincipled":
            color4 = _V != "3.4"
            for n in _PRINCIPLED[_V]:
                self.inputs[n] = _Socket(n, n in _COLOR or (color4 and n == "Specular Tint"))
            self.outputs["BSDF"] = _Socket("BSDF")
            self.distribution = "GGX" if _V == "3.4" else "MULTI_GGX"
        elif kind == "ShaderNodeAddShader":  # node_shader_add_shader.cc: two inputs named "Shader", by index
            self.inputs = _IndexedSockets([_Socket("Shader"), _Socket("Shader")])
            self.outputs["Shader"] = _Socket("Shader")
        elif kind == "ShaderNodeOutputMaterial":
            self.inputs["Surface"] = _Socket("Surface")
        elif kind == "ShaderNodeTangent":
            self.outputs["Tangent"] = _Socket("Tangent")
            self.direction_type = "RADIAL"
            self.uv_map = ""
        else:
            raise RuntimeError(f"unknown node type {kind}")

    def __setattr__(self, k, v):
        if k == "distribution" and v not in ("BECKMANN", "GGX", "MULTI_GGX"):
            raise TypeError(f"enum \"{v}\" not found in ('BECKMANN', 'GGX', 'MULTI_GGX')")
        if k == "fresnel_type" and v not in ("F82", "PHYSICAL_CONDUCTOR"):
            raise TypeError(f"enum \"{v}\" not found in ('F82', 'PHYSICAL_CONDUCTOR')")
        if k == "direction_type" and v not in ("RADIAL", "UV_MAP"):
            raise TypeError(f"enum \"{v}\" not found")
        object.__setattr__(self, k, v)


class _Nodes(list):
    def remove(self, node):
        list.remove(self, node)

    def new(self, kind):
        n = _Node(kind)
        self.append(n)
        return n


class _Links(list):
    def new(self, a, b):
        self.append((a, b))


class _Tree:
    def __init__(self):
        self.nodes, self.links = _Nodes(), _Links()


class _Material:
    def __init__(self, name):
        self.name, self.use_nodes, self.node_tree = name, False, _Tree()


class _Materials(dict):
    def new(self, name):
        self[name] = _Material(name)
        return self[name]


class _Uv:
    name = "UVMap"


class _UvLayers(list):
    @property
    def active(self):
        return self[0] if self else None


class _Mesh:
    def __init__(self):
        self.uv_layers = _UvLayers([_Uv()] if os.environ.get("ANISO_BPY_UV", "1") == "1" else [])
        self.materials = []


class _Object:
    type = "MESH"

    def __init__(self):
        self.data = _Mesh()


class _Ns:
    pass


app = _Ns()
app.version = {"3.4": (3, 4, 1), "4.2": (4, 2, 0), "4.3": (4, 3, 0)}[_V]
app.version_string = _V
data = _Ns()
data.materials = _Materials()
context = _Ns()
context.view_layer = _Ns()
context.view_layer.objects = _Ns()
context.view_layer.objects.active = _Object()
