// The report's WebGL view draws the fitted ellipsoid, Beckmann and GGX NDFs with formulas of its
// own (the GLSL in src/report/material_view.cpp). This test compiles that GLSL text as C++: the
// build cuts the shader's model functions out of the source file (tests/glsl/
// extract_shader_models.cmake) and they are included below into a namespace that gives GLSL's
// vec2 / vec3 / mat3 their meaning. Fed the uniforms the page gets (material_view_data), their
// D, G1 and G2 must equal the registry's models at many directions, so that a change to either
// side alone fails here. (The browser test compares whole BRDF values in a real WebGL context.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "microbrdf/ndf_model.hpp"
#include "report/material_view.hpp"

namespace glsl_view {

struct vec2 {
  double x = 0, y = 0;
};
struct vec3 {
  double x = 0, y = 0, z = 0;
  vec3() = default;
  explicit vec3(double a) : x(a), y(a), z(a) {}
  vec3(double a, double b, double c) : x(a), y(b), z(c) {}
  vec3(vec2 v, double c) : x(v.x), y(v.y), z(c) {}
};
// Column-major as in GLSL: m[i] is column i, m * v = sum_i m[i] v_i.
struct mat3 {
  vec3 col[3];
  const vec3& operator[](int i) const { return col[i]; }
};

inline vec3 operator+(vec3 a, vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline vec3 operator-(vec3 a, vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline vec3 operator*(vec3 a, vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline vec3 operator/(vec3 a, vec3 b) { return {a.x / b.x, a.y / b.y, a.z / b.z}; }
inline vec3 operator+(vec3 a, double s) { return a + vec3(s); }
inline vec3 operator-(vec3 a, double s) { return a - vec3(s); }
inline vec3 operator*(vec3 a, double s) { return a * vec3(s); }
inline vec3 operator/(vec3 a, double s) { return a / vec3(s); }
inline vec3 operator+(double s, vec3 a) { return vec3(s) + a; }
inline vec3 operator-(double s, vec3 a) { return vec3(s) - a; }
inline vec3 operator*(double s, vec3 a) { return vec3(s) * a; }
inline vec3 operator/(double s, vec3 a) { return vec3(s) / a; }
inline vec3 operator-(vec3 a) { return {-a.x, -a.y, -a.z}; }
inline vec3 operator*(const mat3& m, vec3 v) { return m[0] * v.x + m[1] * v.y + m[2] * v.z; }
inline double dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline double length(vec3 a) { return std::sqrt(dot(a, a)); }
inline vec3 normalize(vec3 a) { return a / length(a); }
using std::abs;
using std::exp;
using std::sqrt;
inline vec3 sqrt(vec3 a) { return {std::sqrt(a.x), std::sqrt(a.y), std::sqrt(a.z)}; }
inline double min(double a, double b) { return std::min(a, b); }
inline double max(double a, double b) { return std::max(a, b); }
inline vec3 max(vec3 a, vec3 b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}

// The shader's uniforms and constants.
int uFamily = 0;
mat3 uR;
vec2 uAlpha;
const double PI = 3.14159265358979;

#define float double
#include "material_view_glsl.inc"
#undef float

}  // namespace glsl_view

namespace microbrdf {
namespace {

// Sets the uniforms as the page's script does for one entry of material_view_data's "models":
// family, alpha, and R sent row by row with transpose = true (so uR is R).
void set_uniforms(const nlohmann::json& m) {
  glsl_view::uFamily = m["family"].get<int>();
  glsl_view::uAlpha = {m["alpha"][0].get<double>(), m["alpha"][1].get<double>()};
  const auto& r = m["R"];
  for (int c = 0; c < 3; ++c)
    glsl_view::uR.col[c] = {r[0 * 3 + c].get<double>(), r[1 * 3 + c].get<double>(),
                            r[2 * 3 + c].get<double>()};
}

struct Case {
  std::string model;
  nlohmann::json params;
};

TEST(MaterialViewShader, ModelFunctionsEqualTheRegistrysModels) {
  const Case cases[] = {
      {"ellipsoid",
       {{"alpha_x", 0.08},
        {"alpha_y", 0.2},
        {"theta_x", 0.1},
        {"theta_y", -0.05},
        {"theta_z", 0.3}}},
      {"ellipsoid",
       {{"alpha_x", 0.3},
        {"alpha_y", 0.15},
        {"theta_x", -0.2},
        {"theta_y", 0.15},
        {"theta_z", -0.6}}},
      {"beckmann", {{"alpha_x", 0.1}, {"alpha_y", 0.25}, {"phi", 0.3}}},
      {"beckmann", {{"alpha_x", 0.45}, {"alpha_y", 0.12}, {"phi", -1.1}}},
      {"ggx", {{"alpha_x", 0.05}, {"alpha_y", 0.2}, {"phi", -0.5}}},
      {"ggx", {{"alpha_x", 0.4}, {"alpha_y", 0.3}, {"phi", 0.1}}},
  };
  // The summary's fits as `predict` writes them (params, and phi at the top level).
  nlohmann::json summary;
  summary["fits"] = nlohmann::json::array();
  for (const auto& c : cases)
    summary["fits"].push_back(
        {{"model", c.model}, {"params", c.params}, {"phi", c.params.value("phi", 0.0)}});
  const nlohmann::json view = report::material_view_data(summary);
  ASSERT_EQ(view["models"].size(), std::size(cases));

  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  // Directions over the upper hemisphere, down to 1 degree above the horizon.
  auto direction = [&] {
    const double ct = std::cos(std::acos(u(rng)) * (89.0 / 90.0)), st = std::sqrt(1 - ct * ct);
    const double ph = 2 * M_PI * u(rng);
    return Vec3(st * std::cos(ph), st * std::sin(ph), ct);
  };
  auto g = [](const Vec3& v) { return glsl_view::vec3(v.x(), v.y(), v.z()); };
  for (std::size_t i = 0; i < std::size(cases); ++i) {
    SCOPED_TRACE(cases[i].model + " " + cases[i].params.dump());
    const NdfModel& model = ndf_model(cases[i].model);
    NdfParams p;
    for (const auto& [k, v] : cases[i].params.items()) {
      p.names.push_back(k);
      p.values.push_back(v.get<double>());
    }
    const auto dist = model.make(model.values(p));
    set_uniforms(view["models"][i]);
    double worst_d = 0, worst_g1 = 0, worst_g2 = 0;
    for (int n = 0; n < 4000; ++n) {
      const Vec3 m = direction(), wi = direction(), wo = direction();
      const double d_ref = dist->D(m), d_glsl = glsl_view::D(g(m));
      // (1e-100: where D underflows to subnormal numbers near the horizon, any two roundings
      // differ relatively.)
      worst_d = std::max(worst_d, std::abs(d_glsl - d_ref) / (d_ref + 1e-100));
      worst_g1 = std::max(worst_g1, std::abs(glsl_view::G1(g(wi)) - dist->G1(wi)));
      worst_g2 =
          std::max(worst_g2, std::abs(glsl_view::G2(g(wi), g(wo), g(m)) - dist->G2(wi, wo, m)));
    }
    std::printf("%s: worst |D| relative %.2e, |G1| %.2e, |G2| %.2e over 4000 directions\n",
                cases[i].model.c_str(), worst_d, worst_g1, worst_g2);
    EXPECT_LT(worst_d, 1e-12);
    // (The shader's erfc is Abramowitz & Stegun 7.1.26, |error| < 1.5e-7: Beckmann's Lambda.)
    EXPECT_LT(worst_g1, 1e-6);
    EXPECT_LT(worst_g2, 1e-6);
  }
}

// The check can fail: a view of GGX whose alphas were swapped, or Beckmann drawn as GGX, is far
// from the registry's model.
TEST(MaterialViewShader, AWrongUniformIsSeen) {
  nlohmann::json summary;
  summary["fits"] = {{{"model", "beckmann"},
                      {"params", {{"alpha_x", 0.1}, {"alpha_y", 0.25}, {"phi", 0.3}}},
                      {"phi", 0.3}}};
  const nlohmann::json view = report::material_view_data(summary);
  nlohmann::json m = view["models"][0];
  const NdfModel& model = ndf_model("beckmann");
  NdfParams p{{"alpha_x", "alpha_y", "phi"}, {0.1, 0.25, 0.3}};
  const auto dist = model.make(model.values(p));
  const Vec3 h = Vec3(0.1, 0.05, 1).normalized();
  set_uniforms(m);
  EXPECT_NEAR(glsl_view::D(glsl_view::vec3(h.x(), h.y(), h.z())) / dist->D(h), 1, 1e-12);
  m["family"] = 0;  // drawn as GGX
  set_uniforms(m);
  EXPECT_GT(std::abs(glsl_view::D(glsl_view::vec3(h.x(), h.y(), h.z())) / dist->D(h) - 1), 0.05);
}

}  // namespace
}  // namespace microbrdf
