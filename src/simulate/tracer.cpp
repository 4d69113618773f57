// Path tracing through a micro-scene: the micro-scattering modes of W92 sections 4.2-4.4.
#include <omp.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "microbrdf/error.hpp"
#include "microbrdf/simulate.hpp"

namespace microbrdf {
namespace {

using Vec = Eigen::Vector3d;

std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

SimRng::SimRng(std::uint64_t seed, std::uint64_t stream)
    : s_(mix64(seed * 0x9e3779b97f4a7c15ULL + mix64(stream + 0x632be59bd9b4e019ULL))) {}

std::uint64_t SimRng::next() {
  s_ += 0x9e3779b97f4a7c15ULL;
  return mix64(s_);
}

void TraceCounters::merge(const TraceCounters& o) {
  incident_rays += o.incident_rays;
  exits += o.exits;
  segments += o.segments;
  escapes_bounded += o.escapes_bounded;
  capped += o.capped;
  energy_out += o.energy_out;
  energy_down += o.energy_down;
  energy_capped += o.energy_capped;
  energy_lost += o.energy_lost;
}

Vec uniform_hemisphere(double u1, double u2) {
  const double z = u1, r = std::sqrt(std::max(0.0, 1 - z * z)), phi = 2 * M_PI * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

MicroTracer::MicroTracer(const MicroScene& scene, const TraceOptions& options)
    : scene_(scene), opt_(options) {
  if (opt_.branches > kMaxBranches)
    throw InputError("branches at the first diffuse event must lie in 1.." +
                     std::to_string(kMaxBranches) + " (got " + std::to_string(opt_.branches) +
                     "; --branches)");
  opt_.branches = std::max(1, opt_.branches);
  stack_.reserve(64);
}

bool MicroTracer::follow(Path& path, SimRng& rng, TraceCounters& c, Vec& v) {
  const auto& materials = scene_.desc().materials;
  const double lambda = scene_.desc().wavelength_m;
  const double eps = scene_.epsilon();
  // After a scattering event on the upper side of a height field (a scene of one height field):
  // the point and normal, so that an upward ray can be shown to escape without a query.
  bool above = false;
  Vec above_p, above_n;
  for (;;) {
    if (above && scene_.clears_upward(above_p, above_n, path.d)) {
      ++c.escapes_bounded;
      if (log_) {  // the queries this replaces, for benchmarks
        MicroHit h;
        const std::size_t first = log_->size();
        scene_.trace(path.o, path.d, h, nullptr, log_, 3);
        for (std::size_t k = first; k < log_->size(); ++k) (*log_)[k].kind = 3;
      }
      v = path.d;
      return true;
    }
    above = false;
    MicroHit h;
    std::size_t segments = 0;
    const TraceEnd end = scene_.trace(path.o, path.d, h, &segments, log_, path.depth == 0 ? 0 : 1);
    c.segments += segments;
    if (end == TraceEnd::EscapedUp) {
      v = path.d;
      return true;
    }
    if (end == TraceEnd::EscapedDown) {
      c.energy_down += path.w;
      return false;
    }
    if (end == TraceEnd::Lost) {
      c.energy_lost += path.w;
      return false;
    }
    if (path.depth >= opt_.max_depth) {
      ++c.capped;
      c.energy_capped += path.w;
      return false;
    }
    // Beer's law along the segment just travelled (kappa is that of the medium the ray is in).
    if (path.kappa > 0) path.w *= std::exp(-path.kappa * h.path_length);
    ++path.depth;
    const MicroMaterial& m = materials[h.material];
    const Vec d = path.d;
    const double cos_out = d.dot(h.n);  // < 0: arriving from outside the solid
    switch (m.kind) {
      case MicroMaterial::Kind::Absorber:
        return false;
      case MicroMaterial::Kind::Mirror: {
        const Vec n = cos_out < 0 ? h.n : Vec(-h.n);
        const double ci = -d.dot(n);
        if (m.fresnel) path.w *= m.fresnel->eval(ci, lambda);
        path.d = (d + 2 * ci * n).normalized();
        path.o = h.p + eps * n;
        above = cos_out < 0;
        break;
      }
      case MicroMaterial::Kind::Dielectric: {
        const bool inside = cos_out > 0;
        const Vec n = inside ? Vec(-h.n) : h.n;  // faces the arriving ray
        const double ci = -d.dot(n);
        const double eta = inside ? 1 / m.eta : m.eta;  // n_t / n_i
        const double F = fresnel_dielectric(ci, eta);
        if (rng.uniform() < F) {
          path.d = (d + 2 * ci * n).normalized();
          path.o = h.p + eps * n;
          above = !inside;
        } else {
          const double sin2t = (1 - ci * ci) / (eta * eta);
          const double ct = std::sqrt(std::max(0.0, 1 - sin2t));
          path.d = (d / eta + (ci / eta - ct) * n).normalized();
          path.o = h.p - eps * n;
          path.kappa = inside ? 0.0 : m.absorption;
        }
        break;
      }
      case MicroMaterial::Kind::Lambert:
      case MicroMaterial::Kind::Brdf: {
        const Vec n = cos_out < 0 ? h.n : Vec(-h.n);  // two-sided
        const Vec t = h.tangent, b = n.cross(t);
        const Vec wi(-d.dot(t), -d.dot(b), -d.dot(n));
        // One scattered direction and its weight f cos / pdf; false when absorbed.
        auto scatter = [&](Vec& out, double& weight) {
          Vec wo;
          if (m.kind == MicroMaterial::Kind::Lambert) {
            const double u1 = rng.uniform(), u2 = rng.uniform();
            const double r = std::sqrt(u1), phi = 2 * M_PI * u2;
            wo = Vec(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1 - u1)));
            weight = m.albedo;
          } else if (m.uniform_sampling) {
            wo = uniform_hemisphere(rng.uniform(), rng.uniform());
            weight = m.brdf->eval(wi, wo, lambda) * wo.z() * 2 * M_PI;
          } else {
            const double u1 = rng.uniform(), u2 = rng.uniform();
            const auto s = m.brdf->sample(wi, u1, u2, lambda);
            if (!s || !(s->weight > 0) || !(s->wo.z() > 0)) return false;
            wo = s->wo;
            weight = s->weight;
          }
          out = (wo.x() * t + wo.y() * b + wo.z() * n).normalized();
          return weight > 0 && std::isfinite(weight);
        };
        if (!path.branched && opt_.branches > 1) {
          path.branched = true;
          path.w /= opt_.branches;
          path.w0 = path.w;
          for (int k = 1; k < opt_.branches; ++k) {
            Vec dir;
            double weight;
            if (scatter(dir, weight))
              stack_.push_back(
                  Path{h.p + eps * n, dir, path.w * weight, path.w0, path.kappa, path.depth, true});
          }
        }
        Vec dir;
        double weight;
        if (!scatter(dir, weight)) return false;
        path.d = dir;
        path.w *= weight;
        path.o = h.p + eps * n;
        above = cos_out < 0;
        break;
      }
    }
    if (above) {
      above_p = h.p;
      above_n = h.n;
      above = scene_.has_escape_bound();
    }
    if (!(path.w > 0)) return false;
    if (path.depth >= opt_.rr_depth) {
      const double q = std::min(1.0, path.w / path.w0);
      if (q < 1) {
        if (rng.uniform() >= q) return false;
        path.w /= q;
      }
    }
  }
}

std::vector<double> cap_brdf(const MicroScene& scene, const Vec& u, const std::vector<Vec>& dirs,
                             double half_angle, std::uint64_t rays, const TraceOptions& trace,
                             std::uint64_t seed, TraceCounters* counters, bool average_azimuth,
                             int points_per_block) {
  const std::size_t nc = dirs.size();
  const double cos_half = std::cos(half_angle);
  const std::uint64_t nblocks = (rays + points_per_block - 1) / points_per_block;
  const int nt = omp_get_max_threads();
  std::vector<std::vector<double>> part(nt, std::vector<double>(nc, 0.0));
  std::vector<TraceCounters> cnt(nt);
#pragma omp parallel num_threads(nt)
  {
    const int tid = omp_get_thread_num();
    MicroTracer tracer(scene, trace);
    auto& acc = part[tid];
#pragma omp for schedule(static)
    for (std::int64_t blk = 0; blk < static_cast<std::int64_t>(nblocks); ++blk) {
      SimRng rng(seed, static_cast<std::uint64_t>(blk));
      const int n = static_cast<int>(
          std::min<std::uint64_t>(points_per_block, rays - std::uint64_t(blk) * points_per_block));
      // Stratified azimuth of the plane of incidence for this block (isotropic surfaces).
      const double phi =
          average_azimuth ? 2 * M_PI * (double(blk) + rng.uniform()) / double(nblocks) : 0.0;
      const double cp = std::cos(phi), sp = std::sin(phi);
      const Vec ur(cp * u.x() - sp * u.y(), sp * u.x() + cp * u.y(), u.z());
      tracer.trace(
          ur, n, rng,
          [&](const Vec& w, double r) {
            const Vec v(cp * w.x() + sp * w.y(), -sp * w.x() + cp * w.y(), w.z());
            for (std::size_t k = 0; k < nc; ++k)
              if (v.dot(dirs[k]) >= cos_half) acc[k] += r;
          },
          cnt[tid]);
    }
  }
  std::vector<double> out(nc, 0.0);
  TraceCounters total;
  for (int t = 0; t < nt; ++t) {
    for (std::size_t k = 0; k < nc; ++k) out[k] += part[t][k];
    total.merge(cnt[t]);
  }
  const double solid = M_PI * std::sin(half_angle) * std::sin(half_angle);
  for (std::size_t k = 0; k < nc; ++k)
    out[k] /= static_cast<double>(total.incident_rays) * solid * dirs[k].z();
  if (counters) *counters = total;
  return out;
}

}  // namespace microbrdf
