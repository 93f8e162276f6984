// image/image_io.cpp: the image readers and writers (image_io.h).
//
// This translation unit owns the stb_image and stb_image_write implementations: they are
// compiled here, static to this file, and nowhere else.
#include "aniso/image/image_io.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include <Iex.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include "aniso/io/input_error.h"
#include "io/atomic_file.h"
#include "io/text_input.h"

#include "image/third_party_begin.h"  // closed by the pop below
#define STB_IMAGE_STATIC
// Only the decoders of the documented formats: stb_image otherwise detects a dozen formats by
// content, and would decode a 118-byte file named .png as a run-length TGA of 6168 x 6168 pixels
// (31 s under the sanitizers; fuzz/fuzz_image.cpp keeps such inputs).
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_ONLY_HDR
#define STB_IMAGE_IMPLEMENTATION
#define STBI_NO_STDIO  // every file is read into memory here first, with errors checked
#include <stb_image.h>
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO  // PNGs are encoded to memory, then written atomically
#include <stb_image_write.h>
#pragma GCC diagnostic pop

namespace aniso::render {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Small helpers

// "<where>: <path>: <problem>", or "<path>: <problem>" when there is no `where`.
[[noreturn]] void input_error(const std::string& where, const std::string& path, const std::string& problem) {
  if (where.empty()) throw InputError(fmt::format("{}: {}", path, problem));
  throw InputError(fmt::format("{}: {}: {}", where, path, problem));
}

[[noreturn]] void write_error(const std::string& path, const std::string& reason) {
  throw std::runtime_error(fmt::format("cannot write {}: {}", path, reason));
}

std::string errno_text(int err) { return std::strerror(err); }

// The largest image read: 2^26 pixels (8192 x 8192, 16384 x 4096). An environment map holds about
// 32 bytes a pixel (the float RGB image, its luminance and the sampling tables of
// render/environment.cpp), 2 GiB at this size, and the decoder's own copy comes on top while it
// is read. Checked from the header, before anything is decoded or allocated (a 32 KB PNG can
// claim 16384 x 16384 pixels).
constexpr int64_t kMaxPixels = int64_t(1) << 26;

void check_size(int64_t w, int64_t h, const std::string& where, const std::string& path) {
  if (w <= 0 || h <= 0) input_error(where, path, fmt::format("zero-size image ({} x {})", w, h));
  if (w > kMaxPixels || h > kMaxPixels || w * h > kMaxPixels)
    input_error(where, path,
                fmt::format("image too large ({} x {} = {} pixels; at most {} pixels, e.g. 8192 x 8192 or 16384 x 4096)", w, h,
                            w * h, kMaxPixels));
}

// Reads a whole regular file. Every failure is an InputError that says which one it was.
std::vector<unsigned char> read_file(const std::string& path, const std::string& where) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) {
    const int err = ec ? ec.value() : ENOENT;
    input_error(where, path, fmt::format("cannot open ({})", errno_text(err)));
  }
  if (fs::is_directory(st)) input_error(where, path, "is a directory, expected an image file");
  if (!fs::is_regular_file(st)) input_error(where, path, "not a regular file");
  // stb_image takes the length as an int: refused by its size, before anything is read.
  if (const uintmax_t size = fs::file_size(path, ec); !ec && size > uintmax_t(std::numeric_limits<int>::max()))
    input_error(where, path, fmt::format("file too large ({} bytes, over 2 GiB)", size));

  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) input_error(where, path, fmt::format("cannot open ({})", errno_text(errno)));
  std::vector<unsigned char> data;
  std::array<unsigned char, 1 << 16> chunk;
  for (;;) {
    const size_t n = std::fread(chunk.data(), 1, chunk.size(), f.get());
    data.insert(data.end(), chunk.begin(), chunk.begin() + std::ptrdiff_t(n));
    if (n < chunk.size()) break;
  }
  if (std::ferror(f.get())) input_error(where, path, fmt::format("read error ({})", errno_text(errno)));
  if (data.empty()) input_error(where, path, "empty file (0 bytes)");
  // stb_image takes the length as an int.
  if (data.size() > size_t(std::numeric_limits<int>::max())) input_error(where, path, "file too large (over 2 GiB)");
  return data;
}

