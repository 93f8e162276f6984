// batch/twins/ggx-inl.h: the Highway twin of include/aniso/brdf/ggx.h (anisotropic GGX); the
// rules every twin follows are in src/batch/simd_math-inl.h.
// Per-target include guard, the pattern Highway documents for -inl.h files.
#if defined(ANISO_BATCH_TWINS_GGX_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef ANISO_BATCH_TWINS_GGX_INL_H_
#undef ANISO_BATCH_TWINS_GGX_INL_H_
#else
#define ANISO_BATCH_TWINS_GGX_INL_H_
#endif

#include "batch/simd_math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace aniso::batch::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// --- ggx.h twins -------------------------------------------------------------------------------

template <typename T> struct GGXLobeK {
  T ax, ay, axay;
  explicit GGXLobeK(const GGXLobeT<T>& l) : ax(l.alpha_x), ay(l.alpha_y), axay(l.alpha_x * l.alpha_y) {}
  // D_GGX_Aniso.
  template <class D> HWY_INLINE V<D> Dist(D d, const V3<D>& h) const {
    const V<D> s = hn::Add(hn::Add(Sqr<D>(hn::Div(h.x, K(d, ax))), Sqr<D>(hn::Div(h.y, K(d, ay)))), Sqr<D>(h.z));
    return hn::Div(K(d, kInvPi<T>), hn::Mul(hn::Mul(K(d, axay), s), s));
  }
  // Lambda_GGX_Aniso.
  template <class D> HWY_INLINE V<D> Lambda(D d, const V3<D>& w) const {
    const V<D> tan2 = hn::Div(hn::Add(Sqr<D>(hn::Mul(K(d, ax), w.x)), Sqr<D>(hn::Mul(K(d, ay), w.y))), Sqr<D>(w.z));
    return hn::Mul(hn::Sub(hn::Sqrt(hn::Add(K(d, 1), tan2)), K(d, 1)), K(d, T(0.5)));
  }
  template <class D> HWY_INLINE V<D> EvalH(D d, const V3<D>& h, const V3<D>& wi, const V3<D>& wo) const {
    const V<D> g2 = hn::Div(K(d, 1), hn::Add(hn::Add(K(d, 1), Lambda(d, wi)), Lambda(d, wo)));
    return hn::Div(hn::Mul(Dist(d, h), g2), hn::Mul(hn::Mul(K(d, T(4)), wi.z), wo.z));
  }
  template <class D> HWY_INLINE V<D> Eval(D d, const V3<D>& wi, const V3<D>& wo) const {
    return EvalH(d, Normalize(d, Add3(wi, wo)), wi, wo);
  }
  // GGXLobeT::sample with GGX_SampleVisibleNormal (Heitz 2018, Listing 1), step for step.
  template <class D> HWY_INLINE V3<D> Sample(D d, const V3<D>& wo, V<D> u0, V<D> u1) const {
    const V<D> one = K(d, 1);
    const V3<D> vh = Normalize(d, V3<D>{hn::Mul(K(d, ax), wo.x), hn::Mul(K(d, ay), wo.y), wo.z});
    const V<D> lensq = hn::Add(hn::Mul(vh.x, vh.x), hn::Mul(vh.y, vh.y));
    const M<D> has_len = hn::Gt(lensq, hn::Zero(d));
    const V<D> root = hn::Sqrt(hn::IfThenElse(has_len, lensq, one));
    const V3<D> t1{hn::IfThenElse(has_len, hn::Div(hn::Neg(vh.y), root), one), hn::IfThenElseZero(has_len, hn::Div(vh.x, root)),
                   hn::Zero(d)};
    // glm::cross(vh, t1)
    const V3<D> t2{hn::Sub(hn::Mul(vh.y, t1.z), hn::Mul(t1.y, vh.z)), hn::Sub(hn::Mul(vh.z, t1.x), hn::Mul(t1.z, vh.x)),
                   hn::Sub(hn::Mul(vh.x, t1.y), hn::Mul(t1.x, vh.y))};
    const V<D> r = hn::Sqrt(u0);
    const V<D> phi = hn::Mul(K(d, T(2) * kPi<T>), u1);
    const V<D> p1 = hn::Mul(r, CosNaN(d, phi));
    V<D> p2 = hn::Mul(r, SinNaN(d, phi));
    const V<D> s = hn::Mul(K(d, T(0.5)), hn::Add(one, vh.z));
    p2 = hn::Add(hn::Mul(hn::Sub(one, s), SafeSqrt(d, hn::Sub(one, hn::Mul(p1, p1)))), hn::Mul(s, p2));
    const V<D> q = SafeSqrt(d, hn::Sub(hn::Sub(one, hn::Mul(p1, p1)), hn::Mul(p2, p2)));
    const V3<D> nh{hn::Add(hn::Add(hn::Mul(p1, t1.x), hn::Mul(p2, t2.x)), hn::Mul(q, vh.x)),
                   hn::Add(hn::Add(hn::Mul(p1, t1.y), hn::Mul(p2, t2.y)), hn::Mul(q, vh.y)),
                   hn::Add(hn::Add(hn::Mul(p1, t1.z), hn::Mul(p2, t2.z)), hn::Mul(q, vh.z))};
    const V3<D> h = Normalize(
        d, V3<D>{hn::Mul(K(d, ax), nh.x), hn::Mul(K(d, ay), nh.y), hn::IfThenElseZero(hn::Gt(nh.z, hn::Zero(d)), nh.z)});
    return ReflectAbout(d, wo, h);
  }
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    const V3<D> h = Normalize(d, Add3(wi, wo));
    const M<D> ok = hn::And(hn::Gt(Dot(wo, h), hn::Zero(d)), hn::Gt(h.z, hn::Zero(d)));
    const V<D> g1 = hn::Div(K(d, 1), hn::Add(K(d, 1), Lambda(d, wo)));
    return hn::IfThenElseZero(ok, hn::Div(hn::Mul(g1, Dist(d, h)), hn::Mul(K(d, T(4)), wo.z)));
  }
};

