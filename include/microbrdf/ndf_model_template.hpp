#pragma once
// A registry entry (ndf_model.hpp) from one template D: a model unit writes
//
//   struct MyUnit {
//     static constexpr int kParams = 3;                 // the size of params()
//     template <typename T> struct Lobe {               // T = double or a ceres::Jet
//       explicit Lobe(const T* v);                      // values in the order of params()
//       T D(double x, double y, double z) const;        // D at the unit m = (x, y, z), z > 0
//     };
//   };
//   class MyModel final : public TemplateNdfModel<MyUnit> { name(), summary(), params(), make() };
//
// and TemplateNdfModel gives the fit its D and exact derivatives (forward-mode automatic
// differentiation with ceres::Jet through the fit-space transform of NdfModel). A model with a
// faster hand-written gradient overrides evaluator() for reference == false and keeps this one
// as the reference its test compares with.

#include <ceres/jet.h>

#include <cmath>
#include <memory>

#include "microbrdf/ndf_model.hpp"

namespace microbrdf {

template <class Unit>
class TemplateNdfModel : public NdfModel {
 public:
  static constexpr int K = Unit::kParams;

  std::unique_ptr<NdfEvaluator> evaluator(const double* fit, bool) const override {
    return std::make_unique<JetEvaluator>(*this, fit);
  }

 private:
  using Jet = ceres::Jet<double, K>;

  // Fit space -> values, per kind (the inverse of NdfModel::to_fit), in type T.
  template <typename T>
  static T value(const NdfParam& p, const T& f) {
    using std::exp;
    switch (p.kind) {
      case NdfParam::Kind::Alpha:
        return exp(f);
      case NdfParam::Kind::Exponent:
        return T(p.lo) + exp(f);
      default:
        break;
    }
    return f;
  }

  class JetEvaluator final : public NdfEvaluator {
   public:
    JetEvaluator(const TemplateNdfModel& m, const double* fit)
        : jet_(jet_values(m, fit)), plain_(plain_values(m, fit)) {}
    void row(double x0, double h, std::size_t n, double y, double* val, double* grad,
             std::size_t stride) const override {
      for (std::size_t i = 0; i < n; ++i) {
        const double x = x0 + static_cast<double>(i) * h, r2 = x * x + y * y;
        if (!grad) {
          val[i] = r2 < 1 ? plain_.D(x, y, std::sqrt(1 - r2)) : 0.0;
          continue;
        }
        if (!(r2 < 1)) {
          val[i] = 0;
          for (int p = 0; p < K; ++p) grad[static_cast<std::size_t>(p) * stride + i] = 0;
          continue;
        }
        const Jet d = jet_.D(x, y, std::sqrt(1 - r2));
        val[i] = d.a;
        for (int p = 0; p < K; ++p) grad[static_cast<std::size_t>(p) * stride + i] = d.v[p];
      }
    }

   private:
    using JetLobe = typename Unit::template Lobe<Jet>;
    using PlainLobe = typename Unit::template Lobe<double>;
    static JetLobe jet_values(const TemplateNdfModel& m, const double* fit) {
      Jet v[K];
      for (int p = 0; p < K; ++p)
        v[p] = value(m.params()[static_cast<std::size_t>(p)], Jet(fit[p], p));
      return JetLobe(v);
    }
    static PlainLobe plain_values(const TemplateNdfModel& m, const double* fit) {
      double v[K];
      for (int p = 0; p < K; ++p) v[p] = value(m.params()[static_cast<std::size_t>(p)], fit[p]);
      return PlainLobe(v);
    }
    JetLobe jet_;
    PlainLobe plain_;
  };
};

}  // namespace microbrdf
