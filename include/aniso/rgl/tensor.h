// aniso/rgl/tensor.h: the tensor file container of the RGL material database (Dupuy & Jakob 2018, "An
// Adaptive Parameterization for Efficient Material Acquisition and Rendering"), the `.bsdf` files
// pbrt-v4 (`Material "measured"`) and Mitsuba 3 (`<bsdf type="measured">`) read. docs/rgl.md.
//
// Layout, all little-endian (pbrt-v4 src/pbrt/bxdfs.cpp:729-812 `Tensor::Tensor`; Mitsuba 3
// src/core/tensor.cpp:10-55 and its writer src/python/python/tensor_io.py:66-150):
//   "tensor_file\0" (12 bytes), version u8 1, u8 0, field count u32;
//   per field: name length u16, name bytes, ndim u16, dtype u8, data offset u64, ndim x u64 shape;
//   then each field's data at its offset, C order (last index fastest). Mitsuba's writer aligns
//   every offset to 8 bytes (tensor_io.py:134-135); so does ours (Mitsuba maps the file and casts
//   data + offset to float*, tensor.cpp:50-52).
// dtype codes (pbrt-v4 bxdfs.cpp:582-600 `Tensor::Type`, Mitsuba tensor_io.py:36-47): 1 uint8,
// 2 int8, 3 uint16, 4 int16, 5 uint32, 6 int32, 7 uint64, 8 int64, 9 float16, 10 float32, 11 float64.
//
// The reader checks the container (not the fields' meaning, rgl/rgl_material.h does that): every
// read within the file, the field count and shapes bounded by the file's size (no allocation from an
// unchecked header value), known dtypes, no duplicate names, data inside the file. InputError
// names the file, the field and the problem.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace aniso::rgl {

enum class Dtype : uint8_t { Invalid = 0, UInt8, Int8, UInt16, Int16, UInt32, Int32, UInt64, Int64, Float16, Float32, Float64 };
const char* dtype_name(Dtype t);
size_t dtype_size(Dtype t);  // 0 for Invalid

struct TensorField {
  std::string name;
  Dtype dtype = Dtype::Invalid;
  std::vector<uint64_t> shape;
  uint64_t offset = 0;         // where the data was (reading) or will be (writing)
  std::vector<uint8_t> bytes;  // dtype_size * product(shape) bytes, little-endian

  uint64_t count() const;  // product of the shape (1 for ndim 0)
  // float32 data as floats (the caller has checked dtype == Float32).
  std::vector<float> floats() const;
  std::string shape_string() const;  // "[1, 16, 3, 32, 32]"
};

TensorField make_field(std::string name, std::vector<uint64_t> shape, std::span<const float> data);
TensorField make_field(std::string name, std::vector<uint64_t> shape, std::span<const uint8_t> data);

struct TensorFile {
  std::string source;               // the file name, for messages
  uint64_t size = 0;                // bytes
  std::vector<TensorField> fields;  // in the order of the field table
  const TensorField* find(std::string_view name) const;
};

// Parses a whole file held in memory; `where` names it in messages.
TensorFile parse_tensor(std::span<const uint8_t> bytes, const std::string& where);
// Reads and parses a file (InputError if it cannot be opened or is invalid).
TensorFile read_tensor_file(const std::string& path);
// The bytes of a file holding these fields (offsets assigned here, aligned to 8); the caller writes
// them atomically (io/atomic_file.h, write_file_atomically).
std::vector<uint8_t> serialize_tensor(std::vector<TensorField> fields);

}  // namespace aniso::rgl
