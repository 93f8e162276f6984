// aniso/image/image_io.h: image files in and out, the format chosen by the extension.
//
// Readers: PNG / JPEG / HDR through stb_image, EXR through OpenEXR, PFM by hand (a 3-line text
// header). Writers: .png is tone-mapped 8-bit sRGB (tonemap.h), .exr and .pfm hold linear RGB
// float. Every writer writes to a temporary file beside the target and renames it, so a failed or
// interrupted write never leaves a half-written image.
#pragma once

#include <string>

#include "aniso/image/image.h"
#include "aniso/image/tonemap.h"

namespace aniso::render {

// Reads an image by extension (.png .jpg .jpeg .hdr .exr .pfm). `where` prefixes every error
// (e.g. "scene.json: environment.file"); a missing, unreadable, corrupt or empty file, or one with
// non-finite or negative values, is an InputError (aniso/io/input_error.h) naming the path and the
// problem. 8-bit formats are decoded from sRGB to linear unless `linear_8bit` is set (data maps
// such as tangent maps are read with linear_8bit = true: their bytes are numbers, not colours);
// 16-bit PNGs likewise, over 65535. Grey images are expanded to RGB, alpha is dropped. Messages
// read "<where>: <path>: <problem>".
Image read_image(const std::string& path, const std::string& where, bool linear_8bit = false);

// Writes by extension: .png (tone-mapped with `tm`, 8-bit sRGB), .exr (32-bit float R, G, B, ZIP
// compression), .pfm ("PF", little endian, rows bottom to top as the format wants). An unknown
// extension is an InputError; an empty image or an I/O failure a std::runtime_error reading
// "cannot write <path>: <reason>". Atomic, through io::write_file_atomically (io/atomic_file.h:
// a temporary file beside the target, fsync, rename; mode and symbolic links kept; removed on
// failure and on SIGTERM, SIGHUP, SIGINT and SIGXFSZ).
void write_image(const std::string& path, const Image& img, const ToneMapOptions& tm = {});
void write_png(const std::string& path, const DisplayImage& img);

}  // namespace aniso::render
