// aniso/kernels.h: every BRDF kernel, MaterialT<T> (every model behind one value type), the
// shading frame, sampling helpers, tangent fields and the version: the header-only part of aniso
// (CMake target aniso::kernels, pkg-config aniso-kernels; docs/cpp.md). It needs glm only and
// compiles for the CPU and, under nvcc, for CUDA (ANISO_HD, aniso/core/platform.h). Define
// GLM_FORCE_XYZW_ONLY before including glm anywhere (the targets and .pc files do).
#pragma once

#include "aniso/brdf/fresnel.h"
#include "aniso/brdf/material.h"
#include "aniso/brdf/registry.h"
#include "aniso/core/frame.h"
#include "aniso/core/lobe_mixture.h"
#include "aniso/core/math.h"
#include "aniso/core/platform.h"
#include "aniso/core/sampling.h"
#include "aniso/tangent/fields.h"
#include "aniso/version.h"