template <typename T> struct GGXK {
  T f0[3], f90[3], kd_pi[3], diffuse_weight;
  GGXLobeK<T> lobe;
  explicit GGXK(const GGXT<T>& m) : lobe(m.lobe) {
    for (int c = 0; c < 3; ++c) f0[c] = m.f0[c], f90[c] = m.f90[c], kd_pi[c] = m.kd[c] * kInvPi<T>;
    diffuse_weight = average(m.kd);
  }
  template <class D> HWY_INLINE RGBV<D> F(D d, const V3<D>& wi, const V3<D>& wo) const {
    const M<D> upper = UpperBoth(d, wi, wo);
    const V3<D> h = Normalize(d, Add3(wi, wo));
    const V<D> l = lobe.EvalH(d, h, wi, wo);
    const V<D> cos_ih = Dot(wi, h);
    RGBV<D> out;
    for (int c = 0; c < 3; ++c)
      out.c[c] = hn::IfThenElseZero(upper, hn::Add(hn::Mul(F_Schlick(d, f0[c], f90[c], cos_ih), l), K(d, kd_pi[c])));
    return out;
  }
  template <class D> HWY_INLINE V<D> SpecularProbability(D d, const V3<D>& wo) const {
    const V<D> sw =
        Average(d, F_Schlick(d, f0[0], f90[0], wo.z), F_Schlick(d, f0[1], f90[1], wo.z), F_Schlick(d, f0[2], f90[2], wo.z));
    return SpecularShare(d, K(d, diffuse_weight), sw);
  }
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    const V<D> p_spec = SpecularProbability(d, wo);
    return hn::IfThenElseZero(UpperBoth(d, wi, wo), MixturePdf(d, p_spec, wi.z, lobe.Pdf(d, wi, wo)));
  }
};

template <typename T> struct SimdTwin<GGXT<T>> { using type = GGXK<T>; };

}  // namespace aniso::batch::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard
