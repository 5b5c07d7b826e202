// `sglab envmap lobes`: error against the lobe count of SG mixture fits of environment maps, and
// the shading error of the fit and of every registry method (envmap_lobes.hpp).
//
// The work runs in parallel without changing a number: the environments are independent; within
// one, the Ceres lobe ladder (one fit at the largest N) is sequential, while the vMF-EM fits and
// the shading of every N are independent of each other (compute() says how they are scheduled). Every value is computed
// by the same calls as in a sequential run and stored in its place, and the tables are formatted afterwards in the
// sequential order.
#include "envmap_lobes.hpp"

#include "env_arguments.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <future>
#include <map>
#include <memory>
#include <mutex>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "option_checks.hpp"
#include "registry.hpp"
#include "sglab/render/environment.hpp"
#include "input_error.hpp"
#include "sglab/registry.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::experiments::envmap_lobes {
namespace {

struct Geometry {
  std::string name;
  render::EnvImage image;
};

std::vector<std::string> method_names(const std::string& quantity) {
  std::vector<std::string> v;
  for (const auto& m : find_quantity(quantity)->methods)
    if (m.name != "reference") v.push_back(m.name);
  return v;
}

std::string num(double v) { return fmt::format("{:.3g}", v); }

Options effective(const Options& o) {
  Options a = o;
  if (a.quick) {
    a.lobes = {1, 4};
    a.sphere_res = 12;
  }
  if (a.envs.empty()) throw runner::InputError("envmap lobes needs at least one --env NAME=MAP.exr");
  for (int n : a.lobes)
    if (n < 1) throw runner::InputError(fmt::format("--lobes {} must be ≥ 1", n));
  // The same bounds as the command's option checks, for callers of the library.
  if (a.sphere_res < 2 || a.sphere_res > 2048)
    throw runner::InputError(fmt::format("--res {} must be in [2, 2048]", a.sphere_res));
  for (double r : a.roughness)
    if (!(r >= render::kMinEnvRoughness && r <= 1))
      throw runner::InputError(fmt::format("--roughness {} must be in [{:g}, 1]", r, render::kMinEnvRoughness));
  check_env_arguments(a.envs);  // a name is a table label and a CSV field: a plain word, once
  return a;
}

std::vector<LoadedEnv> load_envs(const Options& a) {
  std::vector<LoadedEnv> envs;
  for (const auto& e : a.envs) {
    envs.push_back(load_env_argument(e));
    for (int n : a.lobes)
      if (std::size_t(n) > envs.back().map.size())
        throw runner::InputError(fmt::format("--lobes {} exceeds {}'s pixel count", n, envs.back().name));
  }
  return envs;
}

std::string command_line(const Options& a) {
  std::string command = "sglab envmap lobes";
  for (const auto& e : a.envs) command += " --env " + e;
  command += " --lobes";
  for (int n : a.lobes) command += " " + std::to_string(n);
  return command + " --res " + std::to_string(a.sphere_res) + " --out " + a.out +
         runner::option_argument("--tables-dir", a.tables_dir);
}

// The map reduced (2×2 means) to at most 128 texels wide, for the figure.
EnvMap small_image(const EnvMap& m) {
  const int iw = std::min(128, m.width);
  EnvMap small = m;
  while (small.width > iw && small.width % 2 == 0 && small.height % 2 == 0) small = downsample_envmap(small);
  return small;
}

// A diffuse shading (a function of the normal only) evaluated once per distinct normal: the plane
// has one normal for all its view directions. `shade` is called on the image of the distinct
// points, so every value is the one the same call gives for that point (the diffuse quadratures
// per pixel, of the map and of the mixture's reference per lobe, were a large part of the run).
template <class Shade>
std::vector<render::Rgb> per_distinct_normal(const render::EnvImage& image, const Shade& shade) {
  render::EnvImage distinct;
  std::vector<std::size_t> slot(image.points.size());
  for (std::size_t k = 0; k < image.points.size(); ++k) {
    const auto& p = image.points[k];
    std::size_t s = 0;
    while (s < distinct.points.size() && distinct.points[s].normal != p.normal) ++s;
    if (s == distinct.points.size()) distinct.points.push_back({int(s), p.normal, p.view});
    slot[k] = s;
  }
  distinct.width = int(distinct.points.size());
  distinct.height = 1;
  const std::vector<render::Rgb> values = shade(distinct);
  std::vector<render::Rgb> out(std::size_t(image.width) * std::size_t(image.height), render::Rgb::Zero());
  for (std::size_t k = 0; k < image.points.size(); ++k) out[std::size_t(image.points[k].pixel)] = values[slot[k]];
  return out;
}

// Layer (1) of one environment: the map's exact shading per geometry (specular per roughness).
struct MapShading {
  std::vector<std::vector<render::Rgb>> diffuse, specular;  // [geometry], [geometry × roughness]
};

// Layer (1) of every environment, in the order given. The specular quadratures take every map of
// one size at once (integrate_specular of several maps: each node's GGX weight once for all of
// them; the same values as one call per map, to the bit).
std::vector<MapShading> shade_maps(const Options& a, const std::vector<LoadedEnv>& envs,
                                   const std::vector<Geometry>& geometries, std::vector<Environment>& out) {
  std::vector<MapShading> s(envs.size());
  const auto& sphere = geometries[0].image;
  for (std::size_t e = 0; e < envs.size(); ++e) {
    std::fprintf(stderr, "envmap lobes: %s (%d×%d): exact shading of the map …\n", envs[e].name.c_str(),
                 envs[e].map.width, envs[e].map.height);
    for (const auto& g : geometries)
      s[e].diffuse.push_back(
          per_distinct_normal(g.image, [&](const auto& im) { return render::integrate_diffuse(envs[e].map, im); }));
    // Quadrature convergence at 2×2 sub-texels on the hardest case (sphere, smallest roughness).
    const auto fine_d = render::integrate_diffuse(envs[e].map, sphere, 2);
    out[e].quadrature_diffuse = render::shading_error(s[e].diffuse[0], fine_d, sphere).relative_l2;
  }
  std::vector<char> done(envs.size(), 0);
  for (std::size_t e = 0; e < envs.size(); ++e) {
    if (done[e]) continue;
    std::vector<std::size_t> same;  // the environments whose maps are e's size
    std::vector<const EnvMap*> maps;
    for (std::size_t f = e; f < envs.size(); ++f)
      if (envs[f].map.width == envs[e].map.width && envs[f].map.height == envs[e].map.height) {
        same.push_back(f);
        maps.push_back(&envs[f].map);
        done[f] = 1;
      }
    for (const auto& g : geometries)
      for (double r : a.roughness) {
        auto values = render::integrate_specular(maps, g.image, r, a.f0);
        for (std::size_t j = 0; j < same.size(); ++j) s[same[j]].specular.push_back(std::move(values[j]));
      }
    const auto fine_s = render::integrate_specular(maps, sphere, a.roughness.front(), a.f0, 2);
    for (std::size_t j = 0; j < same.size(); ++j)
      out[same[j]].quadrature_specular = render::shading_error(s[same[j]].specular[0], fine_s[j], sphere).relative_l2;
  }
  return s;
}

// The Ceres fits of every N: one fit at the largest N gives every N of its lobe ladder
// (fit/envmap.hpp: the rung at n is the fit `sglab fit envmap --lobes n` makes, its time counted
// from the start); lobe counts off the ladder are fitted on their own.
std::map<int, fit::EnvFitResult> ceres_fits(const Options& a, const EnvMap& map) {
  std::map<int, fit::EnvFitResult> fits;
  auto fit_n = [&](int n, bool ladder) {
    fit::EnvFitOptions o;
    o.lobes = n;
    o.init = "kmeans";
    if (ladder) o.on_stage = [&](const fit::EnvFitResult& r) { fits.emplace(int(r.mixture.size()), r); };
    const auto r = fit::fit_envmap_ceres(map, o);
    fits.emplace(int(r.mixture.size()), r);
  };
  fit_n(*std::max_element(a.lobes.begin(), a.lobes.end()), true);
  for (int n : a.lobes)
    if (!fits.count(n)) fit_n(n, false);
  return fits;
}

// Layers (2) and (3) of one fit on one geometry, against the map's layer (1).
// mix_s: layer (2)'s specular quadrature of the fit's texel means on this geometry, per roughness.
GeometryRows shade_fit(const Options& a, const Result& r, const SgMixture& mixture,
                       const std::vector<std::vector<render::Rgb>>& mix_specular, const Geometry& g,
                       const MapShading& map, std::size_t gi) {
  GeometryRows rows;
  // Diffuse: layer 2 by the clamped-cosine reference per lobe, layer 3 per method.
  const auto mix_d = per_distinct_normal(
      g.image, [&](const auto& im) { return render::mixture_diffuse_reference(mixture, im); });
  rows.diffuse.fit = render::shading_error(mix_d, map.diffuse[gi], g.image);
  for (const auto& m : r.diffuse_methods) {
    const auto approx = render::mixture_diffuse_method(mixture, g.image, m);
    rows.diffuse.methods.push_back(
        {render::shading_error(approx, mix_d, g.image), render::shading_error(approx, map.diffuse[gi], g.image)});
  }
  // Specular: layer 2 by the same texel quadrature over the rasterized mixture.
  for (std::size_t ri = 0; ri < a.roughness.size(); ++ri) {
    ShadingRow row;
    row.roughness = a.roughness[ri];
    const auto& exact_map = map.specular[gi * a.roughness.size() + ri];
    const auto& mix_s = mix_specular[ri];
    row.fit = render::shading_error(mix_s, exact_map, g.image);
    for (const auto& m : r.specular_methods) {
      const auto approx = render::mixture_specular_method(mixture, g.image, m, row.roughness, a.f0);
      row.methods.push_back(
          {render::shading_error(approx, mix_s, g.image), render::shading_error(approx, exact_map, g.image)});
    }
    rows.specular.push_back(std::move(row));
  }
  return rows;
}

bool shows_image(const Options& a, int n) { return n == 4 || n == 32 || n == 128 || n == a.lobes.back(); }

// Whether two texel-mean maps are the same bytes (then every quadrature of them gives the same values).
bool same_texels(const EnvMap& x, const EnvMap& y) {
  return x.width == y.width && x.height == y.height && x.texels.size() == y.texels.size() &&
         std::memcmp(x.texels.data(), y.texels.data(), x.texels.size() * sizeof(x.texels[0])) == 0;
}

// The shading of one environment's fits (layers (2) and (3) of every N, and the figure's images),
// once its Ceres fits and the map's layer (1) are known. Layer (2)'s specular quadrature (one GGX
// evaluation per texel and pixel: most of the shading's time) reads only the fit's texel means, so
// it is computed once per distinct texel means: a rung the ladder's guard kept (fit/envmap.hpp,
// EnvFitResult::kept_lobes) has its predecessor's texel means, byte for byte, and reuses that
// rung's quadrature — the same call on the same bytes, so the same values.
void shade_environment(const Result& r, const LoadedEnv& env, const std::vector<Geometry>& geometries,
                       const std::map<int, fit::EnvFitResult>& fits, const MapShading& map, Environment& out) {
  const Options& a = r.options;
  const std::size_t counts = a.lobes.size(), G = geometries.size(), R = a.roughness.size();
  std::vector<std::size_t> source(counts);  // the first count whose texel means are count k's
  for (std::size_t k = 0; k < counts; ++k) {
    LobeCount& c = out.counts[k];
    c.lobes = a.lobes[k];
    c.ceres = fits.at(c.lobes);
    source[k] = k;
    for (std::size_t e = 0; e < k; ++e)
      if (source[e] == e && same_texels(out.counts[e].ceres.texel_means, c.ceres.texel_means)) {
        source[k] = e;
        break;
      }
  }
  // [count × geometry × roughness], filled for the counts that are their own source: per geometry
  // and roughness, every such count's texel means (the mixture rasterized as its fit error saw it)
  // in one call, which evaluates each node's GGX weight once for all of them (the same values as
  // one call per count, to the bit).
  std::vector<const EnvMap*> distinct;
  std::vector<std::size_t> distinct_count;
  for (std::size_t k = 0; k < counts; ++k)
    if (source[k] == k) {
      distinct.push_back(&out.counts[k].ceres.texel_means);
      distinct_count.push_back(k);
    }
  std::vector<std::vector<render::Rgb>> mix_s(counts * G * R);
  tbb::parallel_for(std::size_t(0), G * R, [&](std::size_t i) {
    const std::size_t gi = i / R, ri = i % R;
    auto values = render::integrate_specular(distinct, geometries[gi].image, a.roughness[ri], a.f0);
    for (std::size_t d = 0; d < distinct.size(); ++d)
      mix_s[(distinct_count[d] * G + gi) * R + ri] = std::move(values[d]);
  });
  std::vector<EnvMap> images(counts);
  tbb::parallel_for(std::size_t(0), counts, [&](std::size_t k) {
    LobeCount& c = out.counts[k];
    std::fprintf(stderr, "envmap lobes: %s N = %d: ceres relative error %.4g in %.2f s (on %d×%d)%s\n",
                 env.name.c_str(), c.lobes, c.ceres.error.relative, c.ceres.seconds, c.ceres.fit_width,
                 c.ceres.fit_height,
                 source[k] == k ? "" : " (texel means as N's before it: its specular quadrature reused)");
    if (shows_image(a, c.lobes)) images[k] = small_image(c.ceres.texel_means);
    for (std::size_t gi = 0; gi < G; ++gi) {
      const auto first = mix_s.begin() + std::ptrdiff_t((source[k] * G + gi) * R);
      const std::vector<std::vector<render::Rgb>> specular(first, first + std::ptrdiff_t(R));
      c.geometries.push_back(shade_fit(a, r, c.ceres.mixture, specular, geometries[gi], map, gi));
    }
  });
  out.images.push_back({0, small_image(env.map)});
  for (std::size_t k = 0; k < counts; ++k)
    if (shows_image(a, a.lobes[k])) out.images.push_back({a.lobes[k], std::move(images[k])});
}

}  // namespace

Result compute(const Options& o) {
  const auto t_start = std::chrono::steady_clock::now();
  Result r;
  r.options = effective(o);
  const Options& a = r.options;
  const std::vector<LoadedEnv> envs = load_envs(a);
  r.provenance = runner::Provenance{command_line(a), a.quick};
  r.diffuse_methods = method_names("clamped-cosine");
  r.specular_methods = method_names("specular");
  const std::vector<Geometry> geometries = {{"sphere", render::sphere_image(a.sphere_res)},
                                            {"plane", render::plane_image(a.sphere_res, a.sphere_res / 2)}};
  for (const auto& g : geometries) r.geometries.push_back(g.name);
  // Each environment's Ceres ladder is one long sequential chain: the chains run on threads of
  // their own from the start, each going on to the shading of its environment once the map's
  // layer (1) is there, while this thread computes every layer (1) and then every vMF-EM fit.
  // (Each thread's TBB loops run in its own arena, so a chain never waits behind other work.)
  r.environments.resize(envs.size());
  std::vector<MapShading> maps(envs.size());
  std::promise<void> maps_done;
  std::shared_future<void> maps_ready = maps_done.get_future().share();
  std::vector<std::future<void>> chains;
  for (std::size_t e = 0; e < envs.size(); ++e) {
    r.environments[e].name = envs[e].name;
    r.environments[e].counts.resize(a.lobes.size());
    chains.push_back(std::async(std::launch::async, [&, e] {
      const auto fits = ceres_fits(a, envs[e].map);
      maps_ready.get();  // rethrows a failure of the layer (1) shading
      shade_environment(r, envs[e], geometries, fits, maps[e], r.environments[e]);
    }));
  }
  try {
    maps = shade_maps(a, envs, geometries, r.environments);
    maps_done.set_value();
  } catch (...) {
    maps_done.set_exception(std::current_exception());
    for (auto& c : chains) c.wait();
    throw;
  }
  tbb::parallel_for(std::size_t(0), envs.size() * a.lobes.size(), [&](std::size_t i) {
    const std::size_t e = i / a.lobes.size(), k = i % a.lobes.size();
    fit::EnvFitOptions fo;
    fo.lobes = a.lobes[k];
    fo.init = "kmeans";
    const auto fe = fit::fit_envmap_vmf_em(envs[e].map, fo);
    r.environments[e].counts[k].vmf_relative = fe.error.relative;
    r.environments[e].counts[k].vmf_seconds = fe.seconds;
    std::fprintf(stderr, "envmap lobes: %s N = %d: vMF EM relative error %.4g in %.2f s\n", envs[e].name.c_str(),
                 a.lobes[k], fe.error.relative, fe.seconds);
  });
  for (auto& c : chains) c.get();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return r;
}

namespace {

// The Markdown's introduction: what was fitted, shaded and compared.
std::string markdown_intro(const Result& r) {
  const Options& a = r.options;
  std::string md =
      "# SG environment maps: error against the lobe count\n\n"
      "Generated by `" +
      r.provenance.command + "` (" + fmt::format("{:.0f}", r.seconds) + " s). ";
  md +=
      "Each environment (equirectangular, z up; written by `sglab envmap make`) is fitted with N RGB SG lobes "
      "by `sglab fit envmap` (Ceres Levenberg–Marquardt, solid-angle-weighted L2, k-means initial axes, coarse to fine "
      "up to the level shown, N > 2 grown from the fit at N/2 by lobes placed on the residual) and, beside it in the "
      "same run, by EM for a von Mises–Fisher mixture (Banerjee et al. 2005) "
      "with least-squares amplitudes. Fit error = solid-angle-weighted relative L2 of the mixture's texel means (4×4 "
      "points per texel) against the map; times are wall seconds on this machine (2 cores, shared: compare ratios). "
      "The environments, and within one the Ceres fits, the vMF-EM fits and the shading, run at the same time "
      "(each Ceres fit with 2 threads), so every time includes that contention.\n\n"
      "Shading (`sglab envmap render`, visibility ignored, V = 1): a unit sphere seen orthographically (" +
      std::to_string(a.sphere_res) + "² pixels) and a plane seen from a " + std::to_string(a.sphere_res) + "×" +
      std::to_string(a.sphere_res / 2) +
      " grid of view directions; albedo 1 (diffuse = (1/π)∫L⟨ω·n⟩), GGX with height-correlated Smith "
      "and Schlick f0 = " +
      fmt::format("{}", a.f0) +
      " (specular). Three layers: (1) the map integrated exactly (texel "
      "quadrature of the piecewise-constant map), (2) the fitted mixture integrated exactly (diffuse: the "
      "clamped-cosine "
      "reference per lobe; specular: the same texel quadrature over the mixture's texel means), (3) the "
      "mixture with each registry method. **fit part** = (2) against (1); **approximation part** = (3) against (2); "
      "the CSV also has the total (3) against (1), and SMAPE and the brightness-weighted error Σ|v − r|/Σ|r| for "
      "every entry. The tables below give relative L2 (‖v − r‖/‖r‖ over pixels and channels).\n\n"
      "Scale and reading notes: the images are small (" +
      std::to_string(a.sphere_res) +
      "² sphere) so that the whole "
      "run takes minutes; the specular layer (1) and (2) quadratures cost one GGX evaluation per texel and pixel. "
      "The Ceres problem is sparse (one residual block per 8×8-texel tile, touching the lobes that reach it; CGNR "
      "steps); "
      "N is fitted jointly on the finest level whose estimated Jacobian has at most 1.5·10⁶ nonzeros "
      "(column \"fitted on\"); lobes at that level's sharpness bound are then refined alone on the finer levels. "
      "The Ceres fits of one environment are the rungs of one fit at the largest N (N = 1 is fitted on its own): "
      "every rung is fitted on that fit's level, which for N ≤ 8 is coarser than `sglab fit envmap --lobes N` alone "
      "would use; the Ceres seconds of a rung count from the start of that fit (the time to reach N, the rungs below "
      "it included). "
      "The sky's sun is a uniform disk (2°) far brighter than the sky: it carries most of the map's L2 norm and no "
      "Gaussian matches its edge, which sets the sky's error floor. \"cap\" in the fit table: Levenberg–Marquardt "
      "stopped at its iteration cap (60 per solve) before its tolerances in at least one solve of the fit; that fit's "
      "error is what the capped run "
      "reached, not the optimum.\n\n";
  return md;
}

// "| a | b |…|\n|---|---|…|\n" for the fixed columns then one per method.
std::string table_head(const std::string& fixed, std::size_t fixed_count, const std::vector<std::string>& methods) {
  std::string h = fixed;
  for (const auto& m : methods) h += " " + m + " |";
  h += "\n|";
  for (std::size_t k = 0; k < fixed_count + methods.size(); ++k) h += "---|";
  return h + "\n";
}

}  // namespace

runner::TableWithImages tables(const Result& r) {
  const Options& a = r.options;
  runner::TableWithImages t;
  t.csv =
      "environment,lobes,ceres_relative_error,ceres_seconds,ceres_fit_width,vmf_em_relative_error,vmf_em_seconds,"
      "geometry,component,roughness,method,part,relative_l2,smape,brightness_weighted\n";
  t.images_csv = "environment,lobes,x,y,r,g,b\n";
  std::string fit_md, diffuse_md, specular_md, quadrature_md;
  for (const auto& env : r.environments) {
    quadrature_md += fmt::format("| {} | {} | {} |\n", env.name, num(env.quadrature_diffuse),
                                 num(env.quadrature_specular));
    for (const auto& img : env.images)
      for (int y = 0; y < img.map.height; ++y)
        for (int x = 0; x < img.map.width; ++x) {
          const auto& p = img.map.at(x, y);
          t.images_csv += fmt::format("{},{},{},{},{:.6g},{:.6g},{:.6g}\n", env.name, img.lobes, x, y, p[0], p[1],
                                      p[2]);
        }
    for (const auto& c : env.counts) {
      const auto& fc = c.ceres;
      fit_md += fmt::format("| {} | {} | {} | {:.2f} | {}×{} | {} | {} | {:.2f} |\n", env.name, c.lobes,
                            num(fc.error.relative), fc.seconds, fc.fit_width, fc.fit_height,
                            fc.converged ? "yes" : "cap", num(c.vmf_relative), c.vmf_seconds);
      const std::string prefix = fmt::format("{},{},{:.6g},{:.4f},{},{:.6g},{:.4f}", env.name, c.lobes,
                                             fc.error.relative, fc.seconds, fc.fit_width, c.vmf_relative,
                                             c.vmf_seconds);
      auto row = [&](const std::string& geometry, const std::string& component, double rough, const std::string& method,
                     const std::string& part, const render::ShadingError& e) {
        t.csv += fmt::format("{},{},{},{},{},{},{:.6g},{:.6g},{:.6g}\n", prefix, geometry, component,
                             rough > 0 ? fmt::format("{}", rough) : "", method, part, e.relative_l2, e.smape,
                             e.brightness_weighted);
      };
      for (std::size_t gi = 0; gi < r.geometries.size(); ++gi) {
        const std::string& g = r.geometries[gi];
        const GeometryRows& rows = c.geometries[gi];
        row(g, "diffuse", 0, "", "fit", rows.diffuse.fit);
        diffuse_md += fmt::format("| {} | {} | {} | {} |", env.name, c.lobes, g, num(rows.diffuse.fit.relative_l2));
        for (std::size_t m = 0; m < r.diffuse_methods.size(); ++m) {
          row(g, "diffuse", 0, r.diffuse_methods[m], "approximation", rows.diffuse.methods[m].approximation);
          row(g, "diffuse", 0, r.diffuse_methods[m], "total", rows.diffuse.methods[m].total);
          diffuse_md += " " + num(rows.diffuse.methods[m].approximation.relative_l2) + " |";
        }
        diffuse_md += "\n";
        for (const auto& s : rows.specular) {
          row(g, "specular", s.roughness, "", "fit", s.fit);
          specular_md += fmt::format("| {} | {} | {} | {} | {} |", env.name, c.lobes, g, s.roughness,
                                     num(s.fit.relative_l2));
          for (std::size_t m = 0; m < r.specular_methods.size(); ++m) {
            row(g, "specular", s.roughness, r.specular_methods[m], "approximation", s.methods[m].approximation);
            row(g, "specular", s.roughness, r.specular_methods[m], "total", s.methods[m].total);
            specular_md += fmt::format(" {} |", num(s.methods[m].approximation.relative_l2));
          }
          specular_md += "\n";
        }
      }
    }
  }
  t.markdown = markdown_intro(r);
  t.markdown +=
      "## Quadrature convergence of layer (1)\n\nRelative L2 change of the sphere's shading between 1 and 2×2 "
      "sub-texels per texel (specular at roughness " +
      fmt::format("{}", a.roughness.front()) +
      ", the sharpest lobe):\n\n"
      "| environment | diffuse | specular |\n|---|---|---|\n" +
      quadrature_md;
  t.markdown +=
      "\n## Fit error and time\n\n| environment | N | Ceres rel. L2 | Ceres s | fitted on | LM converged | vMF-EM rel. "
      "L2 | vMF-EM s |\n"
      "|---|---|---|---|---|---|---|---|\n" +
      fit_md;
  t.markdown += "\n## Diffuse: fit part and approximation part (relative L2)\n\n" +
                table_head("| environment | N | geometry | fit part |", 4, r.diffuse_methods) + diffuse_md;
  t.markdown += "\n## Specular: fit part and approximation part (relative L2)\n\n" +
                table_head("| environment | N | geometry | roughness | fit part |", 5, r.specular_methods) +
                specular_md;
  return t;
}

void write(const Result& r) {
  const std::filesystem::path dir = runner::tables_place(r.options.tables_dir, r.options.out);
  runner::write_table_with_images(dir, "envmap_lobes", r.options.out, "envmap_images", r.provenance, tables(r));
  std::printf("envmap lobes: %.1f s; wrote %s/envmap_lobes.{md,csv} and %s/envmap_images.csv\n", r.seconds, dir.c_str(),
              r.options.out.c_str());
}

}  // namespace sglab::experiments::envmap_lobes

// ---- the experiment: its command and its reproduce steps ----------------------------------------

namespace sglab::experiments {

// `sglab envmap lobes` (registered under `envmap`).
void add_envmap_lobes_command(CLI::App& envmap, const runner::RunContext& run) {
  auto a = std::make_shared<envmap_lobes::Options>();
  auto* sub = envmap.add_subcommand("lobes", "fit and render error against the lobe count (envmap_lobes.*)");
  sub->add_option("--env", a->envs, "NAME=MAP.exr (repeat)")->required();
  sub->add_option("--lobes", a->lobes, "lobe counts")->capture_default_str();
  sub->add_option("--roughness", a->roughness, "GGX roughnesses")
      ->capture_default_str()
      ->check(frontend::finite_in(render::kMinEnvRoughness, 1));
  sub->add_option("--res", a->sphere_res, "sphere image size (plane: res × res/2 view directions)")
      ->capture_default_str()
      ->check(frontend::integer_in(2, 2048));
  frontend::add_places_options(*sub, run.places, kEnvmapDir, a->out, a->tables_dir, "directory for envmap_images.csv",
                               "where envmap_lobes.{md,csv} go (default: the --out directory)");
  sub->add_flag("--quick", a->quick, "N ∈ {1, 4}, 12-pixel sphere (a smoke run; not for paper_tables)");
  sub->callback([a, run] { envmap_lobes::write(runner::with_run(envmap_lobes::compute(*a), run)); });
}

// SG environment maps: the three generated environments, the fits and renders against N
// (paper_tables/envmap_lobes.*), and the figures.
Experiment envmap_experiment() {
  return {
      "envmap",
      "`sglab envmap`: SG mixture fits of environment maps and shading error against the lobe count (envmap_lobes.*)",
      add_envmap_lobes_command,
      [](const runner::Places& p) {
        std::vector<Step> v;
        std::vector<std::string> lobes = {"envmap", "lobes"};
        for (const char* kind : {"sky", "studio", "mixture"}) {
          const std::string path = p.dir(kEnvmapDir) + "/" + kind + ".exr";
          // A --quick run makes them 128 wide (a sixteenth of the texels, which every fit and the
          // map's exact shading visit; the 2° sun, 0.7 texels wide there, is held as its texels'
          // supersampled means). The quick bases comparison reads studio and mixture at 32 wide.
          v.push_back(sglab_step(std::string("envmap-make-") + kind,
                                 std::string("generated environment: ") + kind + " (512×256 EXR)",
                                 {"envmap", "make", kind, "--out", path}, {"--width", "128"}));
          lobes.insert(lobes.end(), {"--env", std::string(kind) + "=" + path});
        }
        v.push_back(timed(sglab_step("envmap-lobes",
                                     "SG mixture fits and shading error against N (paper_tables/envmap_lobes.*)", lobes,
                                     {"--quick"})));
        v.push_back(plot_step("plot-envmap", "environment error against N, and each map beside its reconstructions",
                              {"plots/envmap_lobes.py", p.tables + "/envmap_lobes.csv",
                               p.dir(kEnvmapDir) + "/envmap_images.csv", p.key_figures()},
                              {"--quick"}));
        return v;
      },
      "envmap"};
}

}  // namespace sglab::experiments
