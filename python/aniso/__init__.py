"""aniso: anisotropic and measured reflectance from Python (docs/python.md).

NumPy in and out: materials from presets, dicts, files or keywords (``Material``), evaluated,
sampled and integrated through the library's batch path on all cores; conductor Fresnel, tangent
frames, the path tracer (``render``), fitting measured data (``fit``, ``read_measured``) and the GLSL
export.

    >>> import aniso, numpy as np
    >>> m = aniso.Material("brushed-gold")
    >>> wi = aniso.direction(np.radians(30), 0.0); wo = aniso.direction(np.radians(30), np.pi)
    >>> m.eval(wi, wo)          # RGB f(wi, wo), no cosine
"""
from __future__ import annotations

import inspect as _inspect

import numpy as _np

from ._aniso import (  # noqa: F401  (re-exported)
    FitResult,
    Frame,
    Material,
    export,
    export_brdf,
    export_glsl,
    fit,
    fittable_models,
    fresnel,
    glsl_tables,
    metals,
    models,
    preset_source,
    presets,
    read_measured,
    render,
    save_image,
    simd_target,
)
from ._aniso import __version__  # noqa: E402,F401  (the C++ library's, aniso/version.h)

from .fit_db import fit_many  # noqa: E402,F401  (every model on every material: docs/fit-db.md)


def direction(theta, phi):
    """Unit directions from spherical angles in radians (docs/conventions.md): theta from the
    normal z, phi from the tangent x towards y. theta and phi broadcast (NumPy rules); returns
    shape broadcast(theta, phi) + (3,), float64."""
    theta, phi = _np.broadcast_arrays(_np.asarray(theta, dtype=_np.float64), _np.asarray(phi, dtype=_np.float64))
    s = _np.sin(theta)
    return _np.stack([s * _np.cos(phi), s * _np.sin(phi), _np.cos(theta)], axis=-1)


def angles(w):
    """(theta, phi) in radians of directions w (..., 3): the inverse of direction() for unit w."""
    w = _np.asarray(w, dtype=_np.float64)
    return _np.arccos(_np.clip(w[..., 2], -1.0, 1.0)), _np.arctan2(w[..., 1], w[..., 0])


# One constructor per model, ward(alpha_x=0.05, alpha_y=0.3, ...): the keywords are the JSON keys
# of the model's parameter table (aniso.models()), the docstring is that table.
def _make_constructor(model):
    name = model["name"].replace("-", "_")
    lines = [f'A "{model["name"]}" material: {model["title"]} ({model["citation"]}).', "",
             f'Same as Material(model="{model["name"]}", **keys). Keys (the JSON keys; aniso.models()["{model["name"]}"]):', ""]
    params = []
    for p in model["params"]:
        lines.append(f'    {p["name"]} : {p["range"]}, default {p["default"]}')
        lines.append(f'        {p["doc"]}')
        params.append(_inspect.Parameter(p["name"], _inspect.Parameter.KEYWORD_ONLY,
                                         default=p["default_value"] if not p["required"] else _inspect.Parameter.empty))

    def constructor(**keys):
        return Material(model=model["name"], **keys)

    constructor.__name__ = constructor.__qualname__ = name
    constructor.__doc__ = "\n".join(lines)
    constructor.__signature__ = _inspect.Signature(params, return_annotation=Material)
    return name, constructor


_MODEL_CONSTRUCTORS = []
for _model in models().values():
    _name, _fn = _make_constructor(_model)
    globals()[_name] = _fn
    _MODEL_CONSTRUCTORS.append(_name)
del _model, _name, _fn

# Shown as aniso.Material etc. in help() and reprs.
for _cls in (Material, Frame, FitResult):
    _cls.__module__ = "aniso"
del _cls

__all__ = ["Material", "Frame", "FitResult", "presets", "preset_source", "models", "metals", "fresnel", "render",
           "save_image", "fit", "fittable_models", "fit_many", "read_measured", "export_glsl", "glsl_tables", "export_brdf", "export",
           "simd_target", "direction", "angles", *_MODEL_CONSTRUCTORS]
