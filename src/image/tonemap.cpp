// image/tonemap.cpp: the sRGB transfer function and the tone curves (tonemap.h).
#include "aniso/image/tonemap.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace aniso::render {

// IEC 61966-2-1 (sRGB), with the knee at 0.0031308 (linear) / 0.04045 (encoded).
float srgb_encode(float linear) {
  if (!(linear > 0.0f)) return 0.0f;  // also NaN
  if (linear >= 1.0f) return 1.0f;
  return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

float srgb_decode(float encoded) {
  if (!(encoded > 0.0f)) return 0.0f;
  if (encoded >= 1.0f) return 1.0f;
  return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

DisplayImage tonemap(const Image& img, const ToneMapOptions& opt) {
  DisplayImage out(img.width, img.height);
  const float gain = std::exp2(opt.exposure_stops);
  const size_t n = std::min(out.rgb.size(), img.rgb.size());
  for (size_t i = 0; i < n; ++i) {
    float v = img.rgb[i] * gain;
    if (!(v > 0.0f)) v = 0.0f;  // NaN and negative radiance show as black
    if (opt.curve == ToneMap::Aces) {
      // Narkowicz 2015, "ACES Filmic Tone Mapping Curve". The curve reaches 1 near v = 7.24;
      // capping v far above that keeps v * v finite (inf / inf would be NaN).
      v = std::min(v, 1e4f);
      v = v * (2.51f * v + 0.03f) / (v * (2.43f * v + 0.59f) + 0.14f);
    }
    v = std::clamp(v, 0.0f, 1.0f);
    out.rgb[i] = uint8_t(srgb_encode(v) * 255.0f + 0.5f);  // in [0.5, 255.5): never out of range
  }
  return out;
}

}  // namespace aniso::render
