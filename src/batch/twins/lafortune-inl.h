// batch/twins/lafortune-inl.h: the Highway twin of include/aniso/brdf/lafortune.h (Lafortune); the
// rules every twin follows are in src/batch/simd_math-inl.h.
// Per-target include guard, the pattern Highway documents for -inl.h files.
#if defined(ANISO_BATCH_TWINS_LAFORTUNE_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef ANISO_BATCH_TWINS_LAFORTUNE_INL_H_
#undef ANISO_BATCH_TWINS_LAFORTUNE_INL_H_
#else
#define ANISO_BATCH_TWINS_LAFORTUNE_INL_H_
#endif

#include "batch/simd_math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace aniso::batch::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// --- lafortune.h twins -------------------------------------------------------------------------

template <typename T> struct LafortuneLobeK {
  T cx[3], cy[3], cz[3], n[3], scale[3], log_scale[3];
  LafortuneLobeK() = default;
  explicit LafortuneLobeK(const LafortuneLobeT<T>& l) {
    using std::log;
    for (int c = 0; c < 3; ++c) {
      cx[c] = l.cx[c], cy[c] = l.cy[c], cz[c] = l.cz[c], n[c] = l.n[c], scale[c] = l.scale[c];
      log_scale[c] = l.scale[c] > T(0) ? log(l.scale[c]) : T(0);
    }
  }
  // Lafortune_Lobe(base, n, scale) = exp(n log(base) + log(scale)) for base > 0 and scale > 0.
  template <class D> HWY_INLINE V<D> Lobe(D d, V<D> base, int c) const {
    if (!(scale[c] > T(0))) return hn::Zero(d);
    const M<D> pos = hn::Gt(base, hn::Zero(d));
    const V<D> safe = hn::IfThenElse(pos, base, K(d, 1));
    return hn::IfThenElseZero(pos, ExpNaN(d, hn::Add(hn::Mul(K(d, n[c]), hn::Log(d, safe)), K(d, log_scale[c]))));
  }
  // LafortuneLobeT::eval, channel c, p = wi * wo.
  template <class D> HWY_INLINE V<D> Eval(D d, const V3<D>& p, int c) const {
    const V<D> base = hn::Add(hn::Add(hn::Mul(K(d, cx[c]), p.x), hn::Mul(K(d, cy[c]), p.y)), hn::Mul(K(d, cz[c]), p.z));
    return Lobe(d, base, c);
  }
  template <class D> HWY_INLINE V3<D> Axis(D d, const V3<D>& wo, int c) const {
    return {hn::Mul(K(d, cx[c]), wo.x), hn::Mul(K(d, cy[c]), wo.y), hn::Mul(K(d, cz[c]), wo.z)};
  }
  // channel_weight.
  template <class D> HWY_INLINE V<D> ChannelWeight(D d, const V3<D>& wo, int c) const {
    if (!(scale[c] > T(0))) return hn::Zero(d);
    const V3<D> a = Axis(d, wo, c);
    const V<D> len = hn::Sqrt(Dot(a, a));
    const M<D> ok = hn::And(hn::Gt(len, hn::Zero(d)), hn::Gt(a.z, hn::Zero(d)));
    const V<D> safe_len = hn::IfThenElse(ok, len, K(d, 1));
    const V<D> w = hn::Div(hn::Mul(hn::Mul(hn::Mul(Lobe(d, safe_len, c), hn::Div(a.z, safe_len)), K(d, T(2))), K(d, kPi<T>)),
                           K(d, (n[c] + T(1)) * T(3)));
    return hn::IfThenElseZero(ok, w);
  }
  // channel_pdf.
  template <class D> HWY_INLINE V<D> ChannelPdf(D d, const V3<D>& wi, const V3<D>& wo, int c) const {
    const V3<D> a = Axis(d, wo, c);
    const V<D> len2 = Dot(a, a);
    const M<D> ok = hn::Gt(len2, hn::Zero(d));
    const V<D> cos_axis = hn::Div(Dot(a, wi), hn::Sqrt(hn::IfThenElse(ok, len2, K(d, 1))));
    return hn::IfThenElseZero(ok, CosinePowerPdf(d, cos_axis, K(d, n[c])));
  }
};

