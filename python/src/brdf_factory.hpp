#pragma once
// mb.brdf(**flags): a BRDF from the keyword names of the CLI's material and BRDF flags.
#include "bindings.hpp"

namespace microbrdf::python {

py::object make_brdf(const py::kwargs& kwargs);
const char* brdf_factory_doc();

}  // namespace microbrdf::python
