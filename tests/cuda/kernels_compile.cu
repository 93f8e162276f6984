// Compile check: the model kernels build for the GPU from the same headers (ANISO_HD expands to
// __host__ __device__ under nvcc). CI has no GPU, so this translation unit is compiled, not run.
#include "aniso/brdf/material.h"
#include "aniso/core/frame.h"
#include "aniso/tangent/fields.h"

namespace aniso {

__global__ void eval_kernel(const Material* materials, const Vec3* wi, const Vec3* wo, RGB* f, float* pdf,
                            BSDFSampleT<float>* samples, const Frame* frames, int n) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const Material& m = materials[i];
  const Frame frame = frames[i].rotated(0.25f);
  const Vec3 li = frame.to_local(wi[i]), lo = frame.to_local(wo[i]);
  f[i] = m.f(li, lo);
  pdf[i] = m.pdf(li, lo);
  samples[i] = m.sample(lo, 0.5f, Vec2(0.25f, 0.75f));
}

// The methods of aniso/core/kernel.h, every row's: the glossy filter's roughening and the GGX
// question.
__global__ void kernel_methods(Material* materials, const float* alpha, float* alpha_x, int n) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  materials[i].regularize(alpha[i]);
  const GgxDistributionT<float> d = materials[i].ggx_distribution();
  alpha_x[i] = d.part == GgxPart::None ? 0.0f : d.alpha_x;
}

// The tangent fields the renderer uses, on the GPU.
__global__ void tangent_kernel(const TangentFieldT<float>* fields, const SurfacePointT<float>* points, Frame* frames, int n) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  frames[i] = tangent_frame(fields[i], points[i]);
  const Vec2 d = TangentMap_FromDoubled(TangentMap_ToDoubled(TangentMap_DecodeXY(0.2f, 0.9f)));
  frames[i].t += Vec3(d.x, d.y, TangentMap_DecodeAngle(0.3f).x) * 0.0f;
}

}  // namespace aniso