// Radiance must be finite and non-negative; the first offending pixel is named (row 0 = top).
void check_values(const Image& img, const std::string& where, const std::string& path) {
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const RGB c = img.at(x, y);
      for (int k = 0; k < 3; ++k) {
        const float v = c[k];
        if (!std::isfinite(v))
          input_error(where, path, fmt::format("pixel ({}, {}) is not finite ({} {} {})", x, y, c.x, c.y, c.z));
        if (v < 0.0f)
          input_error(where, path,
                      fmt::format("pixel ({}, {}) is negative ({} {} {}); radiance must be >= 0", x, y, c.x, c.y, c.z));
      }
    }
}

// 8-bit sRGB byte -> linear float, one table for all 256 values.
const std::array<float, 256>& srgb_decode_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = srgb_decode(float(i) / 255.0f);
    return t;
  }();
  return table;
}

// ---------------------------------------------------------------------------------------------
// Readers

// stb_image's Radiance decoder (stbi__hdr_load) does not check for the end of the data: past it,
// every byte reads as 0, so a truncated run-length scanline reads "a literal run of 0 bytes" for
// ever (a 49-byte file hung every reader), and a truncated flat file decodes as black pixels.
// This walk follows the same layout with bounds checks, so that stb_image is only given files
// whose pixels all lie inside the data; the decoding itself stays stb_image's.
//
// Layout (Radiance's src/common/color.c, freadcolrs(), as stbi__hdr_load reads it): header
// lines up to an empty line, the resolution line "-Y <h> +X <w>", then <h> scanlines. Rows of
// fewer than 8 or more than 32767 pixels are flat (4 bytes a pixel). Other rows are run-length
// encoded: 2, 2, then the row length (15 bits, big endian), then each of the 4 components (R, G,
// B, E) as runs: a count byte c > 128 repeats the next byte c - 128 times, c <= 128 copies the
// next c bytes. A first scanline without the 2, 2 marker makes stb_image read the whole image flat;
// a later one makes it restart at pixel 0, which no writer produces: that is refused.
void check_radiance_pixels(const std::vector<unsigned char>& data, int64_t w, int64_t h, const std::string& where,
                           const std::string& path) {
  const size_t n = data.size();
  // The pixels start after the first empty line and the resolution line that follows it.
  size_t pos = 0;
  bool empty_line_seen = false;
  for (;;) {
    const size_t start = pos;
    while (pos < n && data[pos] != '\n') ++pos;
    if (pos == n) input_error(where, path, "truncated Radiance HDR header (no pixel data)");
    ++pos;
    if (empty_line_seen) break;  // that was the resolution line
    empty_line_seen = pos - start == 1;
  }
  const size_t header_end = pos;
  auto truncated = [&](int64_t row) {
    input_error(where, path,
                fmt::format("truncated Radiance HDR: scanline {} of {} ends past the end of the file ({} bytes; the "
                            "pixels start at byte {})",
                            row, h, n, header_end));
  };
  auto flat = [&](size_t from) {
    const uint64_t need = uint64_t(w) * uint64_t(h) * 4;
    if (n - from < need) truncated(int64_t((n - from) / (uint64_t(w) * 4)));
  };
  if (w < 8 || w > 32767) return flat(pos);
  for (int64_t y = 0; y < h; ++y) {
    if (n - pos < 4) truncated(y);
    if (data[pos] != 2 || data[pos + 1] != 2 || (data[pos + 2] & 0x80) != 0) {
      if (y == 0) return flat(pos);
      input_error(
          where, path,
          fmt::format("corrupt Radiance HDR: scanline {} of {} (byte {}) is flat after run-length encoded ones", y, h, pos));
    }
    const int64_t len = int64_t(data[pos + 2]) << 8 | data[pos + 3];
    if (len != w)
      input_error(where, path,
                  fmt::format("corrupt Radiance HDR: scanline {} of {} (byte {}) claims {} pixels, the image is {} wide", y, h,
                              pos, len, w));
    pos += 4;
    for (int k = 0; k < 4; ++k)
      for (int64_t x = 0; x < w;) {
        if (pos >= n) truncated(y);
        const unsigned c = data[pos++];
        const int64_t count = c > 128 ? c - 128 : c;
        const size_t bytes = c > 128 ? 1 : c;
        if (count > w - x)
          input_error(where, path,
                      fmt::format("corrupt Radiance HDR: scanline {} of {} (byte {}) has a run past its end", y, h, pos - 1));
        if (n - pos < bytes) truncated(y);
        pos += bytes;
        x += count;
      }
  }
}

