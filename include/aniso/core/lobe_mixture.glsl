// aniso/core/lobe_mixture.glsl: GLSL twin of lobe_mixture.h: the one-model-two-lobes pattern
// shared by Phong, Ward, Ashikhmin-Shirley and GGX: a cosine-distributed diffuse term plus one
// specular lobe, chosen with probability p_spec. The reported pdf is the mixture's, so
// weight = f cos / pdf stays exact (Veach 1997, Sec. 9.2).
//
// GLSL has no templates: pdf_diffuse_specular, sample_diffuse_specular (templates on the lobe and
// model types in C++) and LambertPlusLobeT are written once, as GLSL text with the model's and the
// lobe's names left open, in gl::glsl_lobe_mixture (src/gl/glsl_library.cpp); the library holds
// one instance per model whose C++ type is built on them (overloads with the C++ names and
// argument order), right after that model's file, which keeps only its lobe (docs/glsl.md,
// "Naming"). What they share is here.

// Probability of the specular lobe from the two lobes' weights; no weight at all samples diffuse.
float specular_share(float diffuse_weight, float specular_weight) {
  float total = diffuse_weight + specular_weight;
  return total > 0.0 ? specular_weight / total : 0.0;
}

// The shared body of pdf_diffuse_specular: the mixture density given the lobe's own pdf.
float pdf_diffuse_specular_mix(float p_spec, float lobe_pdf, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return 0.0;
  return (1.0 - p_spec) * cosine_hemisphere_pdf(wi.z) + p_spec * lobe_pdf;
}
