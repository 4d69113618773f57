// Two-lobe NDFs as registry entries (ndf_mixture.hpp): D, derivatives, starting point and JSON
// composed from the two lobes' own.
#include "models/ndf_mixture.hpp"

#include <vector>

#include "microbrdf/error.hpp"
#include "microbrdf/mixture_ndf.hpp"

namespace microbrdf {
namespace {

// w D_a + (1 - w) D_b and its derivatives: the lobes' derivatives scaled, and D_a - D_b for w.
class MixtureEvaluator final : public NdfEvaluator {
 public:
  MixtureEvaluator(std::unique_ptr<NdfEvaluator> a, std::unique_ptr<NdfEvaluator> b, std::size_t ka,
                   std::size_t kb, double w)
      : a_(std::move(a)), b_(std::move(b)), ka_(ka), kb_(kb), w_(w) {}
  void row(double x0, double h, std::size_t n, double y, double* val, double* grad,
           std::size_t stride) const override {
    std::vector<double> va(n), vb(n);
    std::vector<double> ga(grad ? ka_ * n : 0), gb(grad ? kb_ * n : 0);
    a_->row(x0, h, n, y, va.data(), grad ? ga.data() : nullptr, n);
    b_->row(x0, h, n, y, vb.data(), grad ? gb.data() : nullptr, n);
    for (std::size_t i = 0; i < n; ++i) val[i] = w_ * va[i] + (1 - w_) * vb[i];
    if (!grad) return;
    for (std::size_t p = 0; p < ka_; ++p)
      for (std::size_t i = 0; i < n; ++i) grad[p * stride + i] = w_ * ga[p * n + i];
    for (std::size_t p = 0; p < kb_; ++p)
      for (std::size_t i = 0; i < n; ++i) grad[(ka_ + p) * stride + i] = (1 - w_) * gb[p * n + i];
    for (std::size_t i = 0; i < n; ++i) grad[(ka_ + kb_) * stride + i] = va[i] - vb[i];
  }

 private:
  std::unique_ptr<NdfEvaluator> a_, b_;
  std::size_t ka_, kb_;
  double w_;
};

class MixtureModel final : public NdfModel {
 public:
  MixtureModel(const NdfModel& a, const NdfModel& b) : a_(a), b_(b) {
    for (auto p : a.params()) {
      p.name = "lobe1." + p.name;
      params_.push_back(p);
    }
    for (auto p : b.params()) {
      p.name = "lobe2." + p.name;
      params_.push_back(p);
    }
    params_.push_back(
        {"weight", "1", "Weight of the first lobe", NdfParam::Kind::Weight, 0, 1, 0.5});
  }
  std::string name() const override { return "mixture:" + a_.name() + "+" + b_.name(); }
  std::string summary() const override {
    return "w D_" + a_.name() + " + (1 - w) D_" + b_.name() + " (two lobes fitted jointly)";
  }
  const std::vector<NdfParam>& params() const override { return params_; }
  std::shared_ptr<MicrofacetDistribution> make(const std::vector<double>& v) const override {
    const std::vector<double> va(v.begin(), v.begin() + ka()), vb(v.begin() + ka(), v.end() - 1);
    return std::make_shared<MixtureDistribution>(a_.make(va), b_.make(vb), v.back());
  }
  std::vector<double> initial(const NdfMoments& m) const override {
    // A narrow core and a wide tail around the moments' width.
    NdfMoments core = m, tail = m;
    core.alpha_x *= 0.5;
    core.alpha_y *= 0.5;
    tail.alpha_x *= 1.5;
    tail.alpha_y *= 1.5;
    std::vector<double> v = a_.initial(core);
    const std::vector<double> vb = b_.initial(tail);
    v.insert(v.end(), vb.begin(), vb.end());
    v.push_back(0.5);
    return v;
  }
  std::vector<std::vector<double>> starts(const NdfMoments& m) const override {
    // Cores and tails of several widths and weights: a two-lobe cost has local minima.
    std::vector<std::vector<double>> out;
    for (double core : {0.25, 0.5, 1.0})
      for (double tail : {1.5, 3.0})
        for (double w : {0.5, 0.8, 0.95}) {
          NdfMoments a = m, b = m;
          a.alpha_x *= core;
          a.alpha_y *= core;
          b.alpha_x *= tail;
          b.alpha_y *= tail;
          std::vector<double> v = a_.initial(a);
          const std::vector<double> vb = b_.initial(b);
          v.insert(v.end(), vb.begin(), vb.end());
          v.push_back(w);
          out.push_back(std::move(v));
        }
    return out;
  }
  std::vector<const NdfModel*> seeds() const override { return {&a_, &b_}; }
  std::vector<std::vector<double>> seeded_starts(
      const std::vector<std::vector<double>>& fitted) const override {
    // Each lobe's own fit alone (w = 1, w = 0: the mixture then is that fit, so the solver can
    // only end lower), and a core of each with a wider tail of the other (a local minimum of the
    // moment starts need not be near either).
    const std::vector<double>&va = fitted.at(0), &vb = fitted.at(1);
    auto widened = [](const NdfModel& m, std::vector<double> v, double f) {
      for (std::size_t i = 0; i < v.size(); ++i)
        if (m.params()[i].kind == NdfParam::Kind::Alpha) v[i] *= f;
      return v;
    };
    auto join = [](const std::vector<double>& x, const std::vector<double>& y, double w) {
      std::vector<double> v = x;
      v.insert(v.end(), y.begin(), y.end());
      v.push_back(w);
      return v;
    };
    return {join(va, vb, 1.0), join(va, vb, 0.0), join(va, widened(b_, vb, 2.5), 0.8),
            join(widened(a_, va, 2.5), vb, 0.2)};
  }
  void canonicalise(std::vector<double>& v) const override {
    std::vector<double> va(v.begin(), v.begin() + ka()), vb(v.begin() + ka(), v.end() - 1);
    a_.canonicalise(va);
    b_.canonicalise(vb);
    std::copy(va.begin(), va.end(), v.begin());
    std::copy(vb.begin(), vb.end(), v.begin() + ka());
  }
  std::unique_ptr<NdfEvaluator> evaluator(const double* fit, bool reference) const override {
    return std::make_unique<MixtureEvaluator>(
        a_.evaluator(fit, reference), b_.evaluator(fit + ka(), reference),
        static_cast<std::size_t>(ka()), b_.params().size(), fit[params_.size() - 1]);
  }
  nlohmann::json params_json(const std::vector<double>& v) const override {
    const std::vector<double> va(v.begin(), v.begin() + ka()), vb(v.begin() + ka(), v.end() - 1);
    return {{"weight", v.back()},
            {"lobe1", {{"model", a_.name()}, {"params", a_.params_json(va)}}},
            {"lobe2", {{"model", b_.name()}, {"params", b_.params_json(vb)}}}};
  }

 private:
  long ka() const { return static_cast<long>(a_.params().size()); }
  const NdfModel& a_;
  const NdfModel& b_;
  std::vector<NdfParam> params_;
};

}  // namespace

std::unique_ptr<NdfModel> make_mixture_model(const NdfModel& a, const NdfModel& b) {
  return std::make_unique<MixtureModel>(a, b);
}

}  // namespace microbrdf
