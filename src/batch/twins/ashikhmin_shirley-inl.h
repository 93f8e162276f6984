// batch/twins/ashikhmin_shirley-inl.h: the Highway twin of include/aniso/brdf/ashikhmin_shirley.h (Ashikhmin-Shirley); the
// rules every twin follows are in src/batch/simd_math-inl.h.
// Per-target include guard, the pattern Highway documents for -inl.h files.
#if defined(ANISO_BATCH_TWINS_ASHIKHMIN_SHIRLEY_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef ANISO_BATCH_TWINS_ASHIKHMIN_SHIRLEY_INL_H_
#undef ANISO_BATCH_TWINS_ASHIKHMIN_SHIRLEY_INL_H_
#else
#define ANISO_BATCH_TWINS_ASHIKHMIN_SHIRLEY_INL_H_
#endif

#include "batch/simd_math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace aniso::batch::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// --- ashikhmin_shirley.h twins -----------------------------------------------------------------

template <typename T> struct ASLobeK {
  T nu, nv, spec_norm, half_norm;
  explicit ASLobeK(const AshikhminShirleyLobeT<T>& l)
      : nu(l.n_u),
        nv(l.n_v),
        spec_norm(std::sqrt((l.n_u + T(1)) * (l.n_v + T(1))) / (T(8) * kPi<T>)),
        half_norm(std::sqrt((l.n_u + T(1)) * (l.n_v + T(1))) * kInv2Pi<T>) {}
  // AS_Exponent.
  template <class D> HWY_INLINE V<D> Exponent(D d, V<D> hot, V<D> hob) const {
    const V<D> s2 = hn::Add(hn::Mul(hot, hot), hn::Mul(hob, hob));
    const V<D> e = hn::Div(hn::Add(hn::Mul(hn::Mul(K(d, nu), hot), hot), hn::Mul(hn::Mul(K(d, nv), hob), hob)), s2);
    return hn::IfThenElse(hn::Gt(s2, hn::Zero(d)), e, K(d, nu));
  }
  // AS_Specular for a unit h (h.z > 0 above the horizon), 0 unless h.wi > 0.
  template <class D> HWY_INLINE V<D> Specular(D d, const V3<D>& h, V<D> hol, V<D> nol, V<D> nov) const {
    const V<D> p = PowPositive(d, h.z, Exponent(d, h.x, h.y));
    return hn::IfThenElseZero(hn::Gt(hol, hn::Zero(d)), hn::Div(hn::Mul(K(d, spec_norm), p), hn::Mul(hol, hn::Max(nol, nov))));
  }
  template <class D> HWY_INLINE V<D> Eval(D d, const V3<D>& wi, const V3<D>& wo) const {
    const V3<D> h = Normalize(d, Add3(wi, wo));
    return Specular(d, h, Dot(h, wi), wi.z, wo.z);
  }
  // AshikhminShirleyLobeT::sample with AS_SampleHalf (Eqs. 9-10): the four quarters of u.x become
  // masks over one atan; tan(x) as sin / cos (own SIMD version: Highway 1.0 has no Tan).
  template <class D> HWY_INLINE V3<D> Sample(D d, const V3<D>& wo, V<D> u0, V<D> u1) const {
    const V<D> one = K(d, 1), two = K(d, 2);
    const V<D> ratio = K(d, std::sqrt((nu + T(1)) / (nv + T(1))));
    const V<D> q = hn::Mul(K(d, T(4)), u0);
    const M<D> q1 = hn::Lt(q, one), q2 = hn::Lt(q, two), q3 = hn::Lt(q, K(d, 3));
    // The argument of tan(pi / 2 x) in each quarter: q, 2 - q, q - 2, 4 - q.
    const V<D> x =
        hn::IfThenElse(q1, q, hn::IfThenElse(q2, hn::Sub(two, q), hn::IfThenElse(q3, hn::Sub(q, two), hn::Sub(K(d, 4), q))));
    const V<D> arg = hn::Mul(K(d, kPiOver2<T>), x);
    const V<D> base = hn::Atan(d, hn::Mul(ratio, hn::Div(SinNaN(d, arg), CosNaN(d, arg))));
    const V<D> phi =
        hn::IfThenElse(q1, base,
                       hn::IfThenElse(q2, hn::Sub(K(d, kPi<T>), base),
                                      hn::IfThenElse(q3, hn::Add(K(d, kPi<T>), base), hn::Sub(K(d, T(2) * kPi<T>), base))));
    const V<D> c = CosNaN(d, phi), s = SinNaN(d, phi);
    const V<D> e = hn::Add(hn::Mul(hn::Mul(K(d, nu), c), c), hn::Mul(hn::Mul(K(d, nv), s), s));
    const V<D> cos_t = PowPositive(d, hn::Sub(one, u1), hn::Div(one, hn::Add(e, one)));
    const V<D> sin_t = SafeSqrt(d, hn::Sub(one, hn::Mul(cos_t, cos_t)));
    return ReflectAbout(d, wo, V3<D>{hn::Mul(sin_t, c), hn::Mul(sin_t, s), cos_t});
  }
  // AshikhminShirleyLobeT::pdf with AS_PdfHalf.
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    const V3<D> h = Normalize(d, Add3(wi, wo));
    const V<D> woh = Dot(wo, h);
    const M<D> hz_pos = hn::Gt(h.z, hn::Zero(d));
    const V<D> ph = hn::IfThenElseZero(
        hz_pos, hn::Mul(K(d, half_norm), PowPositive(d, hn::IfThenElse(hz_pos, h.z, K(d, 1)), Exponent(d, h.x, h.y))));
    return hn::IfThenElseZero(hn::Gt(woh, hn::Zero(d)), hn::Div(ph, hn::Mul(K(d, T(4)), woh)));
  }
};

