// rgl/tensor.cpp: the tensor file container (rgl/tensor.h; docs/rgl.md "The container").
#include "aniso/rgl/tensor.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <set>

#include <fmt/format.h>

#include "aniso/io/params.h"
#include "io/json_read.h"

namespace aniso::rgl {

static_assert(std::endian::native == std::endian::little, "tensor files are little-endian; this reader copies bytes");

const char* dtype_name(Dtype t) {
  switch (t) {
    case Dtype::UInt8: return "uint8";
    case Dtype::Int8: return "int8";
    case Dtype::UInt16: return "uint16";
    case Dtype::Int16: return "int16";
    case Dtype::UInt32: return "uint32";
    case Dtype::Int32: return "int32";
    case Dtype::UInt64: return "uint64";
    case Dtype::Int64: return "int64";
    case Dtype::Float16: return "float16";
    case Dtype::Float32: return "float32";
    case Dtype::Float64: return "float64";
    case Dtype::Invalid: break;
  }
  return "invalid";
}

size_t dtype_size(Dtype t) {
  switch (t) {
    case Dtype::UInt8:
    case Dtype::Int8: return 1;
    case Dtype::UInt16:
    case Dtype::Int16:
    case Dtype::Float16: return 2;
    case Dtype::UInt32:
    case Dtype::Int32:
    case Dtype::Float32: return 4;
    case Dtype::UInt64:
    case Dtype::Int64:
    case Dtype::Float64: return 8;
    case Dtype::Invalid: break;
  }
  return 0;
}

uint64_t TensorField::count() const {
  uint64_t n = 1;
  for (const uint64_t s : shape) n *= s;  // bounded by the reader (the data fits in the file)
  return n;
}

std::vector<float> TensorField::floats() const {
  std::vector<float> v(bytes.size() / sizeof(float));
  if (!v.empty()) std::memcpy(v.data(), bytes.data(), v.size() * sizeof(float));
  return v;
}

std::string TensorField::shape_string() const {
  std::string s = "[";
  for (size_t i = 0; i < shape.size(); ++i) s += fmt::format("{}{}", i ? ", " : "", shape[i]);
  return s + "]";
}

TensorField make_field(std::string name, std::vector<uint64_t> shape, std::span<const float> data) {
  TensorField f{std::move(name), Dtype::Float32, std::move(shape), 0, {}};
  f.bytes.resize(data.size_bytes());
  if (!data.empty()) std::memcpy(f.bytes.data(), data.data(), data.size_bytes());
  return f;
}

TensorField make_field(std::string name, std::vector<uint64_t> shape, std::span<const uint8_t> data) {
  return TensorField{std::move(name), Dtype::UInt8, std::move(shape), 0, {data.begin(), data.end()}};
}

const TensorField* TensorFile::find(std::string_view name) const {
  for (const TensorField& f : fields)
    if (f.name == name) return &f;
  return nullptr;
}

namespace {

// A bounds-checked cursor over the file's bytes: every read past the end is an InputError saying
// what was being read, never a read outside the buffer.
struct Cursor {
  std::span<const uint8_t> bytes;
  const std::string& where;
  size_t pos = 0;

