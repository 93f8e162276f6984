// python/src/bind_frame.cpp: aniso.Frame, the tangent frame that orients anisotropy
// (aniso/core/frame.h), and the direction arguments it reads.
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "aniso/core/frame.h"
#include "bindings.h"

namespace aniso::python {

namespace {

Vec3d vec3_arg(const py::object& obj, const char* name) {
  const RowsView v = rows_view(obj, name);
  if (!v.single) throw py::value_error(fmt::format("{}: expected one direction of shape (3,), got {} rows", name, v.rows));
  const Vec3d w(v.at<double>(0, 0), v.at<double>(0, 1), v.at<double>(0, 2));
  if (!(std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z)))
    throw py::value_error(fmt::format("{}: expected finite values, got ({}, {}, {})", name, w.x, w.y, w.z));
  return w;
}

Vec3d unit_arg(const py::object& obj, const char* name) {
  const Vec3d w = vec3_arg(obj, name);
  const double len = glm::length(w);
  if (!(len > 0.0)) throw py::value_error(fmt::format("{}: expected a non-zero direction, got (0, 0, 0)", name));
  return w / len;
}

}  // namespace

py::array_t<double> vec3_py(const Vec3d& v) {
  py::array_t<double> a(3);
  a.mutable_at(0) = v.x, a.mutable_at(1) = v.y, a.mutable_at(2) = v.z;
  return a;
}

namespace {

// w as rows, each mapped by fn (double precision), returned in the input's precision and shape.
template <typename Fn> py::array map_rows(const py::object& w_in, const char* name, Fn fn) {
  const RowsView w = rows_view(w_in, name);
  const size_t n = w.single ? 1 : w.rows;
  py::array_t<double> out = rows_out<double>(n, w.single, 3);
  double* o = out.mutable_data();
  for (size_t i = 0; i < n; ++i) {
    const Vec3d r = fn(Vec3d(w.at<double>(i, 0), w.at<double>(i, 1), w.at<double>(i, 2)));
    o[3 * i] = r.x, o[3 * i + 1] = r.y, o[3 * i + 2] = r.z;
  }
  if (w.f32) return out.attr("astype")("float32");
  return out;
}

}  // namespace

void bind_frame(py::module_& m) {
  py::class_<FrameT<double>>(m, "Frame",
                             "An orthonormal tangent frame (t, b = n x t, n) that orients anisotropy (aniso/core/frame.h).\n\n"
                             "Frame(n, t=None): from a normal and an approximate tangent (Gram-Schmidt), or any frame\n"
                             "about n without t (Duff et al. 2017). n and t need not be unit; t parallel to n is a ValueError.")
      .def(py::init([](const py::object& n, const py::object& t) {
             const Vec3d nn = unit_arg(n, "n");
             if (t.is_none()) return FrameT<double>::from_normal(nn);
             // from_normal_tangent falls back to an arbitrary frame when t is (nearly) parallel to n:
             // here that is an error, as the caller asked for a tangent direction.
             const Vec3d tu = unit_arg(t, "t"), t_perp = tu - glm::dot(tu, nn) * nn;
             if (!(glm::dot(t_perp, t_perp) > 1e-12))
               throw py::value_error(
                   fmt::format("t: ({:.6g}, {:.6g}, {:.6g}) is parallel to n, so it gives no tangent direction "
                               "(its part perpendicular to n is below 1e-6 of its length); give a t "
                               "across n, or no t for any frame about n",
                               tu.x, tu.y, tu.z));
             return FrameT<double>::from_normal_tangent(nn, tu);
           }),
           py::arg("n") = py::make_tuple(0.0, 0.0, 1.0), py::arg("t") = py::none())
      .def_property_readonly(
          "t", [](const FrameT<double>& f) { return vec3_py(f.t); }, "tangent (x of the local frame)")
      .def_property_readonly(
          "b", [](const FrameT<double>& f) { return vec3_py(f.b); }, "bitangent n x t (y)")
      .def_property_readonly(
          "n", [](const FrameT<double>& f) { return vec3_py(f.n); }, "normal (z)")
      .def_property_readonly(
          "matrix",
          [](const FrameT<double>& f) {
            py::array_t<double> a({3, 3});
            for (int c = 0; c < 3; ++c) a.mutable_at(0, c) = f.t[c], a.mutable_at(1, c) = f.b[c], a.mutable_at(2, c) = f.n[c];
            return a;
          },
          "rows t, b, n: matrix @ w is to_local(w)")
      .def(
          "to_local",
          [](const FrameT<double>& f, const py::object& w) {
            return map_rows(w, "w", [&](const Vec3d& v) { return f.to_local(v); });
          },
          py::arg("w"), "World directions (N, 3) or (3,) into this frame: (w.t, w.b, w.n).")
      .def(
          "to_world",
          [](const FrameT<double>& f, const py::object& w) {
            return map_rows(w, "w", [&](const Vec3d& v) { return f.to_world(v); });
          },
          py::arg("w"), "Local directions (N, 3) or (3,) into world space: x t + y b + z n.")
      .def("rotated", &FrameT<double>::rotated, py::arg("psi"),
           "The frame with t and b rotated about n by psi radians (the scenes' angle_deg): t' = cos psi t + sin psi b.")
      .def("__repr__", [](const FrameT<double>& f) {
        return fmt::format("aniso.Frame(t=({:.6g}, {:.6g}, {:.6g}), b=({:.6g}, {:.6g}, {:.6g}), n=({:.6g}, {:.6g}, {:.6g}))",
                           f.t.x, f.t.y, f.t.z, f.b.x, f.b.y, f.b.z, f.n.x, f.n.y, f.n.z);
      });
}

}  // namespace aniso::python
