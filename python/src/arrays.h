// python/src/arrays.h: NumPy arrays of directions in, batch::* on chunks, NumPy arrays out.
//
// NumPy users hold (N, 3) arrays, C-contiguous or not, float32 or float64. C-ordered rows (and
// (3,) broadcasts) go to the batch API's interleaved entry points in place
// (batch::evaluate_interleaved / pdf_interleaved), column-major arrays to its structure-of-arrays
// functions in place (bind_batch.cpp). Any other layout takes the general path: each oneTBB task
// takes a chunk of kChunk rows, copies them into SoA buffers of its own (strided gather, any
// source dtype), calls the batch function with Threads::One on them, and writes the chunk's
// results into the output. The chunk's buffers stay in the core's L2 (4096 rows x 15 doubles =
// 480 KiB), so the transposition costs a pass over cached data, and every element's result is
// the batch API's (each element depends only on its own inputs, batch.h).
#pragma once

#include <cstring>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace aniso::python {

namespace py = pybind11;

// One (N, 3) or (3,) input array, as strides into its buffer. A (3,) input broadcasts against
// the other inputs (row stride 0).
struct RowsView {
  const char* data = nullptr;
  py::ssize_t row_stride = 0, col_stride = 0;
  size_t rows = 1;      // 1 for a (3,) input
  bool single = false;  // given as (3,)
  bool f32 = false;     // float32 (else float64: other real dtypes are converted first)
  py::array keep;       // owns the (possibly converted) buffer

  // memcpy: a NumPy buffer need not be aligned to its dtype (a view at a byte offset).
  template <typename T> T at(size_t row, int col) const {
    const char* p = data + py::ssize_t(single ? 0 : row) * row_stride + col * col_stride;
    if (f32) {
      float v;
      std::memcpy(&v, p, sizeof v);
      return T(v);
    }
    double v;
    std::memcpy(&v, p, sizeof v);
    return T(v);
  }
};

// Reads `obj` as an (N, 3) or (3,) real array; `name` is the argument's name for messages.
// float32 and float64 are used as they are (any strides); integers and float16 are converted to
// float64 (exactly); long double (float96, float128) is a ValueError rather than rounded unasked,
// as is anything else (complex, bool, object, strings) and any other shape.
RowsView rows_view(const py::handle& obj, const char* name, int columns = 3);

// The common row count of the inputs: equal, or 1 for a (3,) input that broadcasts. ValueError
// otherwise, naming the arguments.
size_t common_rows(std::initializer_list<std::pair<const char*, const RowsView*>> inputs);

// True when every input is float32: the computation then runs in float (MaterialT<float>),
// otherwise in double.
inline bool all_f32(std::initializer_list<const RowsView*> inputs) {
  for (const RowsView* v : inputs)
    if (!v->f32) return false;
  return true;
}

// The shape description of an array for messages: "(4, 2)", "()".
std::string shape_text(const py::array& a);

// A new result array: (columns,) for one row, else (n, columns).
template <typename T> py::array_t<T> rows_out(size_t n, bool single, int columns) {
  if (single) return py::array_t<T>(std::vector<py::ssize_t>{columns});
  return py::array_t<T>(std::vector<py::ssize_t>{py::ssize_t(n), columns});
}

// An undefined result: a row with a NaN or infinite input, a NaN cosine (docs/python.md).
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace aniso::python
