// batch/kernels-inl.h: everything src/batch/batch.cpp compiles once per SIMD target (through
// hwy/foreach_target.h): the SIMD math (simd_math-inl.h), one twin per model (twins/), the loops
// (loops-inl.h) and the dispatch from a material to its twin (dispatch-inl.h). The argument
// blocks, shared by all targets, are in args.h.
// (No include guard: each file below has Highway's per-target guard.)
#include "batch/args.h"
#include "batch/dispatch-inl.h"
