// aniso/aniso.h: the host API of aniso in one include (CMake target aniso::aniso, pkg-config aniso;
// docs/cpp.md): the kernels (aniso/kernels.h) and
//   materials     MaterialDesc, load_material(spec) for a preset, file or inline JSON,
//                 build_material<T>(desc), the parameter tables, presets, measured metals' IOR
//   errors        InputError, which every reader throws for bad input (the file, key and range)
//   batch         batch::evaluate / pdf / sample over arrays (Highway SIMD, oneTBB)
//   measured      MERL and RGL tensor files as materials, measured samples for fitting
//   albedo        directional albedo of any material
//   image         Image and DisplayImage, image files (PNG, JPEG, HDR, EXR, PFM), tone mapping,
//                 drawing and labels
//   render        scenes from JSON, the path tracer
//   glsl          a material's GLSL (export_glsl) and the GLSL library of the kernels
//   fit / export  fitting a model to samples (Ceres), the renderer exports
// Each part has its own header (include/aniso/<part>/) and CMake component, for a project that
// needs less (find_package(aniso COMPONENTS host) needs neither Embree nor Ceres).
#pragma once

#include "aniso/kernels.h"

#include "aniso/batch/batch.h"
#include "aniso/data/fits.h"
#include "aniso/data/metals.h"
#include "aniso/export/export.h"
#include "aniso/fit/fit.h"
#include "aniso/gl/glsl_export.h"
#include "aniso/gl/glsl_library.h"
#include "aniso/gl/glsl_material.h"
#include "aniso/image/canvas.h"
#include "aniso/image/image.h"
#include "aniso/image/image_io.h"
#include "aniso/image/tonemap.h"
#include "aniso/io/input_error.h"
#include "aniso/io/materials.h"
#include "aniso/io/params.h"
#include "aniso/io/presets.h"
#include "aniso/measured/measured.h"
#include "aniso/measured/merl.h"
#include "aniso/measured/samples.h"
#include "aniso/measured/spectral.h"
#include "aniso/render/gallery.h"
#include "aniso/render/integrator.h"
#include "aniso/render/scene.h"
#include "aniso/rgl/rgl_export.h"
#include "aniso/rgl/rgl_material.h"
#include "aniso/rgl/tensor.h"
#include "aniso/stats/albedo.h"
