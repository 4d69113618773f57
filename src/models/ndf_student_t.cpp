// The Student-t NDF (Ribardiere et al. 2017; include/microbrdf/student_t.hpp) as a registry
// entry (ndf_model.hpp): D is student_t.hpp's template, Lambda and sampling its distribution's.
#include <cmath>
#include <cstdio>

#include "microbrdf/ndf_model_template.hpp"
#include "microbrdf/student_t.hpp"
#include "models/ndf_builtin.hpp"

namespace microbrdf {
namespace {

struct StudentTUnit {
  static constexpr int kParams = 4;
  // Values (alpha_x, alpha_y, phi, gamma).
  template <typename T>
  struct Lobe {
    T ax, ay, gamma, c, s;
    explicit Lobe(const T* v) : ax(v[0]), ay(v[1]), gamma(v[3]) {
      using std::cos;
      using std::sin;
      c = cos(v[2]);
      s = sin(v[2]);
    }
    T D(double x, double y, double z) const {
      return student_t_d(ax, ay, gamma, (c * x + s * y) / z, (c * y - s * x) / z, T(z));
    }
  };
};

class StudentTModel final : public TemplateNdfModel<StudentTUnit> {
 public:
  std::string name() const override { return "student-t"; }
  std::string label() const override { return "Student-t"; }
  std::vector<std::string> aliases() const override { return {"studentt", "std"}; }
  std::string summary() const override {
    return "Student-t slopes (alpha_x, alpha_y, phi, gamma): GGX at gamma 2, Beckmann as gamma "
           "-> inf; Ribardiere et al. 2017";
  }
  const std::vector<NdfParam>& params() const override {
    static const std::vector<NdfParam> p = [] {
      std::vector<NdfParam> q = anisotropic_params();
      q.push_back({"gamma", "1",
                   "Tail exponent (> 1): 2 is GGX, large is Beckmann; tails fall as slope^-2gamma",
                   NdfParam::Kind::Exponent, kStudentTGammaMin, kStudentTGammaMax, 2});
      return q;
    }();
    return p;
  }
  std::vector<std::vector<double>> starts(const NdfMoments& m) const override {
    // Tails from near-Cauchy to near-Gaussian.
    std::vector<std::vector<double>> out;
    for (double gamma : {1.6, 2.0, 4.0, 16.0}) {
      std::vector<double> v = initial(m);
      v[3] = gamma;
      out.push_back(std::move(v));
    }
    return out;
  }
  std::shared_ptr<MicrofacetDistribution> make(const std::vector<double>& v) const override {
    return std::make_shared<StudentTDistribution>(v[0], v[1], v[2], v[3]);
  }
  nlohmann::json params_json(const std::vector<double>& v) const override {
    nlohmann::json j = legacy_anisotropic_json(v);
    j["gamma"] = v[3];
    return j;
  }
  NdfExportLobe export_lobe(const std::vector<double>& v) const override {
    NdfExportLobe e;
    e.exact = false;
    char b[160];
    std::snprintf(b, sizeof b,
                  "the Student-t tails (gamma %.4g) have no equivalent in Mitsuba 3, pbrt-v4 or "
                  "glTF; a tabulated .bsdf keeps them",
                  v[3]);
    e.note = b;
    return e;
  }
};

}  // namespace

std::unique_ptr<NdfModel> make_student_t_model() { return std::make_unique<StudentTModel>(); }

}  // namespace microbrdf