Image read_stb(const std::vector<unsigned char>& data, const std::string& ext, const std::string& where, const std::string& path,
               bool linear_8bit) {
  const auto* bytes = data.data();
  const int len = int(data.size());
  int w = 0, h = 0, comp = 0;
  // The content must be the format the extension names (PNG and JPEG by their signatures; HDR is
  // checked below), so that a file is never decoded as something else.
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (ext == ".png" && (data.size() < 8 || std::memcmp(bytes, kPng, 8) != 0))
    input_error(where, path, "not a PNG file (no PNG signature)");
  // stb_image reserves a PNG chunk's stated length before reading it, so a 405-byte file whose IDAT
  // header claims 2 GB would allocate 2 GB. Every chunk (4-byte length,
  // 4-byte type, data, 4-byte CRC; PNG spec 5.3) must fit in the file.
  if (ext == ".png") {
    for (size_t off = 8; off + 8 <= data.size();) {
      const uint32_t n =
          uint32_t(bytes[off]) << 24 | uint32_t(bytes[off + 1]) << 16 | uint32_t(bytes[off + 2]) << 8 | uint32_t(bytes[off + 3]);
      if (size_t(n) > data.size() - off - 8)
        input_error(where, path,
                    fmt::format("corrupt PNG: the chunk at byte {} claims {} bytes, past the end of the file ({} bytes)", off, n,
                                data.size()));
      off += 12 + size_t(n);
    }
  }
  if ((ext == ".jpg" || ext == ".jpeg") && (data.size() < 3 || bytes[0] != 0xFF || bytes[1] != 0xD8 || bytes[2] != 0xFF))
    input_error(where, path, "not a JPEG file (no JPEG signature)");
  // stbi_loadf applies a 2.2 gamma to 8-bit files; a .hdr must really be Radiance RGBE (linear).
  if (ext == ".hdr" && !stbi_is_hdr_from_memory(bytes, len)) input_error(where, path, "not a Radiance HDR (RGBE) file");
  if (!stbi_info_from_memory(bytes, len, &w, &h, &comp))
    input_error(where, path, fmt::format("corrupt or unsupported image ({})", stbi_failure_reason()));
  check_size(w, h, where, path);
  // stb_image allocates the whole image from the header before decoding a byte of it, so a tiny
  // file claiming 2^28 pixels (397 bytes) would allocate gigabytes. No file of these formats holds more pixels than its
  // compression allows: deflate expands at most 1032:1 (zlib's technical details) and a 1-bit PNG packs 8 pixels a byte, so PNG
  // holds at most 8256 pixels per byte; Radiance RLE and JPEG expand far less. 8256 per byte plus a million pixels of slack
  // rejects only files that cannot be valid.
  constexpr int64_t kMaxPixelsPerByte = 8256, kPixelSlack = int64_t(1) << 20;
  if (int64_t(w) * h > kMaxPixelsPerByte * int64_t(len) + kPixelSlack)
    input_error(where, path, fmt::format("the header claims {} x {} pixels, more than a file of {} bytes can hold", w, h, len));

  Image img;
  auto fail = [&] { input_error(where, path, fmt::format("corrupt or truncated image ({})", stbi_failure_reason())); };
  if (ext == ".hdr") {
    check_radiance_pixels(data, w, h, where, path);
    std::unique_ptr<float, void (*)(void*)> px(stbi_loadf_from_memory(bytes, len, &w, &h, &comp, 3), &stbi_image_free);
    if (!px) fail();
    img = Image(w, h);
    std::copy(px.get(), px.get() + img.rgb.size(), img.rgb.begin());
  } else if (stbi_is_16_bit_from_memory(bytes, len)) {
    std::unique_ptr<stbi_us, void (*)(void*)> px(stbi_load_16_from_memory(bytes, len, &w, &h, &comp, 3), &stbi_image_free);
    if (!px) fail();
    img = Image(w, h);
    for (size_t i = 0; i < img.rgb.size(); ++i) {
      const float v = float(px.get()[i]) / 65535.0f;
      img.rgb[i] = linear_8bit ? v : srgb_decode(v);
    }
  } else {
    std::unique_ptr<stbi_uc, void (*)(void*)> px(stbi_load_from_memory(bytes, len, &w, &h, &comp, 3), &stbi_image_free);
    if (!px) fail();
    img = Image(w, h);
    const auto& table = srgb_decode_table();
    for (size_t i = 0; i < img.rgb.size(); ++i) {
      const stbi_uc v = px.get()[i];
      img.rgb[i] = linear_8bit ? float(v) / 255.0f : table[v];
    }
  }
  return img;
}

