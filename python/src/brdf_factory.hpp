#pragma once
// mb.brdf(**flags): a BRDF from the keyword names of the CLI's material and BRDF flags.
#include <nlohmann/json.hpp>
#include <string>

#include "bindings.hpp"

namespace microbrdf::python {

py::object make_brdf(const py::kwargs& kwargs);
/// The spec keys (brdf_spec.hpp, material_spec.hpp) of mb.brdf's keywords, for the library
/// calls that take a spec; tables must be paths. `who` names the caller in errors.
nlohmann::json file_spec_keys(const py::kwargs& kwargs, const std::string& who);
const char* brdf_factory_doc();

}  // namespace microbrdf::python
