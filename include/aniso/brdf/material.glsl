// aniso/brdf/material.glsl: GLSL twin of material.h: every model behind one value type,
// dispatched by a tag. GLSL has no unions: Material holds one member per model and `kind` says
// which one is live (the others are never read).
//
// Interface of every model (docs/conventions.md): directions in the local shading frame
// (z = normal, x = tangent), wi towards the light, wo towards the viewer, both unit.
//   Material_f(m, wi, wo)           the BRDF without the cosine; 0 unless both are above the horizon
//   Material_pdf(m, wi, wo)         the solid-angle density of Material_sample producing wi for this wo
//   Material_sample(m, wo, uc, u)   {wi, weight = f cos / pdf, pdf} or "no sample"; uc picks the lobe,
//                                   u (2D) the direction; all uniform in [0, 1)

// enum class ModelKind (enumerator values as in material.h).
const int ModelKind_Lambert = 0;
const int ModelKind_Phong = 1;
const int ModelKind_Ward = 2;
const int ModelKind_AshikhminShirley = 3;
const int ModelKind_Lafortune = 4;
const int ModelKind_GGX = 5;
const int ModelKind_Metal = 6;

struct Material {
  int kind;  // ModelKind_*
  Lambert lambert;
  Phong phong;
  Ward ward;
  AshikhminShirley ashikhmin_shirley;
  Lafortune lafortune;
  GGX ggx;
  Metal metal;
};

vec3 Material_f(Material self, vec3 wi, vec3 wo) {
  if (self.kind == ModelKind_Phong) return Phong_f(self.phong, wi, wo);
  if (self.kind == ModelKind_Ward) return Ward_f(self.ward, wi, wo);
  if (self.kind == ModelKind_AshikhminShirley) return AshikhminShirley_f(self.ashikhmin_shirley, wi, wo);
  if (self.kind == ModelKind_Lafortune) return Lafortune_f(self.lafortune, wi, wo);
  if (self.kind == ModelKind_GGX) return GGX_f(self.ggx, wi, wo);
  if (self.kind == ModelKind_Metal) return Metal_f(self.metal, wi, wo);
  return Lambert_f(self.lambert, wi, wo);
}
float Material_pdf(Material self, vec3 wi, vec3 wo) {
  if (self.kind == ModelKind_Phong) return Phong_pdf(self.phong, wi, wo);
  if (self.kind == ModelKind_Ward) return Ward_pdf(self.ward, wi, wo);
  if (self.kind == ModelKind_AshikhminShirley) return AshikhminShirley_pdf(self.ashikhmin_shirley, wi, wo);
  if (self.kind == ModelKind_Lafortune) return Lafortune_pdf(self.lafortune, wi, wo);
  if (self.kind == ModelKind_GGX) return GGX_pdf(self.ggx, wi, wo);
  if (self.kind == ModelKind_Metal) return Metal_pdf(self.metal, wi, wo);
  return Lambert_pdf(self.lambert, wi, wo);
}
BSDFSample Material_sample(Material self, vec3 wo, float uc, vec2 u) {
  if (self.kind == ModelKind_Phong) return Phong_sample(self.phong, wo, uc, u);
  if (self.kind == ModelKind_Ward) return Ward_sample(self.ward, wo, uc, u);
  if (self.kind == ModelKind_AshikhminShirley) return AshikhminShirley_sample(self.ashikhmin_shirley, wo, uc, u);
  if (self.kind == ModelKind_Lafortune) return Lafortune_sample(self.lafortune, wo, uc, u);
  if (self.kind == ModelKind_GGX) return GGX_sample(self.ggx, wo, uc, u);
  if (self.kind == ModelKind_Metal) return Metal_sample(self.metal, wo, uc, u);
  return Lambert_sample(self.lambert, wo, uc, u);
}