// AS_Diffuse.
template <class D> HWY_INLINE V<D> AS_Diffuse(D d, V<D> nol, V<D> nov) {
  using T = hn::TFromD<D>;
  const V<D> a = hn::Sub(K(d, 1), hn::Mul(nol, K(d, T(0.5)))), b = hn::Sub(K(d, 1), hn::Mul(nov, K(d, T(0.5))));
  const V<D> a5 = hn::Mul(hn::Mul(hn::Mul(hn::Mul(a, a), a), a), a);
  const V<D> b5 = hn::Mul(hn::Mul(hn::Mul(hn::Mul(b, b), b), b), b);
  return hn::Mul(hn::Mul(K(d, T(28) / (T(23) * kPi<T>)), hn::Sub(K(d, 1), a5)), hn::Sub(K(d, 1), b5));
}

template <typename T> struct AshikhminShirleyK {
  T rs[3], ks[3], diffuse[3], kd_pi[3], diffuse_weight;
  ASLobeK<T> lobe;
  explicit AshikhminShirleyK(const AshikhminShirleyT<T>& m) : lobe(m.lobe) {
    for (int c = 0; c < 3; ++c) {
      rs[c] = m.rs[c];
      ks[c] = m.ks_scale[c];
      diffuse[c] = m.rd[c] * (T(1) - m.rs[c]);
      kd_pi[c] = m.kd[c] * kInvPi<T>;
    }
    diffuse_weight = average(m.rd * (RGBT<T>(T(1)) - m.rs)) + average(m.kd);
  }
  template <class D> HWY_INLINE RGBV<D> F(D d, const V3<D>& wi, const V3<D>& wo) const {
    const M<D> upper = UpperBoth(d, wi, wo);
    const V3<D> h = Normalize(d, Add3(wi, wo));
    const V<D> woh_i = Dot(wi, h);
    const V<D> spec = lobe.Specular(d, h, Dot(h, wi), wi.z, wo.z);
    const V<D> diff = AS_Diffuse(d, wi.z, wo.z);
    RGBV<D> out;
    for (int c = 0; c < 3; ++c) {
      const V<D> f =
          hn::Add(hn::Add(hn::Mul(hn::Mul(K(d, ks[c]), F_Schlick(d, rs[c], woh_i)), spec), hn::Mul(K(d, diffuse[c]), diff)),
                  K(d, kd_pi[c]));
      out.c[c] = hn::IfThenElseZero(upper, f);
    }
    return out;
  }
  // specular_probability(wo): Schlick at wo.z, averaged over the channels.
  template <class D> HWY_INLINE V<D> SpecularProbability(D d, const V3<D>& wo) const {
    const V<D> sw = Average(d, hn::Mul(K(d, ks[0]), F_Schlick(d, rs[0], wo.z)), hn::Mul(K(d, ks[1]), F_Schlick(d, rs[1], wo.z)),
                            hn::Mul(K(d, ks[2]), F_Schlick(d, rs[2], wo.z)));
    return SpecularShare(d, K(d, diffuse_weight), sw);
  }
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    const V<D> p_spec = SpecularProbability(d, wo);
    return hn::IfThenElseZero(UpperBoth(d, wi, wo), MixturePdf(d, p_spec, wi.z, lobe.Pdf(d, wi, wo)));
  }
};

template <typename T> struct SimdTwin<AshikhminShirleyT<T>> { using type = AshikhminShirleyK<T>; };

}  // namespace aniso::batch::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard
