// fit/jet.h: what the kernels need to run on ceres::Jet (automatic differentiation).
//
// The kernels call maths functions unqualified after `using std::...`, so Ceres' overloads for
// Jet are found by ADL, and glm's vectors accept Jet because Ceres specialises
// std::numeric_limits for it (glm's static asserts ask for is_iec559). What remains are the typed
// constants of aniso/core/platform.h: `constexpr T kPi<T>` needs a literal type, and Jet is not
// one, so Jet gets (non-constexpr) specialisations with the same values. Include this header
// before instantiating any kernel on a Jet.
#pragma once

#include <ceres/jet.h>

#include "aniso/core/platform.h"

namespace aniso {

template <typename T, int N> inline const ceres::Jet<T, N> kPi<ceres::Jet<T, N>> = ceres::Jet<T, N>(kPi<T>);
template <typename T, int N> inline const ceres::Jet<T, N> kInvPi<ceres::Jet<T, N>> = ceres::Jet<T, N>(kInvPi<T>);
template <typename T, int N> inline const ceres::Jet<T, N> kInv2Pi<ceres::Jet<T, N>> = ceres::Jet<T, N>(kInv2Pi<T>);
template <typename T, int N> inline const ceres::Jet<T, N> kInv4Pi<ceres::Jet<T, N>> = ceres::Jet<T, N>(kInv4Pi<T>);
template <typename T, int N> inline const ceres::Jet<T, N> kPiOver2<ceres::Jet<T, N>> = ceres::Jet<T, N>(kPiOver2<T>);

}  // namespace aniso
