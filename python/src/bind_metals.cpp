// python/src/bind_metals.cpp: the measured metals (src/data/metals.cpp) and conductor Fresnel
// reflectance, as `aniso metals` and `aniso fresnel`: aniso.metals(), aniso.fresnel().
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "aniso/brdf/fresnel.h"
#include "aniso/data/metals.h"
#include "bindings.h"

namespace aniso::python {

namespace {

glm::dvec3 rgb_arg(const py::object& obj, const char* name, double lo, bool lo_exclusive, double hi) {
  const py::module_ np = py::module_::import("numpy");
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = np.attr("asarray")(obj, "float64");
  } catch (py::error_already_set& e) {
    throw py::value_error(fmt::format("{}: expected a number or [r, g, b] ({})", name, e.what()));
  }
  if (!(a.size() == 1 || (a.ndim() == 1 && a.size() == 3)))
    throw py::value_error(fmt::format("{}: expected a number or [r, g, b], got shape {}", name, shape_text(a)));
  glm::dvec3 c;
  for (int i = 0; i < 3; ++i) {
    c[i] = a.data()[a.size() == 1 ? 0 : i];
    if (!((lo_exclusive ? c[i] > lo : c[i] >= lo) && c[i] <= hi))
      throw py::value_error(
          fmt::format("{}: channel {}: expected a number in {}{}, {}], got {}", name, i, lo_exclusive ? "(" : "[", lo, hi, c[i]));
  }
  return c;
}

py::array fresnel_py(const py::object& cos_in, const py::object& metal, const py::object& eta_in, const py::object& k_in,
                     bool schlick) {
  glm::dvec3 eta, k;
  if (!metal.is_none()) {
    if (!eta_in.is_none() || !k_in.is_none()) throw py::value_error("give either metal or eta and k, not both");
    const std::string name = py::str(metal);
    const MetalData* md = find_metal(name);
    if (!md) throw py::value_error(fmt::format("metal: {}", unknown_metal_message(name)));
    eta = md->eta, k = md->k;
  } else {
    if (eta_in.is_none() || k_in.is_none())
      throw py::value_error(fmt::format("give metal=NAME (one of {}) or both eta=[r, g, b] and k=[r, g, b]", metal_names()));
    eta = rgb_arg(eta_in, "eta", 0.0, true, 100.0);  // the ranges of `aniso fresnel --eta --k`
    k = rgb_arg(k_in, "k", 0.0, false, 100.0);
  }
  const py::module_ np = py::module_::import("numpy");
  const py::array_t<double, py::array::c_style | py::array::forcecast> c = np.attr("asarray")(cos_in, "float64");
  std::vector<py::ssize_t> shape(c.shape(), c.shape() + c.ndim());
  shape.push_back(3);
  py::array_t<double> out(shape);
  double* o = out.mutable_data();
  const double* ci = c.data();
  const RGBT<double> e(eta), kk(k);
  for (py::ssize_t i = 0; i < c.size(); ++i) {
    RGBT<double> F(kNaN);  // NaN cosines give NaN rows
    if (!std::isnan(ci[i])) F = schlick ? F_Schlick(F_Conductor(1.0, e, kk), ci[i]) : F_Conductor(ci[i], e, kk);
    o[3 * i] = F.x, o[3 * i + 1] = F.y, o[3 * i + 2] = F.z;
  }
  return out;
}

}  // namespace

void bind_metals(py::module_& m) {
  m.def(
      "metals",
      [] {
        py::dict out;
        for (const MetalData& md : metal_table()) {
          py::dict d;
          d["symbol"] = std::string(md.symbol);
          d["eta"] = vec3_py(md.eta);
          d["k"] = vec3_py(md.k);
          d["f0"] = vec3_py(F_Conductor(1.0, RGBT<double>(md.eta), RGBT<double>(md.k)));
          d["source"] = std::string(md.source);
          out[py::str(std::string(md.name))] = d;
        }
        return out;
      },
      "The measured metals (`aniso metals`): {name: {symbol, eta, k, f0, source}}, RGB eta and k.");
  m.def("fresnel", &fresnel_py, py::arg("cos_theta"), py::arg("metal") = py::none(), py::kw_only(), py::arg("eta") = py::none(),
        py::arg("k") = py::none(), py::arg("schlick") = false,
        "Unpolarised conductor Fresnel reflectance from air, RGB, as `aniso fresnel`: of a named metal\n"
        "(aniso.metals()) or of given eta and k (a number or [r, g, b] each). cos_theta: any shape;\n"
        "returns that shape + (3,). schlick=True: Schlick's approximation from the exact F0.");
}

}  // namespace aniso::python
