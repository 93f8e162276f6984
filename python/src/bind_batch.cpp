// python/src/bind_batch.cpp: Material.eval, .pdf, .sample and .albedo on the caller's NumPy arrays,
// through the batch API (aniso/batch/batch.h) on chunks (arrays.h), the GIL released; and
// aniso.simd_target().
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "aniso/batch/batch.h"
#include "aniso/stats/albedo.h"
#include "bindings.h"
#include "io/text_input.h"
#include "transpose.h"

namespace aniso::python {

namespace {

// Rows per task: 4096 rows of 10 double arrays (wi, wo, f, pdf) are 320 KiB, inside one core's
// L2; and 4096 is the batch API's own block size (docs/performance.md), so a chunk is one block.
constexpr size_t kChunk = 4096;

template <typename Fn> void for_chunks(size_t n, Fn&& fn) {
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, n, kChunk),
      [&](const tbb::blocked_range<size_t>& r) {
        for (size_t b = r.begin(); b < r.end(); b += kChunk) fn(b, std::min(r.end(), b + kChunk));
      },
      tbb::simple_partitioner());
}

// Scratch arrays of one thread, reused across calls.
template <typename T> T* scratch(size_t arrays) {
  thread_local std::vector<T> buf;
  if (buf.size() < arrays * kChunk) buf.resize(arrays * kChunk);
  return buf.data();
}

template <typename T, typename S> void gather_as(const RowsView& v, size_t begin, size_t len, T* x, T* y, T* z, uint8_t* bad) {
  const py::ssize_t rs = v.single ? 0 : v.row_stride, cs = v.col_stride;
  const char* base = v.data + py::ssize_t(v.single ? 0 : begin) * rs;
  for (size_t i = 0; i < len; ++i) {
    const char* p = base + py::ssize_t(i) * rs;
    S a, b, c;  // memcpy: NumPy buffers need not be aligned
    std::memcpy(&a, p, sizeof a);
    std::memcpy(&b, p + cs, sizeof b);
    std::memcpy(&c, p + 2 * cs, sizeof c);
    x[i] = T(a), y[i] = T(b), z[i] = T(c);
    bad[i] |= uint8_t(!(std::isfinite(a) && std::isfinite(b) && std::isfinite(c)));
  }
}

// Rows [begin, begin + len) of v as three arrays; bad[i] is set where a value is NaN or infinite.
// Contiguous rows (a C-ordered (N, 3) array, aligned) take the vectorised loops of transpose.h.
template <typename T> void gather(const RowsView& v, size_t begin, size_t len, T* x, T* y, T* z, uint8_t* bad) {
  const size_t item = v.f32 ? sizeof(float) : sizeof(double);
  const bool contiguous = !v.single && v.col_stride == py::ssize_t(item) && v.row_stride == py::ssize_t(3 * item) &&
                          reinterpret_cast<uintptr_t>(v.data) % item == 0;
  if (contiguous && v.f32) return deinterleave(reinterpret_cast<const float*>(v.data) + 3 * begin, len, x, y, z, bad);
  if constexpr (std::is_same_v<T, double>)
    if (contiguous) return deinterleave(reinterpret_cast<const double*>(v.data) + 3 * begin, len, x, y, z, bad);
  if (v.f32)
    gather_as<T, float>(v, begin, len, x, y, z, bad);
  else
    gather_as<T, double>(v, begin, len, x, y, z, bad);
}

// The three columns of v as arrays the batch API can read in place: v holds T and each column is
// contiguous (a Fortran-ordered (N, 3) array, or the transpose of a C-ordered (3, N) one). Sets
// bad[i] for NaN / Inf rows, as gather() does; false (nothing done) for any other layout.
template <typename T> bool columns_in_place(const RowsView& v, size_t begin, size_t len, const T** xyz, uint8_t* bad) {
  if (v.single || v.f32 != std::is_same_v<T, float> || v.row_stride != py::ssize_t(sizeof(T)) ||
      reinterpret_cast<uintptr_t>(v.data) % sizeof(T) != 0)
    return false;
  for (int c = 0; c < 3; ++c) xyz[c] = reinterpret_cast<const T*>(v.data + c * v.col_stride) + begin;
  mark_nonfinite(xyz[0], xyz[1], xyz[2], len, bad);
  return true;
}

// The columns of v as the batch API's structure of arrays, read in place: v holds T, each column
// contiguous and aligned (Fortran order, or the transpose of a C-ordered (3, N) array). False
// otherwise (nothing set).
template <typename T> bool column_arrays(const RowsView& v, batch::Directions<T>& out) {
  if (v.single || v.f32 != std::is_same_v<T, float> || v.row_stride != py::ssize_t(sizeof(T)) ||
      reinterpret_cast<uintptr_t>(v.data) % sizeof(T) != 0)
    return false;
  out = {reinterpret_cast<const T*>(v.data), reinterpret_cast<const T*>(v.data + v.col_stride),
         reinterpret_cast<const T*>(v.data + 2 * v.col_stride)};
  return true;
}

template <typename T> py::object scalar_or_rows(py::array_t<T> a, bool single) {
  if (single) return a[py::int_(0)];  // a NumPy scalar of the array's dtype
  return a;
}

// The caller's `out` array, checked: the dtype the computation runs in, the result's shape,
// C-contiguous and writeable. None: a new array.
template <typename T>
py::array_t<T> out_array(const py::object& out, size_t n, bool single, int columns, const char* name = "out") {
  if (out.is_none()) {
    if (columns == 0) return py::array_t<T>(std::vector<py::ssize_t>{single ? 1 : py::ssize_t(n)});
    return rows_out<T>(n, single, columns);
  }
  const char* dtype = std::is_same_v<T, float> ? "float32" : "float64";
  const std::string shape = columns == 0 ? (single ? "()" : fmt::format("({},)", n))
                                         : (single ? fmt::format("({},)", columns) : fmt::format("({}, {})", n, columns));
  const std::string want = fmt::format(
      "{}: expected a writeable C- or Fortran-contiguous {} array of shape {} (the inputs' dtype and rows)", name, dtype, shape);
  if (!py::isinstance<py::array>(out))
    throw py::value_error(fmt::format("{}, got {}", want, std::string(py::str(py::type::of(out).attr("__name__")))));
  const py::array a = out.cast<py::array>();
  std::vector<py::ssize_t> expected;
  if (columns == 0) {
    if (!single) expected.push_back(py::ssize_t(n));
  } else {
    if (!single) expected.push_back(py::ssize_t(n));
    expected.push_back(columns);
  }
  const bool shape_ok = a.ndim() == py::ssize_t(expected.size()) && std::equal(expected.begin(), expected.end(), a.shape());
  const bool contiguous = (a.flags() & py::array::c_style) || (a.flags() & py::array::f_style);
  if (!py::isinstance<py::array_t<T>>(a) || !shape_ok || !contiguous || !a.writeable())
    throw py::value_error(fmt::format("{}, got {} of shape {}{}{}", want, std::string(py::str(a.dtype())), shape_text(a),
                                      contiguous ? "" : ", not contiguous", a.writeable() ? "" : ", read-only"));
  if (columns == 0 && single) return py::array_t<T>(a.attr("reshape")(1));  // a view of the 0-d array
  return py::reinterpret_borrow<py::array_t<T>>(a);  // as it is (array_t's converting constructor would make it C-ordered)
}

// v as the batch API's interleaved rows (batch::Interleaved): C-ordered rows of T, aligned to T, read
// in place; or a (3,) input, converted into `row` and broadcast (stride 0). False for other layouts
// (Fortran order, slices, another dtype), which take the chunked path below.
template <typename T> bool interleaved_rows(const RowsView& v, T (&row)[3], batch::Interleaved<T>& out) {
  if (v.single) {
    for (int c = 0; c < 3; ++c) row[c] = v.at<T>(0, c);
    out = {row, 0};
    return true;
  }
  if (v.f32 != std::is_same_v<T, float> || v.col_stride != py::ssize_t(sizeof(T)) || v.row_stride != py::ssize_t(3 * sizeof(T)) ||
      reinterpret_cast<uintptr_t>(v.data) % sizeof(T) != 0)
    return false;
  out = {reinterpret_cast<const T*>(v.data), 3};
  return true;
}

template <typename T> py::array_t<T> eval_typed(const MaterialT<T>& m, const RowsView& wi, const RowsView& wo, size_t n,
                                                bool single, const py::object& out_in) {
  py::array_t<T> out = out_array<T>(out_in, n, single, 3);
  T* f = out.mutable_data();
  // A Fortran-ordered `out` (columns contiguous) is written in place, without the interleave.
  const bool out_columns = !single && n > 1 && (out.flags() & py::array::f_style);
  // C-ordered rows in and out (the default layout) go to the batch API as they are: its kernels
  // load and store interleaved rows and write NaN rows themselves, one pass over the memory.
  T row_i[3], row_o[3];
  batch::Interleaved<T> ri, ro;
  if (!out_columns && interleaved_rows(wi, row_i, ri) && interleaved_rows(wo, row_o, ro)) {
    py::gil_scoped_release release;
    batch::evaluate_interleaved(m, ri, ro, n, f, batch::Threads::All, batch::Kernels::Simd, batch::NonFinite::NaN);
    return out;
  }
  // Column-major in and out likewise, through the structure-of-arrays entry point.
  batch::Directions<T> ci, co;
  if (out_columns && column_arrays(wi, ci) && column_arrays(wo, co)) {
    py::gil_scoped_release release;
    batch::evaluate(m, ci, co, n, {f, f + n, f + 2 * n}, batch::Threads::All, batch::Kernels::Simd, batch::NonFinite::NaN);
    return out;
  }
  {
    py::gil_scoped_release release;
    for_chunks(n, [&](size_t begin, size_t end) {
      const size_t len = end - begin;
      T* s = scratch<T>(9);
      uint8_t bad[kChunk] = {};
      const T *a[3] = {s, s + kChunk, s + 2 * kChunk}, *b[3] = {s + 3 * kChunk, s + 4 * kChunk, s + 5 * kChunk};
      if (!columns_in_place(wi, begin, len, a, bad)) gather(wi, begin, len, s, s + kChunk, s + 2 * kChunk, bad);
      if (!columns_in_place(wo, begin, len, b, bad)) gather(wo, begin, len, s + 3 * kChunk, s + 4 * kChunk, s + 5 * kChunk, bad);
      T* rgb[3] = {s + 6 * kChunk, s + 7 * kChunk, s + 8 * kChunk};
      if (out_columns)
        for (int c = 0; c < 3; ++c) rgb[c] = f + c * n + begin;
      batch::evaluate(m, {a[0], a[1], a[2]}, {b[0], b[1], b[2]}, len, {rgb[0], rgb[1], rgb[2]}, batch::Threads::One);
      // NaN rows for NaN / Inf input (docs/python.md).
      if (out_columns)
        for (int c = 0; c < 3; ++c) mark_bad(rgb[c], len, bad);
      else
        interleave(f + 3 * begin, len, rgb[0], rgb[1], rgb[2], bad);
    });
  }
  return out;
}

template <typename T> py::array_t<T> pdf_typed(const MaterialT<T>& m, const RowsView& wi, const RowsView& wo, size_t n,
                                               bool single, const py::object& out_in) {
  py::array_t<T> out = out_array<T>(out_in, n, single, 0);
  T* p = out.mutable_data();
  T row_i[3], row_o[3];
  batch::Interleaved<T> ri, ro;
  batch::Directions<T> ci, co;
  if (interleaved_rows(wi, row_i, ri) && interleaved_rows(wo, row_o, ro)) {  // as in eval_typed
    py::gil_scoped_release release;
    batch::pdf_interleaved(m, ri, ro, n, p, batch::Threads::All, batch::Kernels::Simd, batch::NonFinite::NaN);
    return out;
  }
  if (column_arrays(wi, ci) && column_arrays(wo, co)) {
    py::gil_scoped_release release;
    batch::pdf(m, ci, co, n, p, batch::Threads::All, batch::Kernels::Simd, batch::NonFinite::NaN);
    return out;
  }
  {
    py::gil_scoped_release release;
    for_chunks(n, [&](size_t begin, size_t end) {
      const size_t len = end - begin;
      T* s = scratch<T>(6);
      uint8_t bad[kChunk] = {};
      const T *a[3] = {s, s + kChunk, s + 2 * kChunk}, *b[3] = {s + 3 * kChunk, s + 4 * kChunk, s + 5 * kChunk};
      if (!columns_in_place(wi, begin, len, a, bad)) gather(wi, begin, len, s, s + kChunk, s + 2 * kChunk, bad);
      if (!columns_in_place(wo, begin, len, b, bad)) gather(wo, begin, len, s + 3 * kChunk, s + 4 * kChunk, s + 5 * kChunk, bad);
      batch::pdf(m, {a[0], a[1], a[2]}, {b[0], b[1], b[2]}, len, p + begin, batch::Threads::One);
      mark_bad(p + begin, len, bad);
    });
  }
  return out;
}

// Directions as the CLI reads them (io/text_input.h, normalized_direction): normalised, a zero one
// an error naming its row. Rows of unit length already (|w|^2 within kUnitSlack of 1, a few
// roundings of the input's float type) are read as they are, so that the usual input is used in
// place; otherwise a normalised copy (same dtype, C order) replaces the input. Rows with NaN or
// Inf stay as they are (their results are NaN, docs/python.md).
void normalize_rows(RowsView& v, const char* name) {
  const double slack = v.f32 ? 4e-7 : 1e-15;  // ~4 float / ~5 double roundings of |w|^2
  bool unit = true;
  {
    py::gil_scoped_release release;
    for (size_t r = 0; r < v.rows && unit; ++r) {
      const double x = v.at<double>(r, 0), y = v.at<double>(r, 1), z = v.at<double>(r, 2);
      const bool finite = std::isfinite(x) && std::isfinite(y) && std::isfinite(z);  // NaN, Inf: as they are
      unit = !finite || std::abs(x * x + y * y + z * z - 1.0) <= slack;
    }
  }
  if (unit) return;
  const py::ssize_t rows = py::ssize_t(v.rows);
  py::array copy =
      v.f32 ? py::array(py::array_t<float>({rows, py::ssize_t(3)})) : py::array(py::array_t<double>({rows, py::ssize_t(3)}));
  char* base = static_cast<char*>(copy.mutable_data());
  size_t zero_row = SIZE_MAX;
  {
    py::gil_scoped_release release;
    for (size_t r = 0; r < v.rows; ++r) {
      const Vec3d w(v.at<double>(r, 0), v.at<double>(r, 1), v.at<double>(r, 2));
      Vec3d u = w;
      if (std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z)) {
        const auto nw = normalized_direction(w);
        if (!nw) {
          zero_row = r;
          break;
        }
        u = *nw;
      }
      for (int c = 0; c < 3; ++c) {
        if (v.f32)
          reinterpret_cast<float*>(base)[3 * r + size_t(c)] = float(u[c]);
        else
          reinterpret_cast<double*>(base)[3 * r + size_t(c)] = u[c];
      }
    }
  }
  if (zero_row != SIZE_MAX)
    throw py::value_error(v.single ? fmt::format("{}: expected a non-zero direction, got (0, 0, 0)", name)
                                   : fmt::format("{}[{}]: expected a non-zero direction, got (0, 0, 0)", name, zero_row));
  const bool single = v.single;
  v = rows_view(single ? copy.attr("reshape")(3) : py::object(copy), name);
}

}  // namespace

py::object material_eval(const PyMaterial& m, const py::object& wi_in, const py::object& wo_in, const py::object& out) {
  RowsView wi = rows_view(wi_in, "wi"), wo = rows_view(wo_in, "wo");
  const size_t n = common_rows({{"wi", &wi}, {"wo", &wo}});
  normalize_rows(wi, "wi");
  normalize_rows(wo, "wo");
  const bool single = wi.single && wo.single;
  if (all_f32({&wi, &wo})) return eval_typed<float>(m.mf, wi, wo, n, single, out);
  return eval_typed<double>(m.md, wi, wo, n, single, out);
}

py::object material_pdf(const PyMaterial& m, const py::object& wi_in, const py::object& wo_in, const py::object& out) {
  RowsView wi = rows_view(wi_in, "wi"), wo = rows_view(wo_in, "wo");
  const size_t n = common_rows({{"wi", &wi}, {"wo", &wo}});
  normalize_rows(wi, "wi");
  normalize_rows(wo, "wo");
  const bool single = wi.single && wo.single;
  if (!out.is_none()) {  // the caller's array, as given (0-d for one pair)
    if (all_f32({&wi, &wo}))
      pdf_typed<float>(m.mf, wi, wo, n, single, out);
    else
      pdf_typed<double>(m.md, wi, wo, n, single, out);
    return out;
  }
  if (all_f32({&wi, &wo})) return scalar_or_rows(pdf_typed<float>(m.mf, wi, wo, n, single, out), single);
  return scalar_or_rows(pdf_typed<double>(m.md, wi, wo, n, single, out), single);
}

namespace {

// The samplers take uniforms in [0, 1); 1 itself (a float64 uniform rounded to float32 can become 1)
// is taken as the largest number below 1. True when u needs no change.
template <typename T> bool uniforms_ok(const T* uc, const T* u0, const T* u1, size_t len) {
  bool ok = true;
  for (size_t i = 0; i < len; ++i)
    ok &= (uc[i] >= T(0)) & (uc[i] < T(1)) & (u0[i] >= T(0)) & (u0[i] < T(1)) & (u1[i] >= T(0)) & (u1[i] < T(1));
  return ok;
}

template <typename T> py::tuple sample_typed(const MaterialT<T>& m, const RowsView& wo, const RowsView& u, size_t n, bool single,
                                             const py::object& out) {
  py::array_t<T> wi_out, weight_out, pdf_out;
  if (out.is_none()) {
    wi_out = rows_out<T>(n, single, 3), weight_out = rows_out<T>(n, single, 3);
    pdf_out = py::array_t<T>(std::vector<py::ssize_t>{single ? 1 : py::ssize_t(n)});
  } else {
    if (!(py::isinstance<py::tuple>(out) || py::isinstance<py::list>(out)) || py::len(out) != 3)
      throw py::value_error(fmt::format("out: expected a tuple of three arrays (wi, weight, pdf), got {}",
                                        std::string(py::str(py::type::of(out).attr("__name__")))));
    const py::sequence o = out.cast<py::sequence>();
    wi_out = out_array<T>(o[0], n, single, 3, "out[0] (wi)");
    weight_out = out_array<T>(o[1], n, single, 3, "out[1] (weight)");
    pdf_out = out_array<T>(o[2], n, single, 0, "out[2] (pdf)");
  }
  T *wi = wi_out.mutable_data(), *w = weight_out.mutable_data(), *p = pdf_out.mutable_data();
  // Fortran-ordered outputs (columns contiguous) are written in place, as eval's.
  const bool wi_columns = !single && n > 1 && (wi_out.flags() & py::array::f_style);
  const bool weight_columns = !single && n > 1 && (weight_out.flags() & py::array::f_style);
  std::atomic<size_t> first_out_of_range{SIZE_MAX};
  {
    py::gil_scoped_release release;
    for_chunks(n, [&](size_t begin, size_t end) {
      const size_t len = end - begin;
      T* s = scratch<T>(12);
      uint8_t bad[kChunk] = {}, valid[kChunk];
      const T* o[3] = {s, s + kChunk, s + 2 * kChunk};
      T *uc = s + 3 * kChunk, *u0 = s + 4 * kChunk, *u1 = s + 5 * kChunk;
      // Column-major wo and u are read in place (u when it needs no change), as eval reads wi, wo.
      const T* uu[3];
      bool u_in_place = columns_in_place(u, begin, len, uu, bad);
      if (u_in_place && !uniforms_ok(uu[0], uu[1], uu[2], len)) {
        std::fill(bad, bad + len, uint8_t(0));  // gather marks the rows again
        u_in_place = false;
      }
      if (!u_in_place) {
        gather(u, begin, len, uc, u0, u1, bad);
        const T below_one = std::nextafter(T(1), T(0));
        for (size_t i = 0; i < len; ++i) {
          for (T* c : {uc + i, u0 + i, u1 + i}) {
            if (*c >= T(0) && *c < T(1)) continue;
            if (*c == T(1))
              *c = below_one;
            else if (!std::isnan(*c)) {
              size_t cur = first_out_of_range.load();
              while (begin + i < cur && !first_out_of_range.compare_exchange_weak(cur, begin + i)) {}
              *c = T(0);
            }
          }
        }
        uu[0] = uc, uu[1] = u0, uu[2] = u1;
      }
      if (!columns_in_place(wo, begin, len, o, bad)) gather(wo, begin, len, s, s + kChunk, s + 2 * kChunk, bad);
      T* col[6] = {s + 6 * kChunk, s + 7 * kChunk, s + 8 * kChunk, s + 9 * kChunk, s + 10 * kChunk, s + 11 * kChunk};
      if (wi_columns)
        for (int c = 0; c < 3; ++c) col[c] = wi + c * n + begin;
      if (weight_columns)
        for (int c = 0; c < 3; ++c) col[3 + c] = w + c * n + begin;
      batch::Samples<T> r{col[0], col[1], col[2], col[3], col[4], col[5], p + begin, valid};
      batch::sample(m, {o[0], o[1], o[2]}, uu[0], uu[1], uu[2], len, r, batch::Threads::One);
      // NaN rows for NaN / Inf input (docs/python.md).
      if (wi_columns)
        for (int c = 0; c < 3; ++c) mark_bad(col[c], len, bad);
      else
        interleave(wi + 3 * begin, len, col[0], col[1], col[2], bad);
      if (weight_columns)
        for (int c = 0; c < 3; ++c) mark_bad(col[3 + c], len, bad);
      else
        interleave(w + 3 * begin, len, col[3], col[4], col[5], bad);
      mark_bad(p + begin, len, bad);
    });
  }
  if (const size_t row = first_out_of_range.load(); row != SIZE_MAX) {
    double value = 0.0;
    for (int c = 0; c < 3; ++c)
      if (const double x = u.at<double>(row, c); !(x >= 0.0 && x <= 1.0)) value = x;
    throw py::value_error(fmt::format("u: expected uniforms in [0, 1), got {} in row {}", value, u.single ? 0 : row));
  }
  if (!out.is_none()) return py::make_tuple(wi_out, weight_out, out.cast<py::sequence>()[2]);
  return py::make_tuple(wi_out, weight_out, scalar_or_rows(pdf_out, single));
}

}  // namespace

py::tuple material_sample(const PyMaterial& m, const py::object& wo_in, const py::object& u_in, const py::object& out) {
  RowsView wo = rows_view(wo_in, "wo");
  const RowsView u = rows_view(u_in, "u");
  const size_t n = common_rows({{"wo", &wo}, {"u", &u}});
  normalize_rows(wo, "wo");
  const bool single = wo.single && u.single;
  if (all_f32({&wo, &u})) return sample_typed<float>(m.mf, wo, u, n, single, out);
  return sample_typed<double>(m.md, wo, u, n, single, out);
}

namespace {

// The largest albedo sample count, as `aniso albedo --samples` allows.
constexpr int64_t kMaxAlbedoSamples = 1'000'000'000;

}  // namespace

py::object material_albedo(const PyMaterial& m, const py::object& theta_in, double phi, int64_t samples, uint64_t seed,
                           bool return_error) {
  if (samples < 1 || samples > kMaxAlbedoSamples)
    throw py::value_error(fmt::format("samples: expected a whole number in [1, {}], got {}", kMaxAlbedoSamples, samples));
  if (!std::isfinite(phi)) throw py::value_error(fmt::format("phi: expected a finite angle in radians, got {}", phi));
  const py::module_ np = py::module_::import("numpy");
  // Numbers only: NumPy would read the text "0.3" as 0.3 (the CLI's --theta-deg takes text; a
  // Python argument is a number). Real dtypes as rows_view reads them (arrays.h).
  const py::array given = np.attr("asarray")(theta_in);
  const char kind = given.dtype().kind();
  if (!(kind == 'f' || kind == 'i' || kind == 'u') || (kind == 'f' && given.dtype().itemsize() > 8))
    throw py::value_error(
        fmt::format("theta: expected a number or an array of float16, float32, float64 or integers (radians), got {} of dtype {}",
                    std::string(py::str(py::type::of(theta_in).attr("__name__"))), std::string(py::str(given.dtype()))));
  const py::array_t<double, py::array::c_style | py::array::forcecast> theta = np.attr("asarray")(given, "float64");
  if (theta.ndim() > 1)
    throw py::value_error(fmt::format("theta: expected a number or an array of shape (N,), got shape {}", shape_text(theta)));
  const size_t n = size_t(theta.size());
  const double* t = theta.data();
  for (size_t i = 0; i < n; ++i)
    if (!(t[i] >= 0.0 && t[i] <= M_PI / 2) && !std::isnan(t[i]))
      throw py::value_error(fmt::format("theta: expected viewing angles in [0, pi/2] radians from the normal, got {}", t[i]));
  const bool single = theta.ndim() == 0;
  py::array_t<double> mean = rows_out<double>(n, single, 3), err = rows_out<double>(n, single, 3);
  double *pm = mean.mutable_data(), *pe = err.mutable_data();
  {
    py::gil_scoped_release release;
    for (size_t i = 0; i < n; ++i) {
      if (std::isnan(t[i])) {
        for (int c = 0; c < 3; ++c) pm[3 * i + c] = pe[3 * i + c] = kNaN;
        continue;
      }
      // As `aniso albedo` (direction_from_degrees, src/io/text_input.cpp), in radians.
      const Vec3d wo(std::sin(t[i]) * std::cos(phi), std::sin(t[i]) * std::sin(phi), std::cos(t[i]));
      const AlbedoEstimate a = albedo_importance(m.md, wo, samples, seed);
      for (int c = 0; c < 3; ++c) pm[3 * i + c] = a.mean[c], pe[3 * i + c] = a.std_error[c];
    }
  }
  if (return_error) return py::make_tuple(mean, err);
  return mean;
}

void bind_batch(py::module_& m) {
  m.def(
      "simd_target", [] { return std::string(batch::simd_target()); },
      "The SIMD target the batch path runs on this machine (\"AVX3\", \"AVX2\", ...).");
}

}  // namespace aniso::python
