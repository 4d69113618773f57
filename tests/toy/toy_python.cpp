// The Python module with the toy model registered (python/CMakeLists.txt builds it from the
// module's own objects into build/python-toy; tests/toy/test_toy_python.py imports it). The
// model is registered when the extension is loaded, before Python initialises the module.
#include "toy/toy_ndf.hpp"

namespace {
[[maybe_unused]] const bool kRegistered =
    (microbrdf::register_ndf_model(microbrdf::toy::make_toy_model()), true);  // registration line
}  // namespace
