// The environment-lighting basis registry, the evaluation of a fitted basis and the NNLS solver
// (envmap_basis.hpp).
#include "envmap_basis.hpp"
#include "envmap.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <tbb/parallel_for.h>

#include "sglab/reference.hpp"
#include "sglab/sh.hpp"

namespace sglab::fit {

std::array<double, 3> EnvBasisFit::radiance(const Vec3<double>& w) const {
  if (sh_order < 0) return mixture_eval(mixture, w);
  double y[sh_count(kMaxShOrder)];
  sh_eval(sh_order, w, y);
  std::array<double, 3> out{0, 0, 0};
  for (int k = 0; k < sh_count(sh_order); ++k)
    for (int c = 0; c < 3; ++c) out[std::size_t(c)] += sh[std::size_t(k)][std::size_t(c)] * y[k];
  return out;
}

std::array<double, 3> EnvBasisFit::diffuse(const Vec3<double>& n) const {
  std::array<double, 3> out{0, 0, 0};
  if (sh_order < 0) {
    for (const auto& l : mixture) {
      const double d = clamped_cosine_reference(l.sharpness, std::clamp(l.axis.dot(n), -1.0, 1.0)) / M_PI;
      for (int c = 0; c < 3; ++c) out[std::size_t(c)] += l.amplitude[std::size_t(c)] * d;
    }
    return out;
  }
  double y[sh_count(kMaxShOrder)];
  sh_eval(sh_order, n, y);
  for (int l = 0; l <= sh_order; ++l) {
    const double a = sh_clamped_cosine_band<double>(l) / M_PI;
    if (a == 0) continue;
    for (int m = -l; m <= l; ++m)
      for (int c = 0; c < 3; ++c)
        out[std::size_t(c)] += a * sh[std::size_t(sh_index(l, m))][std::size_t(c)] * y[sh_index(l, m)];
  }
  return out;
}

std::vector<std::array<double, 3>> diffuse_at(const EnvBasisFit& f, const std::vector<Vec3<double>>& normals,
                                              LobeDiffuseCache& cache) {
  std::vector<std::array<double, 3>> out(normals.size());
  if (f.sh_order >= 0) {
    tbb::parallel_for(std::size_t(0), normals.size(), [&](std::size_t k) { out[k] = f.diffuse(normals[k]); });
    return out;
  }
  const std::size_t n = f.mixture.size();
  auto same = [&](const LobeDiffuseCache::Entry& e) {
    if (e.normals.size() != normals.size() || e.lobes.size() != n) return false;
    for (std::size_t k = 0; k < normals.size(); ++k)
      if (e.normals[k] != normals[k]) return false;
    for (std::size_t j = 0; j < n; ++j)
      if (e.lobes[j].first != f.mixture[j].axis || e.lobes[j].second != f.mixture[j].sharpness) return false;
    return true;
  };
  auto it = std::find_if(cache.entries.begin(), cache.entries.end(), same);
  if (it != cache.entries.end()) {  // used: to the back, the last to be evicted
    std::rotate(it, it + 1, cache.entries.end());
    it = cache.entries.end() - 1;
  } else {
    if (cache.entries.size() >= LobeDiffuseCache::kEntries) cache.entries.erase(cache.entries.begin());
    LobeDiffuseCache::Entry e;
    e.normals = normals;
    for (const auto& l : f.mixture) e.lobes.emplace_back(l.axis, l.sharpness);
    e.factor.assign(normals.size() * n, std::numeric_limits<double>::quiet_NaN());
    cache.entries.push_back(std::move(e));
    it = cache.entries.end() - 1;
  }
  std::vector<double>& factor = it->factor;
  tbb::parallel_for(std::size_t(0), normals.size(), [&](std::size_t k) {
    std::array<double, 3> sum{0, 0, 0};
    for (std::size_t j = 0; j < n; ++j) {
      const auto& l = f.mixture[j];
      if (l.amplitude[0] == 0 && l.amplitude[1] == 0 && l.amplitude[2] == 0) continue;
      double& d = factor[k * n + j];  // row k is this task's alone
      if (std::isnan(d))
        d = clamped_cosine_reference(l.sharpness, std::clamp(l.axis.dot(normals[k]), -1.0, 1.0)) / M_PI;
      for (int c = 0; c < 3; ++c) sum[std::size_t(c)] += l.amplitude[std::size_t(c)] * d;
    }
    out[k] = sum;
  });
  return out;
}

const std::vector<EnvBasis>& envmap_bases() {
#define SGLAB_LIST_ENVMAP_BASIS(name) name##_basis(),
  static const std::vector<EnvBasis> bases{SGLAB_ENVMAP_BASES(SGLAB_LIST_ENVMAP_BASIS)};
#undef SGLAB_LIST_ENVMAP_BASIS
  return bases;
}

const EnvBasis* find_envmap_basis(const std::string& name) {
  for (const auto& b : envmap_bases())
    if (b.name == name) return &b;
  return nullptr;
}

std::string envmap_basis_names() {
  std::string s;
  for (const auto& b : envmap_bases()) s += (s.empty() ? "" : ", ") + b.name;
  return s;
}

int zero_amplitude_lobes(const SgMixture& m) {
  int n = 0;
  for (const auto& l : m) n += l.amplitude[0] == 0 && l.amplitude[1] == 0 && l.amplitude[2] == 0;
  return n;
}

EnvBasisFit basis_fit_from(const std::string& basis, const EnvFitResult& r) {
  EnvBasisFit f;
  f.basis = basis;
  f.size = int(r.mixture.size());
  f.floats = six_floats_per_lobe(f.size);
  f.seconds = r.seconds;
  f.mixture = r.mixture;
  f.zero_lobes = zero_amplitude_lobes(r.mixture);
  f.kept_lobes = r.kept_lobes;
  f.iterations = r.iterations;
  f.fit_width = r.fit_width;
  f.fit_height = r.fit_height;
  f.detail_tiles = r.detail_tiles;
  return f;
}

EnvFitOptions mixture_fit_options(int lobes, const EnvBasisOptions& o) {
  EnvFitOptions fo;
  fo.lobes = lobes;
  fo.init = "kmeans";
  fo.seed = o.seed;
  fo.threads = o.threads;
  fo.sparse = o.sparse;
  return fo;
}

Eigen::VectorXd nnls(const Eigen::MatrixXd& H, const Eigen::VectorXd& g, double tolerance) {
  const Eigen::Index n = g.size();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  std::vector<char> passive(std::size_t(n), 0);
  const double scale = std::max(g.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  // The unconstrained minimiser over the passive set (zero elsewhere).
  auto solve_passive = [&](Eigen::VectorXd& s) {
    std::vector<Eigen::Index> idx;
    for (Eigen::Index i = 0; i < n; ++i)
      if (passive[std::size_t(i)]) idx.push_back(i);
    const Eigen::Index p = Eigen::Index(idx.size());
    Eigen::MatrixXd Hp(p, p);
    Eigen::VectorXd gp(p);
    for (Eigen::Index a = 0; a < p; ++a) {
      gp(a) = g(idx[std::size_t(a)]);
      for (Eigen::Index b = 0; b < p; ++b) Hp(a, b) = H(idx[std::size_t(a)], idx[std::size_t(b)]);
    }
    const Eigen::VectorXd sp = Hp.ldlt().solve(gp);
    s.setZero(n);
    for (Eigen::Index a = 0; a < p; ++a) s(idx[std::size_t(a)]) = sp(a);
  };
  Eigen::VectorXd s(n);
  for (Eigen::Index outer = 0; outer < 3 * n; ++outer) {
    const Eigen::VectorXd w = g - H * x;  // minus the gradient
    Eigen::Index best = -1;
    double wmax = tolerance * scale;
    for (Eigen::Index i = 0; i < n; ++i)
      if (!passive[std::size_t(i)] && w(i) > wmax) wmax = w(i), best = i;
    if (best < 0) break;
    passive[std::size_t(best)] = 1;
    for (Eigen::Index inner = 0; inner <= n; ++inner) {
      solve_passive(s);
      double alpha = 1;
      bool feasible = true;
      for (Eigen::Index i = 0; i < n; ++i)
        if (passive[std::size_t(i)] && s(i) <= 0) {
          feasible = false;
          const double d = x(i) - s(i);
          alpha = std::min(alpha, d > 0 ? x(i) / d : 0.0);
        }
      if (feasible) {
        x = s;
        break;
      }
      x += alpha * (s - x);
      for (Eigen::Index i = 0; i < n; ++i)
        if (passive[std::size_t(i)] && x(i) <= 0) passive[std::size_t(i)] = 0, x(i) = 0;
    }
  }
  return x.cwiseMax(0.0);
}

}  // namespace sglab::fit
