// Parametric fits of tabulated NDFs (Dong 2015 section 8): the dict `microbrdf fit --json` prints.
#include "bindings.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fit.hpp"
#include "microbrdf/ndf_io.hpp"

namespace microbrdf::python {

void bind_fit(py::module_& m) {
  m.def(
      "fit",
      [](const py::object& ndf, const std::string& model, const std::string& objective,
         const std::string& sampling, int subsamples, int threads) {
        FitOptions o;
        o.model = parse_fit_model(model);
        o.objective = parse_fit_objective(objective);
        o.sampling = parse_fit_sampling(sampling);
        if (subsamples < 0 || subsamples > 8) throw InputError("subsamples must lie in 0..8");
        o.tent_subsamples = subsamples;
        o.threads = threads;
        std::shared_ptr<const TabulatedNdf> table;
        std::string input;
        if (py::isinstance<TabulatedNdf>(ndf)) {
          table = ndf.cast<std::shared_ptr<TabulatedNdf>>();
        } else {
          input = fspath(ndf, "ndf");
          table = call_released([&] { return std::make_shared<TabulatedNdf>(read_ndf(input)); });
        }
        const nlohmann::json j = call_released([&] {
          nlohmann::json r = fit_result_json(fit_ndf(*table, o));
          if (!input.empty()) r["input"] = input;
          return r;
        });
        return json_to_py(j);
      },
      py::arg("ndf"), py::arg("model") = "ellipsoid", py::arg("objective") = "sqrt",
      py::arg("sampling") = "auto", py::arg("subsamples") = 0, py::arg("threads") = 0,
      R"(Fits a parametric NDF to a table, as `microbrdf fit --json`.

ndf: a TabulatedNdf or the path of a table (.npy/.exr).
model: any registered model (ndf_models()): 'ellipsoid' (alpha_x, alpha_y, theta_x, theta_y,
    theta_z; Dong 2015 eqs. 10-12), 'beckmann' or 'ggx' (alpha_x, alpha_y, phi; also reported as
    theta_z = -phi), ...; or 'mixture:A+B' (two lobes, params {weight, lobe1, lobe2}).
objective: 'sqrt' (Hellinger; default) | 'linear' | 'log'. sampling: 'auto' | 'node' | 'tent'.
Returns a dict: model, params (the model's, angles in radians),
rms_error (1/sr), relative_l2_error, hellinger, iterations, converged (False when a parameter
ended on a bound), at_bound (which bound, or None), ... Runs without the GIL.)");
}

}  // namespace microbrdf::python
