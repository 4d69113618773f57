// The Brdf interface over numpy arrays: eval / sample / pdf / albedo on (N, 3) direction stacks
// (local frame, n = +z, both directions pointing away from the surface; f in 1/sr).
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "brdf_factory.hpp"
#include "microbrdf/brdf.hpp"
#include "microbrdf/brdf_albedo.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/kirchhoff_brdf.hpp"
#include "microbrdf/lambertian_brdf.hpp"
#include "microbrdf/microfacet_brdf.hpp"

namespace microbrdf::python {
namespace {

py::object scalar_or_array(py::array_t<double> out, bool single) {
  if (single) return py::float_(out.data()[0]);
  return out;
}

py::object eval(const Brdf& b, const py::object& wi_obj, const py::object& wo_obj,
                double wavelength) {
  const Vec3Array wi = vec3_array(wi_obj, "wi"), wo = vec3_array(wo_obj, "wo");
  const std::size_t n = broadcast_count(wi, wo);
  py::array_t<double> out(static_cast<py::ssize_t>(n));
  double* o = out.mutable_data();
  {
    py::gil_scoped_release r;
    for (std::size_t i = 0; i < n; ++i)
      o[i] = b.eval(wi[wi.single ? 0 : i], wo[wo.single ? 0 : i], wavelength);
  }
  return scalar_or_array(out, wi.single && wo.single);
}

py::object pdf(const Brdf& b, const py::object& wi_obj, const py::object& wo_obj) {
  const Vec3Array wi = vec3_array(wi_obj, "wi"), wo = vec3_array(wo_obj, "wo");
  const std::size_t n = broadcast_count(wi, wo);
  py::array_t<double> out(static_cast<py::ssize_t>(n));
  double* o = out.mutable_data();
  {
    py::gil_scoped_release r;
    for (std::size_t i = 0; i < n; ++i) o[i] = b.pdf(wi[wi.single ? 0 : i], wo[wo.single ? 0 : i]);
  }
  return scalar_or_array(out, wi.single && wo.single);
}

py::tuple sample(const Brdf& b, const py::object& wi_obj, const py::object& u_obj,
                 double wavelength, const py::object& seed) {
  const Vec3Array wi = vec3_array(wi_obj, "wi");
  py::object u_src = u_obj;
  if (u_src.is_none()) {
    auto rng = py::module_::import("numpy").attr("random").attr("default_rng")(seed);
    u_src = rng.attr("random")(py::make_tuple(wi.n, 2));
  }
  const CArray u = CArray::ensure(u_src);
  if (!u || u.ndim() != 2 || u.shape(1) != 2 || std::size_t(u.shape(0)) != wi.n)
    throw py::value_error("sample: u must have shape (N, 2) with N the number of wi");
  py::array_t<double> wo({py::ssize_t(wi.n), py::ssize_t(3)});
  py::array_t<double> weight(static_cast<py::ssize_t>(wi.n)), p(static_cast<py::ssize_t>(wi.n));
  double *w = wo.mutable_data(), *wt = weight.mutable_data(), *pp = p.mutable_data();
  const double* uu = u.data();
  {
    py::gil_scoped_release r;
    for (std::size_t i = 0; i < wi.n; ++i) {
      auto s = b.sample(wi[i], uu[2 * i], uu[2 * i + 1], wavelength);
      if (s) {
        for (int k = 0; k < 3; ++k) w[3 * i + k] = s->wo[k];
        wt[i] = s->weight;
        pp[i] = s->pdf;
      } else {
        w[3 * i] = w[3 * i + 1] = w[3 * i + 2] = 0;
        wt[i] = pp[i] = 0;
      }
    }
  }
  return py::make_tuple(wo, weight, p);
}

py::object albedo(const Brdf& b, const py::object& wi_obj, double wavelength,
                  const std::string& method, int n) {
  const Vec3Array wi = vec3_array(wi_obj, "wi");
  if (method != "quadrature" && method != "sampled")
    throw InputError("albedo: method must be 'quadrature' or 'sampled'");
  // n x 2n quadrature nodes (n x n samples) per direction: n = 4096 is 33 million evaluations,
  // seconds of work; more adds no precision, only minutes.
  if (n < 2 || n > 4096) throw InputError("albedo: n must lie in 2..4096");
  py::array_t<double> out(static_cast<py::ssize_t>(wi.n));
  double* o = out.mutable_data();
  {
    py::gil_scoped_release r;
    for (std::size_t i = 0; i < wi.n; ++i)
      o[i] = method == "sampled" ? directional_albedo_sampled(b, wi[i], wavelength, n)
                                 : directional_albedo(b, wi[i], wavelength, n, 2 * n);
  }
  return scalar_or_array(out, wi.single);
}

}  // namespace

void bind_brdf(py::module_& m) {
  py::class_<Brdf, std::shared_ptr<Brdf>>(m, "Brdf", R"(A BRDF in the local frame.

Directions are unit vectors with the macro normal n = +z (x = the scan's x axis); wi (towards
the light) and wo (towards the viewer) both point away from the surface. Values in 1/sr,
wavelengths in metres. Arrays of directions have shape (N, 3) (or (3,) for one); float64
C-contiguous arrays are read in place, anything else is converted once. Loops run in C++
without the GIL.)")
      .def("eval", &eval, py::arg("wi"), py::arg("wo"), py::arg("wavelength") = 555e-9,
           "f(wi, wo) in 1/sr, shape (N,) (a float for two single vectors); either argument may "
           "be a single (3,) vector, broadcast against the other.")
      .def("pdf", &pdf, py::arg("wi"), py::arg("wo"),
           "Density of sample() per steradian of wo, shape (N,).")
      .def("sample", &sample, py::arg("wi"), py::arg("u") = py::none(),
           py::arg("wavelength") = 555e-9, py::arg("seed") = py::none(),
           "Draws one wo per wi from the uniforms u (N, 2) in [0, 1) (numpy's default_rng(seed) "
           "when u is None). Returns (wo (N, 3), weight (N,) = f cos(theta_o) / pdf, pdf (N,)); "
           "an absorbed sample has wo = 0, weight 0, pdf 0.")
      .def("albedo", &albedo, py::arg("wi"), py::arg("wavelength") = 555e-9,
           py::arg("method") = "quadrature", py::arg("n") = 128,
           "Directional albedo a(wi) = integral f cos(theta_o) dwo: 'quadrature' (Gauss-Legendre "
           "in cos theta_o, n x 2n nodes) or 'sampled' (the BRDF's sampler, n x n strata).")
      .def("describe", [](const Brdf& b) { return text(b.describe()); })
      .def("__repr__", [](const Brdf& b) { return text("<microbrdf.Brdf " + b.describe() + ">"); });

  py::class_<MicrofacetBrdf, Brdf, std::shared_ptr<MicrofacetBrdf>>(
      m, "MicrofacetBrdf", "Dong 2015 eq. 1: F(wi.h) D(h) G(wi, wo) / (4 |wi.n| |wo.n|).");
  py::class_<KirchhoffBrdf, Brdf, std::shared_ptr<KirchhoffBrdf>>(
      m, "KirchhoffBrdf", "Dong 2015 eq. 8: D_K(4 pi h / lambda_q) F G / (4 |wi.n| |wo.n|).");
  py::class_<LambertianBrdf, Brdf, std::shared_ptr<LambertianBrdf>>(m, "LambertianBrdf",
                                                                    "f = albedo / pi.");

  m.def("brdf", &make_brdf, brdf_factory_doc());

  m.def(
      "_input_address",
      [](const py::object& a) {
        return reinterpret_cast<std::uintptr_t>(vec3_array(a, "a").array.data());
      },
      "The address the direction arrays of eval/pdf/sample read (tests of the no-copy claim).");
}

}  // namespace microbrdf::python
