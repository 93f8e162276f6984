// src/image/third_party_begin.h: included right before a third-party single-header library's
// implementation (stb_image, stb_image_write, stb_truetype): their own code is not held to the
// project's warning flags. The includer ends the region with `#pragma GCC diagnostic pop`.
// No include guard: each implementation block opens its own region.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wcast-qual"
#pragma GCC diagnostic ignored "-Wold-style-cast"
#ifndef __clang__  // a GCC-only warning (clang would warn about the unknown group)
#pragma GCC diagnostic ignored "-Wuseless-cast"
#endif