// PFM (Portable Float Map): "PF" (RGB) or "Pf" (grey), width, height, scale (negative: little
// endian, positive: big endian), each separated by white space and the scale followed by exactly
// one white-space byte; then float rows from the BOTTOM row up.
Image read_pfm(const std::vector<unsigned char>& data, const std::string& where, const std::string& path) {
  size_t pos = 0;
  auto is_space = [](unsigned char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
  auto token = [&](const char* what) {
    while (pos < data.size() && is_space(data[pos])) ++pos;
    const size_t start = pos;
    while (pos < data.size() && !is_space(data[pos]) && pos - start < 64) ++pos;
    if (pos == start) input_error(where, path, fmt::format("truncated PFM header (no {})", what));
    return std::string(data.begin() + std::ptrdiff_t(start), data.begin() + std::ptrdiff_t(pos));
  };
  const std::string magic = token("\"PF\" or \"Pf\"");
  if (magic != "PF" && magic != "Pf") input_error(where, path, "not a PFM file (the header must start with \"PF\" or \"Pf\")");
  const int channels = magic == "PF" ? 3 : 1;

  auto integer = [&](const char* what) -> int64_t {
    const std::string t = token(what);
    int64_t v = 0;
    for (char c : t) {
      if (c < '0' || c > '9' || v > kMaxPixels) input_error(where, path, fmt::format("bad PFM {} \"{}\"", what, t));
      v = v * 10 + (c - '0');
    }
    return v;
  };
  const int64_t w = integer("width");
  const int64_t h = integer("height");
  const std::string scale_text = token("scale");
  char* end = nullptr;
  const double scale = std::strtod(scale_text.c_str(), &end);
  if (end != scale_text.c_str() + scale_text.size() || !std::isfinite(scale) || scale == 0.0)
    input_error(where, path, fmt::format("bad PFM scale \"{}\" (expected a non-zero number)", scale_text));
  if (pos >= data.size() || !is_space(data[pos])) input_error(where, path, "truncated PFM header");
  ++pos;  // the single white-space byte before the pixels
  check_size(w, h, where, path);

  const size_t count = size_t(w) * size_t(h) * size_t(channels);
  const size_t available = data.size() - pos;
  if (available < count * 4)
    input_error(where, path,
                fmt::format("truncated PFM: {} x {} needs {} bytes of pixels, the file has {}", w, h, count * 4, available));
  const bool file_little = scale < 0.0;
  const bool swap = file_little != (std::endian::native == std::endian::little);

  Image img(static_cast<int>(w), static_cast<int>(h));
  const unsigned char* src = data.data() + pos;
  for (int64_t row = 0; row < h; ++row) {
    const int y = int(h - 1 - row);  // the file's first row is the image's bottom row
    for (int64_t x = 0; x < w; ++x) {
      float v[3];
      for (int c = 0; c < channels; ++c) {
        uint32_t bits;
        std::memcpy(&bits, src, 4);
        src += 4;
        if (swap) bits = __builtin_bswap32(bits);
        std::memcpy(&v[c], &bits, 4);
      }
      if (channels == 1) v[1] = v[2] = v[0];
      img.set(int(x), y, RGB(v[0], v[1], v[2]));
    }
  }
  return img;
}

// OpenEXR reads from the bytes already in memory: the file is opened once, by read_file().
class MemoryIStream : public Imf::IStream {
 public:
  MemoryIStream(const char* name, const std::vector<unsigned char>& data) : Imf::IStream(name), data_(data) {}
  bool read(char c[], int n) override {
    if (n < 0 || uint64_t(n) > data_.size() - std::min<uint64_t>(pos_, data_.size()))
      throw Iex::InputExc("unexpected end of file");
    std::memcpy(c, data_.data() + pos_, size_t(n));
    pos_ += uint64_t(n);
    return pos_ < data_.size();
  }
  uint64_t tellg() override { return pos_; }
  void seekg(uint64_t pos) override { pos_ = pos; }

 private:
  const std::vector<unsigned char>& data_;
  uint64_t pos_ = 0;
};

Image read_exr(const std::vector<unsigned char>& data, const std::string& where, const std::string& path) {
  try {
    MemoryIStream stream(path.c_str(), data);
    Imf::InputFile file(stream);
    const Imath::Box2i dw = file.header().dataWindow();
    const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
    check_size(w, h, where, path);
    const Imf::ChannelList& ch = file.header().channels();
    const bool rgb = ch.findChannel("R") || ch.findChannel("G") || ch.findChannel("B");
    const bool grey = !rgb && ch.findChannel("Y");
    if (!rgb && !grey) input_error(where, path, "the EXR file has no R, G, B or Y channel");

    Image img(static_cast<int>(w), static_cast<int>(h));
    const size_t xs = 3 * sizeof(float), ys = xs * size_t(w);
    Imf::FrameBuffer fb;
    char* base = reinterpret_cast<char*>(img.rgb.data());
    if (rgb) {
      fb.insert("R", Imf::Slice::Make(Imf::FLOAT, base, dw, xs, ys));
      fb.insert("G", Imf::Slice::Make(Imf::FLOAT, base + sizeof(float), dw, xs, ys));
      fb.insert("B", Imf::Slice::Make(Imf::FLOAT, base + 2 * sizeof(float), dw, xs, ys));
    } else {
      fb.insert("Y", Imf::Slice::Make(Imf::FLOAT, base, dw, xs, ys));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    if (grey)
      for (size_t i = 0; i < img.rgb.size(); i += 3) img.rgb[i + 1] = img.rgb[i + 2] = img.rgb[i];
    return img;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    input_error(where, path, fmt::format("corrupt or unsupported EXR file ({})", e.what()));
  }
}

// ---------------------------------------------------------------------------------------------
// Writers: every format is encoded to memory first, then written with io::write_file_atomically().

void write_bytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  io::write_file_atomically(path, bytes.data(), bytes.size());
}

class MemoryOStream : public Imf::OStream {
 public:
  explicit MemoryOStream(const char* name) : Imf::OStream(name) {}
  void write(const char c[], int n) override {
    if (pos_ + uint64_t(n) > bytes.size()) bytes.resize(pos_ + uint64_t(n));
    std::memcpy(bytes.data() + pos_, c, size_t(n));
    pos_ += uint64_t(n);
  }
  uint64_t tellp() override { return pos_; }
  void seekp(uint64_t pos) override { pos_ = pos; }
  std::vector<unsigned char> bytes;

 private:
  uint64_t pos_ = 0;
};

std::vector<unsigned char> encode_exr(const std::string& path, const Image& img) {
  try {
    MemoryOStream stream(path.c_str());
    {
      Imf::Header header(img.width, img.height);
      header.compression() = Imf::ZIP_COMPRESSION;  // lossless
      for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
      Imf::FrameBuffer fb;
      // OutputFile only reads the slices; Slice wants a non-const pointer.
      char* base = const_cast<char*>(reinterpret_cast<const char*>(img.rgb.data()));
      const size_t xs = 3 * sizeof(float), ys = xs * size_t(img.width);
      fb.insert("R", Imf::Slice(Imf::FLOAT, base, xs, ys));
      fb.insert("G", Imf::Slice(Imf::FLOAT, base + sizeof(float), xs, ys));
      fb.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xs, ys));
      Imf::OutputFile file(stream, header);
      file.setFrameBuffer(fb);
      file.writePixels(img.height);
    }  // the OutputFile's destructor writes the line offset table
    return std::move(stream.bytes);
  } catch (const std::exception& e) {
    write_error(path, fmt::format("OpenEXR: {}", e.what()));
  }
}

