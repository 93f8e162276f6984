// aniso/image/tonemap.h: linear radiance to 8-bit sRGB (what `aniso render` writes to PNG, the
// gallery shows and the GL backend's tone-map pass reproduces), and the sRGB transfer function.
#pragma once

#include "aniso/image/image.h"

namespace aniso::render {

enum class ToneMap {
  Aces,   // exposure, then the ACES filmic curve (Narkowicz 2015 fit), then the sRGB OETF
  Clamp,  // exposure, clamp to [0, 1], then the sRGB OETF
};

struct ToneMapOptions {
  float exposure_stops = 0.0f;  // radiance is multiplied by 2^exposure_stops first
  ToneMap curve = ToneMap::Aces;
};

// The sRGB transfer function (IEC 61966-2-1) and its inverse, on [0, 1]: inputs outside are
// clamped, NaN gives 0.
float srgb_encode(float linear);
float srgb_decode(float encoded);

// Per channel: radiance * 2^exposure_stops, the curve, the sRGB OETF, rounded to the nearest
// byte. NaN and negative radiance give 0, +inf gives 255.
DisplayImage tonemap(const Image& img, const ToneMapOptions& opt);

}  // namespace aniso::render
