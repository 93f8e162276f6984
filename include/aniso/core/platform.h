// aniso/core/platform.h: the one host/device macro, and the numeric constants every kernel uses.
//
// ANISO_HD marks a function that compiles both for the CPU and, under nvcc, for the GPU
// (pbrt-v4's PBRT_CPU_GPU idea). Kernels are header-only, allocate nothing and throw nothing.
#pragma once

#if defined(__CUDACC__)
#define ANISO_HD __host__ __device__
#else
#define ANISO_HD
#endif

#define ANISO_INLINE ANISO_HD inline

namespace aniso {

template <typename T> inline constexpr T kPi = T(3.14159265358979323846264338327950288);
template <typename T> inline constexpr T kInvPi = T(0.318309886183790671537767526745028724);
template <typename T> inline constexpr T kInv2Pi = T(0.159154943091895335768883763372514362);
template <typename T> inline constexpr T kInv4Pi = T(0.0795774715459476678844418816862571810);
template <typename T> inline constexpr T kPiOver2 = T(1.57079632679489661923132169163975144);

}  // namespace aniso
