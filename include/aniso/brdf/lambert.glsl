// aniso/brdf/lambert.glsl: GLSL twin of lambert.h: the ideal diffuse reflector, f = kd / pi
// (Lambert 1760).

float Fd_Lambert() { return kInvPi; }

struct Lambert {
  vec3 kd;
};

vec3 Lambert_f(Lambert self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return vec3(0.0);
  return self.kd * Fd_Lambert();
}
float Lambert_pdf(Lambert self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return 0.0;
  return cosine_hemisphere_pdf(wi.z);
}
BSDFSample Lambert_sample(Lambert self, vec3 wo, float uc, vec2 u) {
  if (!above_horizon(wo)) return BSDFSample_none();
  vec3 wi = sample_cosine_hemisphere(u);
  return make_sample(wi, Lambert_f(self, wi, wo), Lambert_pdf(self, wi, wo));
}