// PF, scale -1 (little endian), rows from the bottom up.
std::vector<unsigned char> encode_pfm(const Image& img) {
  const std::string header = fmt::format("PF\n{} {}\n-1.0\n", img.width, img.height);
  std::vector<unsigned char> out(header.begin(), header.end());
  out.reserve(header.size() + img.rgb.size() * 4);
  const size_t row_floats = size_t(img.width) * 3;
  for (int y = img.height - 1; y >= 0; --y)
    for (size_t i = 0; i < row_floats; ++i) {
      uint32_t bits;
      std::memcpy(&bits, &img.rgb[size_t(y) * row_floats + i], 4);
      if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap32(bits);
      unsigned char b[4];
      std::memcpy(b, &bits, 4);
      out.insert(out.end(), b, b + 4);
    }
  return out;
}

void check_writable(const std::string& path, int w, int h, size_t size) {
  if (w <= 0 || h <= 0) write_error(path, fmt::format("invalid image size {} x {}", w, h));
  if (size != size_t(w) * size_t(h) * 3)
    write_error(path, fmt::format("the pixel buffer holds {} values, {} x {} x 3 expected", size, w, h));
}

}  // namespace

Image read_image(const std::string& path, const std::string& where, bool linear_8bit) {
  const std::string ext = lower_extension(path);
  const bool known = ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".hdr" || ext == ".exr" || ext == ".pfm";
  if (!known)
    input_error(where, path, fmt::format("unknown image extension \"{}\" (expected .png, .jpg, .jpeg, .hdr, .exr or .pfm)", ext));
  const std::vector<unsigned char> data = read_file(path, where);
  Image img;
  if (ext == ".pfm")
    img = read_pfm(data, where, path);
  else if (ext == ".exr")
    img = read_exr(data, where, path);
  else
    img = read_stb(data, ext, where, path, linear_8bit);
  check_values(img, where, path);
  return img;
}

