// aniso/image/tonemap.glsl: GLSL twin of render::tonemap's per-channel curve (aniso/image/tonemap.h,
// src/image/tonemap.cpp), the one tone map of the GL backend's display pass (src/gl/shaders/
// tonemap_pass.frag.glsl) and of the web explorer (web/explorer.js, delivered by `aniso web-data` as
// ANISO_DATA.glsl.tonemap). GLSL 3.30 core and ES 3.00; self-contained (no library names).
// tests/test_tonemap_parity.cpp and tests/web (check "tonemap") hold both to the CPU's bytes.
//
// Per channel: radiance * gain (gain = 2^exposure_stops), NaN and negative radiance to 0, then
// Narkowicz 2015, "ACES Filmic Tone Mapping Curve", or a clamp to [0, 1], then the sRGB transfer
// function (IEC 61966-2-1). The result is the encoded value in [0, 1]; the CPU writes
// uint8(255 x + 0.5) of it. +inf radiance gives 1 (the CPU's 255), NaN and -inf 0.

// IEC 61966-2-1 (sRGB) encoding, knee at 0.0031308; NaN and x <= 0 give 0 (render::srgb_encode).
float ToneMap_srgb_encode(float x) {
  if (isnan(x) || !(x > 0.0)) return 0.0;
  if (x >= 1.0) return 1.0;
  return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

// One channel: linear radiance to the encoded display value in [0, 1].
float ToneMap_channel(float radiance, float gain, bool aces) {
  float v = radiance * gain;
  // NaN (also inf * 0) and negative radiance show as black. isnan as well as the comparison: a
  // compiler that assumes no NaN may turn !(v > 0.0) into v <= 0.0.
  if (isnan(v) || !(v > 0.0)) v = 0.0;
  if (aces) {
    // The curve reaches 1 near v = 7.24; capping v far above that keeps v * v finite (inf / inf
    // would be NaN).
    v = min(v, 1e4);
    v = v * (2.51 * v + 0.03) / (v * (2.43 * v + 0.59) + 0.14);
  }
  return ToneMap_srgb_encode(clamp(v, 0.0, 1.0));
}

vec3 ToneMap_apply(vec3 radiance, float gain, bool aces) {
  return vec3(ToneMap_channel(radiance.r, gain, aces), ToneMap_channel(radiance.g, gain, aces),
              ToneMap_channel(radiance.b, gain, aces));
}