  template <typename T> T read(const std::string& what) {
    T v;
    if (bytes.size() - pos < sizeof(T))
      throw InputError(
          fmt::format("{}: truncated file: {} at byte {} runs past the end ({} bytes)", where, what, pos, bytes.size()));
    std::memcpy(&v, bytes.data() + pos, sizeof(T));
    pos += sizeof(T);
    return v;
  }
  std::string read_string(size_t n, const std::string& what) {
    if (bytes.size() - pos < n)
      throw InputError(fmt::format("{}: truncated file: {} ({} bytes at byte {}) runs past the end ({} bytes)", where, what, n,
                                   pos, bytes.size()));
    std::string s(reinterpret_cast<const char*>(bytes.data() + pos), n);
    pos += n;
    return s;
  }
};

// The smallest field table entry: name length, an empty name, ndim, dtype, offset (2 + 2 + 1 + 8).
constexpr size_t kMinFieldEntry = 13;
constexpr size_t kHeaderSize = 12 + 2 + 4;

}  // namespace

TensorFile parse_tensor(std::span<const uint8_t> bytes, const std::string& where) {
  TensorFile t;
  t.source = where;
  t.size = bytes.size();
  // pbrt-v4 bxdfs.cpp:757 and Mitsuba tensor.cpp:13: at least the magic, the version and the count.
  if (bytes.size() < kHeaderSize)
    throw InputError(
        fmt::format("{}: not a tensor file: {} bytes, the header alone is {} (truncated?)", where, bytes.size(), kHeaderSize));
  Cursor c{bytes, where};
  const std::string magic = c.read_string(12, "the magic");
  if (std::memcmp(magic.data(), "tensor_file\0", 12) != 0)
    throw InputError(fmt::format(
        "{}: not a tensor file: the first 12 bytes are not \"tensor_file\\0\" (pbrt-v4 and Mitsuba 3's magic)", where));
  const auto major = c.read<uint8_t>("the version"), minor = c.read<uint8_t>("the version");
  if (major != 1 || minor != 0)
    throw InputError(fmt::format("{}: tensor file version {}.{}, only 1.0 exists (pbrt-v4 bxdfs.cpp:769)", where, major, minor));
  const uint32_t n_fields = c.read<uint32_t>("the field count");
  // Each entry takes at least kMinFieldEntry bytes: a count the file cannot hold is refused before
  // anything is allocated for it.
  if (n_fields > (bytes.size() - kHeaderSize) / kMinFieldEntry)
    throw InputError(fmt::format("{}: the header announces {} fields, more than the {} bytes of the file can hold", where,
                                 n_fields, bytes.size()));
  std::set<std::string> names;
  t.fields.reserve(n_fields);
  for (uint32_t i = 0; i < n_fields; ++i) {
    TensorField f;
    const std::string entry = fmt::format("field table entry {}", i);
    const uint16_t name_length = c.read<uint16_t>(entry + ": name length");
    f.name = c.read_string(name_length, entry + ": name");
    const std::string label = fmt::format("field \"{}\"", text_escape(f.name));  // a name may hold any byte
    const uint16_t ndim = c.read<uint16_t>(label + ": ndim");
    const uint8_t dtype = c.read<uint8_t>(label + ": dtype");
    f.offset = c.read<uint64_t>(label + ": offset");
    if (dtype == 0 || dtype > uint8_t(Dtype::Float64))
      throw InputError(fmt::format("{}: {}: unknown dtype code {} (1 to 11: uint8 ... float64)", where, label, dtype));
    f.dtype = Dtype(dtype);
    if (size_t(ndim) * 8 > bytes.size() - c.pos)
      throw InputError(fmt::format("{}: truncated file: {} has {} dimensions, their sizes run past the end", where, label, ndim));
    f.shape.resize(ndim);
    // The data must fit in the file: the product of the shape is checked against the file size at
    // every step, so that a huge or overflowing shape is an error, not an allocation.
    uint64_t total = dtype_size(f.dtype);
    bool zero = false;
    for (uint16_t d = 0; d < ndim; ++d) {
      f.shape[d] = c.read<uint64_t>(label + ": shape");
      if (f.shape[d] == 0) zero = true;
      if (!zero && f.shape[d] > bytes.size() / total)
        throw InputError(fmt::format("{}: {}: shape {} ({}) needs more bytes than the file has ({})", where, label, d, f.shape[d],
                                     bytes.size()));
      total = zero ? 0 : total * f.shape[d];
    }
    if (f.offset > bytes.size() || total > bytes.size() - f.offset)
      throw InputError(fmt::format("{}: {}: data ({} bytes at offset {}) runs past the end of the file ({} bytes)", where, label,
                                   total, f.offset, bytes.size()));
    if (!names.insert(f.name).second) throw InputError(fmt::format("{}: {} appears twice in the field table", where, label));
    f.bytes.assign(bytes.begin() + ptrdiff_t(f.offset), bytes.begin() + ptrdiff_t(f.offset + total));
    t.fields.push_back(std::move(f));
  }
  return t;
}

TensorFile read_tensor_file(const std::string& path) {
  // The common whole-file reader: its file-kind messages and its size limit (io/json_read.h).
  const std::string text = read_text_file(path, "an RGL tensor file (.bsdf)", kMaxTensorFileBytes);
  return parse_tensor(std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()), path);
}

std::vector<uint8_t> serialize_tensor(std::vector<TensorField> fields) {
  std::vector<uint8_t> out;
  auto put = [&](const void* p, size_t n) {
    const auto* b = static_cast<const uint8_t*>(p);
    out.insert(out.end(), b, b + n);
  };
  out.insert(out.end(), {'t', 'e', 'n', 's', 'o', 'r', '_', 'f', 'i', 'l', 'e', '\0', 1, 0});
  const uint32_t n = uint32_t(fields.size());
  put(&n, 4);
  std::vector<size_t> offset_pos;
  for (const TensorField& f : fields) {
    const uint16_t len = uint16_t(f.name.size()), ndim = uint16_t(f.shape.size());
    const uint8_t dtype = uint8_t(f.dtype);
    put(&len, 2);
    put(f.name.data(), f.name.size());
    put(&ndim, 2);
    put(&dtype, 1);
    offset_pos.push_back(out.size());
    const uint64_t zero = 0;
    put(&zero, 8);
    for (const uint64_t s : f.shape) put(&s, 8);
  }
  for (size_t i = 0; i < fields.size(); ++i) {
    // Mitsuba's writer aligns every field to 8 bytes (tensor_io.py:134-135).
    out.resize((out.size() + 7) / 8 * 8, 0);
    const uint64_t off = out.size();
    std::memcpy(out.data() + offset_pos[i], &off, 8);
    put(fields[i].bytes.data(), fields[i].bytes.size());
  }
  return out;
}

}  // namespace aniso::rgl