void write_image(const std::string& path, const Image& img, const ToneMapOptions& tm) {
  const std::string ext = lower_extension(path);
  if (ext != ".png" && ext != ".exr" && ext != ".pfm")
    throw InputError(fmt::format("cannot write {}: unknown image extension \"{}\" (expected .png, .exr or .pfm)", path, ext));
  check_writable(path, img.width, img.height, img.rgb.size());
  if (ext == ".png")
    write_png(path, tonemap(img, tm));
  else
    write_bytes(path, ext == ".exr" ? encode_exr(path, img) : encode_pfm(img));
}

void write_png(const std::string& path, const DisplayImage& img) {
  check_writable(path, img.width, img.height, img.rgb.size());
  if (int64_t(img.width) * 3 > std::numeric_limits<int>::max()) write_error(path, "image too wide for PNG");
  std::vector<unsigned char> bytes;
  auto append = [](void* context, void* data, int size) {
    auto* out = static_cast<std::vector<unsigned char>*>(context);
    const auto* p = static_cast<const unsigned char*>(data);
    out->insert(out->end(), p, p + size);
  };
  if (!stbi_write_png_to_func(append, &bytes, img.width, img.height, 3, img.rgb.data(), img.width * 3))
    write_error(path, "PNG encoding failed");
  write_bytes(path, bytes);
}

}  // namespace aniso::render
