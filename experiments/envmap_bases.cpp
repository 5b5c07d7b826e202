// `sglab envmap bases`: environment-lighting bases compared at equal storage (envmap_bases.hpp).
//
// Environments run one after another and the fits of one environment one after another (each
// fit's own loops in parallel), so that the fit times are those of one fit on the machine; each
// fitted row is measured (map, diffuse and specular error) beside the later fits on core time they
// leave idle (RowMeasurer), and what is left once every fit is done in parallel over pixels.
#include "envmap_bases.hpp"

#include "env_arguments.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>

#include <pthread.h>
#include <sched.h>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "envmap_basis.hpp"
#include "option_checks.hpp"
#include "registry.hpp"
#include "envmap_data.hpp"
#include "envmap_sparse.hpp"
#include "input_error.hpp"
#include "sglab/render/environment.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::experiments::envmap_bases {
namespace {

using render::Rgb;

// Points per texel side of the texel means that the map error compares (fit/envmap.hpp).
constexpr int kMeanSubsamples = 4;
// Wall seconds over which the diffuse cost of a row is timed (repeated until then): --quick's
// ns/pixel column needs a magnitude, not three digits, and its rows are many.
constexpr double kTimingSeconds = 0.01, kQuickTimingSeconds = 0.001;

struct Loaded {
  std::string name;
  EnvMap map;
  std::optional<fit::SparseEnvMap> sparse;  // --resolve
};

Options effective(const Options& o) {
  Options a = o;
  if (a.envs.empty()) throw runner::InputError("envmap bases needs at least one --env NAME=MAP.exr");
  // Checked before --quick replaces it: a bad --width is refused, not silently ignored.
  if (a.width < 8 || a.width > 1024) throw runner::InputError(fmt::format("--width {} must be in [8, 1024]", a.width));
  if (a.quick) a.width = 32;
  if (a.sphere_res < 2 || a.sphere_res > 256)
    throw runner::InputError(fmt::format("--res {} must be in [2, 256]", a.sphere_res));
  if (a.normals < 1 || a.normals > 100000)
    throw runner::InputError(fmt::format("--normals {} must be in [1, 100000]", a.normals));
  if (!(a.tolerance > 0 && a.tolerance < 1))
    throw runner::InputError(fmt::format("--tolerance {} must be in (0, 1)", a.tolerance));
  for (double r : a.roughness)
    if (!(r > 0 && r <= 1)) throw runner::InputError(fmt::format("--roughness {} must be in (0, 1]", r));
  if (std::find(a.roughness.begin(), a.roughness.end(), kTargetRoughness) == a.roughness.end())
    a.roughness.push_back(kTargetRoughness);
  std::sort(a.roughness.begin(), a.roughness.end());
  if (a.bases.empty())
    for (const auto& b : fit::envmap_bases()) a.bases.push_back(b.name);
  for (std::size_t i = 0; i < a.bases.size(); ++i) {
    if (!fit::find_envmap_basis(a.bases[i]))
      throw runner::InputError("unknown --basis '" + clip_text(a.bases[i]) + "' (bases: " + fit::envmap_basis_names() +
                               ")");
    if (std::find(a.bases.begin(), a.bases.begin() + std::ptrdiff_t(i), a.bases[i]) !=
        a.bases.begin() + std::ptrdiff_t(i))
      throw runner::InputError("--basis " + quote(a.bases[i]) + " is given twice");
  }
  check_env_arguments(a.envs);  // a name is a table label and a CSV field: a plain word, once
  std::vector<std::string> names;
  for (const auto& e : a.envs) names.push_back(e.substr(0, e.find('=')));
  for (std::size_t i = 0; i < a.resolve.size(); ++i) {
    if (std::find(names.begin(), names.end(), a.resolve[i]) == names.end())
      throw runner::InputError("--resolve '" + clip_text(a.resolve[i]) + "' names no --env");
    if (std::find(a.resolve.begin(), a.resolve.begin() + std::ptrdiff_t(i), a.resolve[i]) !=
        a.resolve.begin() + std::ptrdiff_t(i))
      throw runner::InputError("--resolve " + quote(a.resolve[i]) + " is given twice");
  }
  if (!(a.resolve_tolerance > 0 && a.resolve_tolerance < 1))
    throw runner::InputError(fmt::format("--resolve-tolerance {} must be in (0, 1)", a.resolve_tolerance));
  return a;
}

std::vector<Loaded> load(const Options& a) {
  std::vector<Loaded> out;
  for (const auto& e : a.envs) {
    LoadedEnv env = load_env_argument(e);
    EnvMap& m = env.map;
    const std::string& name = env.name;
    if (std::find(a.resolve.begin(), a.resolve.end(), name) != a.resolve.end()) {
      // The same reduced map as below, plus the detail tiles of the full map.
      fit::SparseEnvMap sparse = fit::make_sparse_envmap(m, a.width, a.resolve_tolerance);
      EnvMap reduced = sparse.reduced;
      out.push_back({name, std::move(reduced), std::move(sparse)});
      continue;
    }
    while (m.width > a.width && m.width % 2 == 0 && m.height % 2 == 0) m = downsample_envmap(m);
    out.push_back({name, std::move(m), std::nullopt});
  }
  return out;
}

// The sizes of a basis in this run (the registry's defaults; --quick keeps the small ones: L ≤ 4,
// N ≤ 16, and of sg-free, whose lobe ladder costs the most per size, N ≤ 8).
std::vector<int> sizes(const fit::EnvBasis& b, const Options& a, const EnvMap& map) {
  const int quick_max = b.size_symbol == "L" ? 4 : b.name == "sg-free" ? 8 : 16;
  std::vector<int> v;
  for (int n : b.default_sizes)
    if ((!a.quick || n <= quick_max) && (b.size_symbol == "L" || std::size_t(n) <= map.size())) v.push_back(n);
  return v;
}

// A representation sampled as texel means of s × s points per texel of a width × height grid.
EnvMap texel_means(const fit::EnvBasisFit& f, int width, int height, int s) {
  EnvMap m{width, height, std::vector<std::array<float, 3>>(std::size_t(width) * std::size_t(height))};
  if (f.sh_order < 0 && (s & (s - 1)) == 0) {
    // An SG fit: rasterize_mixture_rows, the same points (envmap_direction's) and sums in the same
    // order, its exponentials batched; its ·(1/s²) is the division by s² when s is a power of two.
    tbb::parallel_for(tbb::blocked_range<int>(0, height, 4), [&](const tbb::blocked_range<int>& rows) {
      rasterize_mixture_rows(f.mixture, s, rows.begin(), rows.end(), m);
    });
    return m;
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 4), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v < rows.end(); ++v)
      for (int u = 0; u < width; ++u) {
        std::array<double, 3> sum{0, 0, 0};
        for (int sy = 0; sy < s; ++sy)
          for (int sx = 0; sx < s; ++sx) {
            const auto x = f.radiance(envmap_direction(width, height, u + (sx + 0.5) / s, v + (sy + 0.5) / s));
            for (int c = 0; c < 3; ++c) sum[std::size_t(c)] += x[std::size_t(c)];
          }
        auto& t = m.texels[std::size_t(v) * std::size_t(width) + std::size_t(u)];
        for (int c = 0; c < 3; ++c) t[std::size_t(c)] = float(sum[std::size_t(c)] / (s * s));
      }
  });
  return m;
}

// f(s) for s = 1, 2, 4, … until two successive results differ by at most `tolerance` (relative
// L2 over the image); returns the finer one and records s and the change.
template <class F>
std::vector<Rgb> converged(const F& f, const render::EnvImage& image, double tolerance, Convergence& c) {
  std::vector<Rgb> previous = f(1);
  for (int s = 2;; s *= 2) {
    std::vector<Rgb> next = f(s);
    c.subsamples = s;
    c.change = render::shading_error(previous, next, image).relative_l2;
    if (c.change <= tolerance || s >= kMaxSubsamples) return next;
    previous = std::move(next);
  }
}

// A resolved map's SG fit on a quadrature grid `height` rows high: each lobe convolved with the
// grid's texel as a Gaussian (1/λ' = 1/λ + δ²/12, δ = π/height, integral kept: the texel model of
// the fits, fit/envmap.hpp), so that a lobe narrower than the grid's spacing (a sun fitted on the
// detail tiles) is integrated over the texel, not point-sampled.
fit::EnvBasisFit blurred_for_grid(const fit::EnvBasisFit& f, int height) {
  fit::EnvBasisFit b = f;
  const double delta = M_PI / double(height), s2 = delta * delta / 12;
  for (auto& l : b.mixture) {
    const double q = 1 / (1 + l.sharpness * s2);
    l.sharpness *= q;
    for (double& x : l.amplitude) x *= q;
  }
  return b;
}

render::EnvImage normal_image(int count) {
  render::EnvImage im{count, 1, {}};
  const auto normals = fit::envmap_detail::fibonacci_axes(count);
  for (int k = 0; k < count; ++k) im.points.push_back({k, normals[std::size_t(k)], normals[std::size_t(k)]});
  return im;
}

// The shading repeated for at least `seconds` of wall time; ns per pixel of one repetition.
template <class F>
double ns_per_pixel(const F& shade, std::size_t pixels, double seconds) {
  int reps = 0;
  const auto t0 = std::chrono::steady_clock::now();
  double elapsed = 0;
  do {
    shade();
    ++reps;
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } while (elapsed < seconds);
  return elapsed * 1e9 / (double(reps) * double(pixels));
}

std::string command_line(const Options& a) {
  std::string c = "sglab envmap bases";
  for (const auto& e : a.envs) c += " --env " + e;
  for (const auto& b : a.bases) c += " --basis " + b;
  for (const auto& n : a.resolve) c += " --resolve " + n;
  if (!a.resolve.empty()) c += fmt::format(" --resolve-tolerance {}", a.resolve_tolerance);
  c += fmt::format(" --width {} --res {} --normals {} --tolerance {} --seed {}", a.width, a.sphere_res, a.normals,
                   a.tolerance, a.seed);
  return c + " --out " + a.out + " --tables-dir " + runner::tables_place(a.tables_dir, a.out).string();
}

// What the rows of one environment are measured against: its map, its converged quadratures and
// the images they were computed on.
struct EnvReferences {
  const Loaded* env = nullptr;
  const Options* options = nullptr;
  const render::EnvImage* normals = nullptr;
  const render::EnvImage* sphere = nullptr;
  const std::vector<Vec3<double>>* normal_dirs = nullptr;
  std::vector<Rgb> exact_diffuse;
  std::vector<std::vector<Rgb>> exact_specular;  // per roughness
  std::vector<Convergence> convergence;          // diffuse, then per roughness
};

// The errors and the diffuse cost of one fit (one row of the tables).
void measure_row(const EnvReferences& e, const fit::EnvBasisFit& f, fit::LobeDiffuseCache& diffuse_cache,
                 std::mutex& cache_lock, Row& row) {
  const Loaded& env = *e.env;
  const Options& a = *e.options;
  const render::EnvImage& normals = *e.normals;
  const render::EnvImage& sphere = *e.sphere;
  const EnvMap means = texel_means(f, env.map.width, env.map.height, kMeanSubsamples);
  row.map_error = env.sparse ? fit::sparse_error(*env.sparse, means,
                                                 fit::tile_texel_means(
                                                     *env.sparse, [&f](const Vec3<double>& w) { return f.radiance(w); },
                                                     kMeanSubsamples))
                                   .relative
                             : envmap_error(env.map, means).relative;
  std::vector<Rgb> diffuse(normals.points.size());
  std::vector<std::array<double, 3>> exact;
  {
    const std::lock_guard guard(cache_lock);
    exact = fit::diffuse_at(f, *e.normal_dirs, diffuse_cache);
  }
  for (std::size_t k = 0; k < exact.size(); ++k) diffuse[k] = Rgb(exact[k][0], exact[k][1], exact[k][2]);
  row.diffuse_error = render::shading_error(diffuse, e.exact_diffuse, normals).relative_l2;
  const double timing = a.quick ? kQuickTimingSeconds : kTimingSeconds;
  if (f.sh_order >= 0) {
    row.engine_diffuse_error = row.diffuse_error;
    row.diffuse_ns = ns_per_pixel(
        [&] {
          for (const auto& p : normals.points) diffuse[std::size_t(p.pixel)][0] = f.diffuse(p.normal)[0];
        },
        normals.points.size(), timing);
  } else {
    const auto engine = render::mixture_diffuse_method(f.mixture, normals, kEngineDiffuse);
    row.engine_diffuse_error = render::shading_error(engine, e.exact_diffuse, normals).relative_l2;
    row.diffuse_ns = ns_per_pixel([&] { render::mixture_diffuse_method(f.mixture, normals, kEngineDiffuse); },
                                  normals.points.size(), timing);
  }
  // The representation integrated on the same nodes as the map's accepted quadrature.
  std::map<int, EnvMap> grids;
  for (std::size_t ri = 0; ri < a.roughness.size(); ++ri) {
    const int s = e.convergence[ri + 1].subsamples;
    if (!grids.count(s))
      grids.emplace(s, texel_means(env.sparse && f.sh_order < 0 ? blurred_for_grid(f, env.map.height * s) : f,
                                   env.map.width * s, env.map.height * s, 1));
    const auto spec = render::integrate_specular(grids.at(s), sphere, a.roughness[ri], a.f0, 1);
    row.specular_error.push_back(render::shading_error(spec, e.exact_specular[ri], sphere).relative_l2);
  }
  std::fprintf(stderr,
               "envmap bases: %s %s%s%s %s=%d (%d floats): map %.3g, diffuse %.3g, specular(0.3) %.3g, %.3f s%s\n",
               env.name.c_str(), row.basis.c_str(), row.variant.empty() ? "" : " ", row.variant.c_str(),
               row.size_symbol.c_str(), f.size, f.floats, row.map_error, row.diffuse_error,
               row.specular_error[std::size_t(std::find(a.roughness.begin(), a.roughness.end(), kTargetRoughness) -
                                              a.roughness.begin())],
               f.seconds, f.zero_lobes ? fmt::format(", {} zero-amplitude lobes", f.zero_lobes).c_str() : "");
}

// The rows' measurements (measure_row) beside the fits. The fits run one at a time on the calling
// thread, and their times are part of the tables; the free-lobe fit's Ceres solves leave a core
// mostly idle (Ceres 2.1's conjugate-gradient products run on one thread). A thread of its own, at
// the idle scheduling class (SCHED_IDLE: it runs only where a core would otherwise be idle, and
// yields to the fits at once), measures the rows already fitted, one at a time and each on that
// thread alone (a task arena of one slot), in the order fitted; once every fit is done, the calling
// thread measures the rows still waiting, with every core. Every row is measured by the same calls
// on the same inputs in either place, so the values do not depend on which thread measured it.
class RowMeasurer {
 public:
  // beside = false: each row is measured on the calling thread as it is pushed (no idle thread).
  explicit RowMeasurer(bool beside) {
    if (beside) idle_ = std::thread(&RowMeasurer::idle_loop, this);
  }
  ~RowMeasurer() { finish_noexcept(); }
  RowMeasurer(const RowMeasurer&) = delete;
  RowMeasurer& operator=(const RowMeasurer&) = delete;

  void push(const EnvReferences* e, fit::EnvBasisFit f, Row* row) {
    if (!idle_.joinable()) {
      Job j{e, std::move(f), row};
      run(j);
      return;
    }
    {
      const std::lock_guard guard(lock_);
      jobs_.push_back({e, std::move(f), row});
    }
    wake_.notify_one();
  }

  // Measures what is left on this thread (all cores), then waits for the idle thread's last row.
  void finish() {
    if (!idle_.joinable()) return;
    {
      const std::lock_guard guard(lock_);
      closed_ = true;
    }
    wake_.notify_one();
    // The idle thread's current row is now waited for: it may run at normal priority (where the
    // system allows raising it back; otherwise it keeps the idle class).
    sched_param normal{};
    pthread_setschedparam(idle_.native_handle(), SCHED_OTHER, &normal);
    for (std::optional<Job> j; (j = take());) run(*j);
    idle_.join();
    if (failure_) std::rethrow_exception(failure_);
  }

 private:
  struct Job {
    const EnvReferences* e;
    fit::EnvBasisFit f;
    Row* row;
  };

  std::optional<Job> take() {
    const std::lock_guard guard(lock_);
    if (jobs_.empty()) return std::nullopt;
    Job j = std::move(jobs_.front());
    jobs_.pop_front();
    return j;
  }

  void run(Job& j) { measure_row(*j.e, j.f, cache_, cache_lock_, *j.row); }

  void idle_loop() {
    sched_param idle{};
    pthread_setschedparam(pthread_self(), SCHED_IDLE, &idle);  // if refused: normal priority
    tbb::task_arena alone(1);
    for (;;) {
      std::optional<Job> j;
      {
        std::unique_lock guard(lock_);
        wake_.wait(guard, [&] { return closed_ || !jobs_.empty(); });
        if (jobs_.empty() || failure_) return;
        j = std::move(jobs_.front());
        jobs_.pop_front();
      }
      try {
        alone.execute([&] { run(*j); });
      } catch (...) {
        const std::lock_guard guard(lock_);
        failure_ = std::current_exception();
        return;
      }
    }
  }

  void finish_noexcept() {
    if (!idle_.joinable()) return;
    {
      const std::lock_guard guard(lock_);
      closed_ = true;
      jobs_.clear();
    }
    wake_.notify_one();
    idle_.join();
  }

  std::mutex lock_;
  std::condition_variable wake_;
  std::deque<Job> jobs_;
  bool closed_ = false;
  std::exception_ptr failure_;
  fit::LobeDiffuseCache cache_;  // shared by both threads under cache_lock_ (its values do not depend on hits)
  std::mutex cache_lock_;
  std::thread idle_;  // last: started once the members it uses exist
};

}  // namespace

Result compute(const Options& o) {
  const auto t_start = std::chrono::steady_clock::now();
  Result r;
  r.options = effective(o);
  const Options& a = r.options;
  const auto envs = load(a);
  r.provenance = runner::Provenance{command_line(a), a.quick};
  const render::EnvImage normals = normal_image(a.normals);
  const render::EnvImage sphere = render::sphere_image(a.sphere_res);
  std::vector<Vec3<double>> normal_dirs;
  for (const auto& p : normals.points) normal_dirs.push_back(p.normal);
  fit::EnvBasisOptions bo;
  bo.seed = a.seed;
  // Kept in place until every row is measured: the rows point into them.
  std::deque<EnvReferences> references;
  std::vector<std::deque<Row>> rows(envs.size());
  RowMeasurer measurer(a.measure_beside_fits);
  for (std::size_t ei = 0; ei < envs.size(); ++ei) {
    const Loaded& env = envs[ei];
    Environment out;
    out.name = env.name;
    out.width = env.map.width;
    out.height = env.map.height;
    bo.sparse = env.sparse ? &*env.sparse : nullptr;
    if (env.sparse) {
      out.full_width = env.sparse->full_width;
      out.full_height = env.sparse->full_height;
      out.tiles = int(env.sparse->tiles.size());
      out.reduced_l2 = env.sparse->reduced_relative_l2;
      out.sparse_l2 = env.sparse->relative_l2;
      std::fprintf(
          stderr,
          "envmap bases: %s resolved: %d×%d as %d×%d + %d tiles of %d×%d (relative L2 %.3g, reduced alone %.3g)\n",
          env.name.c_str(), out.full_width, out.full_height, out.width, out.height, out.tiles, env.sparse->factor,
          env.sparse->factor, out.sparse_l2, out.reduced_l2);
    }
    std::fprintf(stderr, "envmap bases: %s (%d×%d): converged quadratures of the map …\n", env.name.c_str(), out.width,
                 out.height);
    EnvReferences& ref = references.emplace_back();
    ref.env = &env;
    ref.options = &a;
    ref.normals = &normals;
    ref.sphere = &sphere;
    ref.normal_dirs = &normal_dirs;
    Convergence cd;
    ref.exact_diffuse = converged([&](int s) { return render::integrate_diffuse(env.map, normals, s); }, normals,
                                  a.tolerance, cd);
    ref.convergence.push_back(cd);
    for (double rough : a.roughness) {
      Convergence cs;
      cs.roughness = rough;
      ref.exact_specular.push_back(converged(
          [&](int s) { return render::integrate_specular(env.map, sphere, rough, a.f0, s); }, sphere, a.tolerance, cs));
      ref.convergence.push_back(cs);
    }
    out.convergence = ref.convergence;
    for (const auto& name : a.bases) {
      const fit::EnvBasis& basis = *fit::find_envmap_basis(name);
      for (const auto& variant : basis.variants) {
        std::vector<fit::EnvBasisFit> fits;
        try {
          fits = basis.fit(env.map, sizes(basis, a, env.map), variant, bo);
        } catch (const std::invalid_argument& e) {
          throw runner::InputError(e.what());
        }
        for (auto& f : fits) {
          Row& row = rows[ei].emplace_back();
          row.basis = basis.name;
          row.variant = variant;
          row.size_symbol = basis.size_symbol;
          row.size = f.size;
          row.floats = f.floats;
          row.zero_lobes = f.zero_lobes;
          row.kept_lobes = f.kept_lobes;
          row.iterations = f.iterations;
          row.fit_width = f.fit_width;
          row.fit_height = f.fit_height;
          row.detail_tiles = f.detail_tiles;
          row.seconds = f.seconds;
          measurer.push(&ref, std::move(f), &row);
        }
      }
    }
    r.environments.push_back(std::move(out));
  }
  measurer.finish();
  for (std::size_t ei = 0; ei < envs.size(); ++ei)
    r.environments[ei].rows.assign(std::make_move_iterator(rows[ei].begin()), std::make_move_iterator(rows[ei].end()));
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return r;
}

}  // namespace sglab::experiments::envmap_bases

// ---- the experiment: its command and its reproduce steps ----------------------------------------

namespace sglab::experiments {

// `sglab envmap bases` (registered under `envmap`).
void add_envmap_bases_command(CLI::App& envmap, const runner::RunContext& run) {
  auto a = std::make_shared<envmap_bases::Options>();
  auto* sub = envmap.add_subcommand("bases",
                                    "SH, fixed-lobe SG, vMF and free-lobe SG at equal storage (envmap_bases.{md,csv})");
  sub->add_option("--env", a->envs, "NAME=MAP.exr (repeat)")->required();
  sub->add_option("--basis", a->bases, "bases to compare (repeat; default all): " + fit::envmap_basis_names());
  sub->add_option("--width", a->width, "maps reduced by 2×2 means to at most this width")->capture_default_str();
  sub->add_option("--roughness", a->roughness, "GGX roughnesses (0.3 is always included)")->capture_default_str();
  sub->add_option("--res", a->sphere_res, "sphere image size of the specular layer")->capture_default_str();
  sub->add_option("--normals", a->normals, "Fibonacci normals of the diffuse layer")->capture_default_str();
  sub->add_option("--tolerance", a->tolerance, "relative L2 change at which the map quadratures count as converged")
      ->capture_default_str();
  sub->add_option("--seed", a->seed, "k-means++ and running-average seed")->capture_default_str();
  sub->add_option(
      "--resolve", a->resolve,
      "environment NAME held at full resolution: the reduced map plus detail tiles (repeat; vmf-em and sg-free fit it, "
      "map errors against the full map)");
  sub->add_option(
         "--resolve-tolerance", a->resolve_tolerance,
         "relative L2 of the reduced map plus detail tiles against the full map at which tiles stop being added")
      ->capture_default_str();
  frontend::add_places_options(*sub, run.places, kEnvmapDir, a->out, a->tables_dir, "directory for per-run outputs",
                               "where envmap_bases.{md,csv} go (default: the --out directory)");
  sub->add_flag("--quick", a->quick, "32-wide maps, N ≤ 16 (sg-free N ≤ 8), L ≤ 4 (a smoke run; not for paper_tables)");
  sub->callback([a, run] { envmap_bases::write(runner::with_run(envmap_bases::compute(*a), run)); });
}

// The three new generated environments (a physically sized sun, an overcast sky, an indoor room
// with rectangular emitters), then every basis on them and on the three maps of the `envmap`
// experiment (written before this one runs), and the figure.
Experiment envmap_bases_experiment() {
  return {
      "envmap-bases", "`sglab envmap bases`: SH, fixed-lobe SG, vMF and free-lobe SG at equal storage (envmap_bases.*)",
      add_envmap_bases_command,
      [](const runner::Places& p) {
        std::vector<Step> v;
        const std::string dir = p.dir(kEnvmapDir) + "/";
        // The sun of the sky at its real angular diameter, 0.53°, with the power of the default
        // 2° disk (luminance × (2/0.53)² ≈ 14.24, 500 → 7120).
        // Both suns at 2048 wide (a texel of 0.18°), held by `--resolve` as the 128-wide map plus
        // full-resolution tiles where the sun is.
        // A --quick run makes them 1024 wide (a quarter of the texels; the sun still spans 1.5 texels),
        // and the overcast and indoor maps 256 wide (the quick comparison reads them at 32 wide).
        v.push_back(sglab_step("envmap-make-sun", "generated environment: clear sky, 0.53° sun (2048×1024 EXR)",
                               {"envmap", "make", "sky", "--sun-size", "0.53", "--sun-luminance", "7120", "--width",
                                "2048", "--out", dir + "sun.exr"},
                               {"--width", "1024"}));
        v.push_back(sglab_step("envmap-make-sky-2048", "generated environment: clear sky, 2° sun (2048×1024 EXR)",
                               {"envmap", "make", "sky", "--width", "2048", "--out", dir + "sky_2048.exr"},
                               {"--width", "1024"}));
        v.push_back(sglab_step("envmap-make-overcast", "generated environment: CIE overcast sky (512×256 EXR)",
                               {"envmap", "make", "overcast", "--out", dir + "overcast.exr"}, {"--width", "256"}));
        v.push_back(sglab_step("envmap-make-indoor",
                               "generated environment: indoor room with rectangular emitters (512×256 EXR)",
                               {"envmap", "make", "indoor", "--out", dir + "indoor.exr"}, {"--width", "256"}));
        std::vector<std::string> args = {"envmap", "bases"};
        for (const char* kind : {"sky", "sun", "overcast", "studio", "indoor", "mixture"})
          args.insert(args.end(), {"--env", std::string(kind) + "=" + dir +
                                                (kind == std::string("sky") ? "sky_2048" : kind) + ".exr"});
        args.insert(args.end(), {"--resolve", "sky", "--resolve", "sun"});
        // --quick: also the map quadratures converged to 1 % instead of 0.2 %, detail tiles
        // until the resolved maps are within 5 % of the full map instead of 1 %, and the
        // shading layers on an 8 × 8 sphere and 32 normals instead of 12 × 12 and 128 (the
        // exact diffuse of every fitted lobe at every normal, a quadrature each, was a fifth of
        // the quick run's time at 64).
        v.push_back(timed(sglab_step(
            "envmap-bases", "bases at equal storage (paper_tables/envmap_bases.*)", args,
            {"--quick", "--tolerance", "0.01", "--resolve-tolerance", "0.05", "--res", "8", "--normals", "32"})));
        v.push_back(plot_step("plot-envmap-bases", "error against stored floats, one panel per layer",
                              {"plots/envmap_bases.py", p.tables + "/envmap_bases.csv", p.key_figures()}, {"--quick"}));
        return v;
      },
      "envmap"};
}

}  // namespace sglab::experiments
