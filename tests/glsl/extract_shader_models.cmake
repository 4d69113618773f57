# Cuts the model functions (fresnel, erfc_, D, lambda_, G1, G2, brdf) out of the report's WebGL
# shader in src/report/material_view.cpp into OUT, for tests/test_material_view_shader.cpp to
# compile them as C++. Usage: cmake -DIN=material_view.cpp -DOUT=file.inc -P this file.
file(READ "${IN}" text)
set(first "vec3 fresnel(float cosi")
set(after "// Environment lookup")
string(FIND "${text}" "${first}" a)
string(FIND "${text}" "${after}" b)
if(a EQUAL -1 OR b EQUAL -1 OR NOT b GREATER a)
  message(FATAL_ERROR "${IN}: the shader's model functions ('${first}' ... '${after}') were not "
                      "found; update tests/glsl/extract_shader_models.cmake with the shader")
endif()
math(EXPR len "${b} - ${a}")
string(SUBSTRING "${text}" ${a} ${len} body)
file(WRITE "${OUT}" "// Generated from ${IN} by ${CMAKE_CURRENT_LIST_FILE}\n${body}")