template <typename T> struct LafortuneK {
  T rho_pi[3], rho_avg;
  int lobe_count;
  LafortuneLobeK<T> lobes[kLafortuneMaxLobes];
  explicit LafortuneK(const LafortuneT<T>& m) : lobe_count(m.lobe_count) {
    for (int c = 0; c < 3; ++c) rho_pi[c] = m.rho_d[c] * kInvPi<T>;
    rho_avg = average(m.rho_d);
    for (int i = 0; i < lobe_count; ++i) lobes[i] = LafortuneLobeK<T>(m.lobes[i]);
  }
  template <class D> HWY_INLINE RGBV<D> F(D d, const V3<D>& wi, const V3<D>& wo) const {
    const M<D> upper = UpperBoth(d, wi, wo);
    const V3<D> p{hn::Mul(wi.x, wo.x), hn::Mul(wi.y, wo.y), hn::Mul(wi.z, wo.z)};
    RGBV<D> out;
    for (int c = 0; c < 3; ++c) {
      V<D> f = K(d, rho_pi[c]);
      for (int i = 0; i < lobe_count; ++i) f = hn::Add(f, lobes[i].Eval(d, p, c));
      out.c[c] = hn::IfThenElseZero(upper, f);
    }
    return out;
  }
  // LafortuneT::sample's direction: walk the cumulative weights with uc (cosine first, then each
  // (lobe, channel) of positive weight while the target is not negative), per lane with masks.
  template <class D> HWY_INLINE V3<D> SampleDirection(D d, const V3<D>& wo, V<D> uc, V<D> u0, V<D> u1, M<D>& /*ok*/) const {
    V<D> w[kLafortuneMaxLobes][3];
    V<D> total = hn::Zero(d);
    for (int i = 0; i < lobe_count; ++i)
      for (int c = 0; c < 3; ++c) total = hn::Add(total, w[i][c] = lobes[i].ChannelWeight(d, wo, c));
    const V<D> cos_w = hn::Add(K(d, rho_avg), hn::Mul(K(d, T(LafortuneT<T>::kDefensiveShare)), total));
    const V<D> cosine = hn::IfThenElse(hn::Or(hn::Gt(cos_w, hn::Zero(d)), hn::Gt(total, hn::Zero(d))), cos_w, K(d, 1));
    V<D> target = hn::Sub(hn::Mul(uc, hn::Add(cosine, total)), cosine);
    M<D> chosen = hn::Lt(K(d, 1), hn::Zero(d));  // all false
    V3<D> axis{hn::Zero(d), hn::Zero(d), K(d, 1)};
    V<D> n = K(d, 1);
    for (int i = 0; i < lobe_count; ++i)
      for (int c = 0; c < 3; ++c) {
        const M<D> take = hn::AndNot(hn::Lt(target, hn::Zero(d)), hn::Gt(w[i][c], hn::Zero(d)));
        const V3<D> a = lobes[i].Axis(d, wo, c);
        axis = {hn::IfThenElse(take, a.x, axis.x), hn::IfThenElse(take, a.y, axis.y), hn::IfThenElse(take, a.z, axis.z)};
        n = hn::IfThenElse(take, K(d, lobes[i].n[c]), n);
        chosen = hn::Or(chosen, take);
        target = hn::IfThenElse(take, hn::Sub(target, w[i][c]), target);
      }
    const V<D> len = hn::Sqrt(Dot(axis, axis));
    const V3<D> a_unit{hn::Div(axis.x, len), hn::Div(axis.y, len), hn::Div(axis.z, len)};
    const V3<D> wl = CosinePowerSample(d, a_unit, n, u0, u1);
    const V3<D> wc = CosineHemisphere(d, u0, u1);
    return {hn::IfThenElse(chosen, wl.x, wc.x), hn::IfThenElse(chosen, wl.y, wc.y), hn::IfThenElse(chosen, wl.z, wc.z)};
  }
  // pdf(sampling_weights(wo), wi, wo).
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    V<D> w[kLafortuneMaxLobes][3];
    V<D> total = hn::Zero(d);
    for (int i = 0; i < lobe_count; ++i)
      for (int c = 0; c < 3; ++c) total = hn::Add(total, w[i][c] = lobes[i].ChannelWeight(d, wo, c));
    const V<D> cos_w = hn::Add(K(d, rho_avg), hn::Mul(K(d, T(LafortuneT<T>::kDefensiveShare)), total));
    const V<D> cosine = hn::IfThenElse(hn::Or(hn::Gt(cos_w, hn::Zero(d)), hn::Gt(total, hn::Zero(d))), cos_w, K(d, 1));
    V<D> p = hn::Mul(cosine, CosineHemispherePdf(d, wi.z));
    for (int i = 0; i < lobe_count; ++i)
      for (int c = 0; c < 3; ++c)
        p = hn::Add(p, hn::IfThenElseZero(hn::Gt(w[i][c], hn::Zero(d)), hn::Mul(w[i][c], lobes[i].ChannelPdf(d, wi, wo, c))));
    return hn::IfThenElseZero(UpperBoth(d, wi, wo), hn::Div(p, hn::Add(cosine, total)));
  }
};

template <typename T> struct SimdTwin<LafortuneT<T>> { using type = LafortuneK<T>; };

}  // namespace aniso::batch::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard
