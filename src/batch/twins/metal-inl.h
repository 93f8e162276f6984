// batch/twins/metal-inl.h: the Highway twin of include/aniso/brdf/metal.h (metal); the
// rules every twin follows are in src/batch/simd_math-inl.h.
// Per-target include guard, the pattern Highway documents for -inl.h files.
#if defined(ANISO_BATCH_TWINS_METAL_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef ANISO_BATCH_TWINS_METAL_INL_H_
#undef ANISO_BATCH_TWINS_METAL_INL_H_
#else
#define ANISO_BATCH_TWINS_METAL_INL_H_
#endif

#include "batch/simd_math-inl.h"
#include "batch/twins/ashikhmin_shirley-inl.h"
#include "batch/twins/ggx-inl.h"
#include "batch/twins/lafortune-inl.h"
#include "batch/twins/ward-inl.h"

HWY_BEFORE_NAMESPACE();
namespace aniso::batch::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// --- metal.h twins -----------------------------------------------------------------------------

template <typename T> struct MetalK {
  T eta[3], k[3], specular_weight[3];
  SpecularLobeKind kind;
  WardLobeK<T> ward;
  ASLobeK<T> as;
  GGXLobeK<T> ggx;
  bool has_dd;
  LafortuneLobeK<T> dd;
  explicit MetalK(const MetalT<T>& m)
      : kind(m.lobe_kind),
        ward(m.ward),
        as(m.ashikhmin_shirley),
        ggx(m.ggx),
        has_dd(m.has_directional_diffuse),
        dd(m.directional_diffuse) {
    for (int c = 0; c < 3; ++c) eta[c] = m.eta[c], k[c] = m.k[c], specular_weight[c] = m.specular_weight[c];
  }
  template <class D> HWY_INLINE V<D> Specular(D d, const V3<D>& wi, const V3<D>& wo) const {
    switch (kind) {
      case SpecularLobeKind::Ward: return ward.Eval(d, wi, wo);
      case SpecularLobeKind::AshikhminShirley: return as.Eval(d, wi, wo);
      default: return ggx.Eval(d, wi, wo);
    }
  }
  template <class D> HWY_INLINE V<D> SpecularPdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    switch (kind) {
      case SpecularLobeKind::Ward: return ward.Pdf(d, wi, wo);
      case SpecularLobeKind::AshikhminShirley: return as.Pdf(d, wi, wo);
      default: return ggx.Pdf(d, wi, wo);
    }
  }
  template <class D> HWY_INLINE V3<D> SpecularSample(D d, const V3<D>& wo, V<D> u0, V<D> u1) const {
    switch (kind) {
      case SpecularLobeKind::Ward: return ward.Sample(d, wo, u0, u1);
      case SpecularLobeKind::AshikhminShirley: return as.Sample(d, wo, u0, u1);
      default: return ggx.Sample(d, wo, u0, u1);
    }
  }
  // specular_probability(wo).
  template <class D> HWY_INLINE V<D> SpecularProbability(D d, const V3<D>& wo, V<D> ws[3]) const {
    V<D> fw[3];
    for (int c = 0; c < 3; ++c) fw[c] = hn::Mul(K(d, specular_weight[c]), F_Conductor(d, wo.z, eta[c], k[c]));
    const V<D> s = Average(d, fw[0], fw[1], fw[2]);
    V<D> dsum = hn::Zero(d);
    for (int c = 0; c < 3; ++c) ws[c] = hn::Zero(d);
    if (has_dd)
      for (int c = 0; c < 3; ++c) dsum = hn::Add(dsum, ws[c] = dd.ChannelWeight(d, wo, c));
    const V<D> sd = hn::Add(s, dsum);
    return hn::IfThenElse(hn::Gt(sd, hn::Zero(d)), hn::Div(s, sd), K(d, 1));
  }
  // MetalT::sample's direction: the specular lobe with probability ps, else a channel of the
  // directional-diffuse lobe picked by weight with uc rescaled (first c with target < ws[c], else
  // the last positive one); no weight at all is "no sample".
  template <class D> HWY_INLINE V3<D> SampleDirection(D d, const V3<D>& wo, V<D> uc, V<D> u0, V<D> u1, M<D>& ok) const {
    V<D> ws[3];
    const V<D> ps = SpecularProbability(d, wo, ws);
    const M<D> spec = hn::Lt(uc, ps);
    const V3<D> w_spec = SpecularSample(d, wo, u0, u1);
    if (!has_dd) {
      ok = hn::And(ok, spec);  // ps = 1 here unless every weight is 0
      return w_spec;
    }
    const V<D> wsum = hn::Add(hn::Add(ws[0], ws[1]), ws[2]);
    V<D> target = hn::Mul(hn::Div(hn::Sub(uc, ps), hn::Sub(K(d, 1), ps)), wsum);
    M<D> found = hn::Lt(K(d, 1), hn::Zero(d));  // all false
    V<D> chosen = K(d, 2);
    for (int c = 0; c < 3; ++c) {
      const M<D> hit = hn::AndNot(found, hn::And(hn::Gt(ws[c], hn::Zero(d)), hn::Lt(target, ws[c])));
      chosen = hn::IfThenElse(hit, K(d, T(c)), chosen);
      found = hn::Or(found, hit);
      target = hn::IfThenElse(found, target, hn::Sub(target, ws[c]));
    }
    // while (chosen > 0 && !(ws[chosen] > 0)) --chosen, for the lanes that found nothing.
    const V<D> last_positive =
        hn::IfThenElse(hn::Gt(ws[2], hn::Zero(d)), K(d, 2), hn::IfThenElse(hn::Gt(ws[1], hn::Zero(d)), K(d, 1), hn::Zero(d)));
    chosen = hn::IfThenElse(found, chosen, last_positive);
    V3<D> axis{hn::Zero(d), hn::Zero(d), hn::Zero(d)};
    V<D> n = hn::Zero(d);
    for (int c = 0; c < 3; ++c) {
      const M<D> is_c = hn::Eq(chosen, K(d, T(c)));
      const V3<D> a = dd.Axis(d, wo, c);
      axis = {hn::IfThenElse(is_c, a.x, axis.x), hn::IfThenElse(is_c, a.y, axis.y), hn::IfThenElse(is_c, a.z, axis.z)};
      n = hn::IfThenElse(is_c, K(d, dd.n[c]), n);
    }
    const V<D> len = hn::Sqrt(Dot(axis, axis));
    const V3<D> w_dd = CosinePowerSample(d, V3<D>{hn::Div(axis.x, len), hn::Div(axis.y, len), hn::Div(axis.z, len)}, n, u0, u1);
    ok = hn::And(ok, hn::Or(spec, hn::Gt(wsum, hn::Zero(d))));
    return {hn::IfThenElse(spec, w_spec.x, w_dd.x), hn::IfThenElse(spec, w_spec.y, w_dd.y),
            hn::IfThenElse(spec, w_spec.z, w_dd.z)};
  }
  template <class D> HWY_INLINE RGBV<D> F(D d, const V3<D>& wi, const V3<D>& wo) const {
    const M<D> upper = UpperBoth(d, wi, wo);
    const V3<D> h = Normalize(d, Add3(wi, wo));
    const V<D> cos_ih = Dot(wi, h);
    const V<D> s = Specular(d, wi, wo);
    const V3<D> p{hn::Mul(wi.x, wo.x), hn::Mul(wi.y, wo.y), hn::Mul(wi.z, wo.z)};
    RGBV<D> out;
    for (int c = 0; c < 3; ++c) {
      V<D> f = hn::Mul(hn::Mul(K(d, specular_weight[c]), F_Conductor(d, cos_ih, eta[c], k[c])), s);
      if (has_dd) f = hn::Add(f, dd.Eval(d, p, c));
      out.c[c] = hn::IfThenElseZero(upper, f);
    }
    return out;
  }
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    // specular_probability(wo)
    V<D> fw[3];
    for (int c = 0; c < 3; ++c) fw[c] = hn::Mul(K(d, specular_weight[c]), F_Conductor(d, wo.z, eta[c], k[c]));
    const V<D> s = Average(d, fw[0], fw[1], fw[2]);
    V<D> dsum = hn::Zero(d), ws[3];
    if (has_dd)
      for (int c = 0; c < 3; ++c) dsum = hn::Add(dsum, ws[c] = dd.ChannelWeight(d, wo, c));
    const V<D> sd = hn::Add(s, dsum);
    const V<D> ps = hn::IfThenElse(hn::Gt(sd, hn::Zero(d)), hn::Div(s, sd), K(d, 1));
    V<D> p = hn::Mul(ps, SpecularPdf(d, wi, wo));
    if (has_dd) {
      // directional_diffuse_pdf
      V<D> wsum = hn::Zero(d), pd = hn::Zero(d);
      for (int c = 0; c < 3; ++c) {
        const M<D> pos = hn::Gt(ws[c], hn::Zero(d));
        wsum = hn::Add(wsum, hn::IfThenElseZero(pos, ws[c]));
        pd = hn::Add(pd, hn::IfThenElseZero(pos, hn::Mul(ws[c], dd.ChannelPdf(d, wi, wo, c))));
      }
      const M<D> wpos = hn::Gt(wsum, hn::Zero(d));
      const V<D> ddp = hn::IfThenElseZero(wpos, hn::Div(pd, hn::IfThenElse(wpos, wsum, K(d, 1))));
      p = hn::Add(p, hn::IfThenElseZero(hn::Lt(ps, K(d, 1)), hn::Mul(hn::Sub(K(d, 1), ps), ddp)));
    }
    return hn::IfThenElseZero(UpperBoth(d, wi, wo), p);
  }
};

template <typename T> struct SimdTwin<MetalT<T>> { using type = MetalK<T>; };

}  // namespace aniso::batch::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard
