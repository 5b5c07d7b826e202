// `sglab render SCENE.json --out IMAGE.exr …`: renders a scene with direct light
// (shadow map), indirect light from VSGLs, and the exact VPL-sum reference, and writes a
// multi-layer OpenEXR (direct, indirect, indirect_reference, error = indirect − reference) and a
// stats JSON. Bad input (scene or options) stops with exit status 2 before anything is written;
// outputs are written atomically.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>

#include <fmt/format.h>

#include "atomic_file.hpp"
#include "commands.hpp"
#include "environment_render.hpp"
#include "option_checks.hpp"
#include "render_job.hpp"
#include "sglab/render/exr.hpp"
#include "sglab/render/vsgl_specular_methods.hpp"

namespace sglab::cli {
namespace {

struct Options {
  frontend::RenderJob job;
  std::string out;
  std::string stats;
  std::string dump_csv;
  std::string specular{render::kDefaultSpecularMethod};  // --specular
  bool quiet = false;
};

// Every pixel's layers as CSV (x, y, hit, then R, G, B of each layer; 9 significant digits, the
// EXR's float precision) for tools without an EXR reader (plots/render_images.py).
std::string pixel_csv(const render::RenderResult& r) {
  std::string csv =
      "x,y,hit,direct_r,direct_g,direct_b,indirect_r,indirect_g,indirect_b,indirect_reference_r,indirect_reference_g,"
      "indirect_reference_b,error_r,error_g,error_b\n";
  csv.reserve(csv.size() + std::size_t(r.width) * std::size_t(r.height) * 140);
  for (int j = 0; j < r.height; ++j)
    for (int i = 0; i < r.width; ++i) {
      const std::size_t k = std::size_t(j) * std::size_t(r.width) + std::size_t(i);
      csv += fmt::format("{},{},{}", i, j, int(r.hit[k]));
      for (const auto* layer : {&r.direct, &r.indirect, &r.indirect_reference, &r.error})
        for (int c = 0; c < 3; ++c) csv += fmt::format(",{:.9g}", float((*layer)[k](c)));
      csv += '\n';
    }
  return csv;
}

std::string quote_if_needed(const std::string& s) {
  if (s.find_first_of(" \t'\"\\$`") == std::string::npos && !s.empty()) return s;
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

void run(const Options& o) {
  if (o.out.empty()) throw runner::InputError("render needs --out IMAGE.exr");
  runner::check_output_paths({{"--out", o.out}, {"--stats", o.stats}, {"--dump-csv", o.dump_csv}},
                             {{"scene", o.job.scene_path}});
  frontend::RenderJobRun job(o.job, o.specular, frontend::load_scene(o.job), !o.dump_csv.empty());
  const render::Scene& scene = job.scene;
  render::RenderOptions& options = job.options;
  std::string command = "sglab render " + quote_if_needed(o.job.scene_path) + " --out " + quote_if_needed(o.out);
  for (const auto& a : frontend::render_job_arguments(o.job)) command += " " + quote_if_needed(a);
  if (o.specular != render::kDefaultSpecularMethod) command += " --specular " + quote_if_needed(o.specular);
  if (!o.stats.empty()) command += " --stats " + quote_if_needed(o.stats);
  if (!o.dump_csv.empty()) command += " --dump-csv " + quote_if_needed(o.dump_csv);

  const auto start = std::chrono::steady_clock::now();
  // Progress on stderr: a line when a stage starts and ends, and at most every 2 s in between.
  struct ProgressState {
    std::mutex mutex;
    std::chrono::steady_clock::time_point last, stage_start;
  };
  auto progress_state = std::make_shared<ProgressState>();
  if (!o.quiet)
    options.progress = [start, progress_state](std::string_view stage, double fraction) {
      std::lock_guard lock(progress_state->mutex);
      const auto now = std::chrono::steady_clock::now();
      const double total = std::chrono::duration<double>(now - start).count();
      if (fraction == 0) progress_state->stage_start = now;
      const double in_stage = std::chrono::duration<double>(now - progress_state->stage_start).count();
      if (fraction > 0 && fraction < 1 && std::chrono::duration<double>(now - progress_state->last).count() < 2) return;
      progress_state->last = now;
      if (fraction == 0) std::fprintf(stderr, "render: %.*s …\n", int(stage.size()), stage.data());
      else if (fraction == 1)
        std::fprintf(stderr, "render: %.*s done in %.2f s (%.1f s total)\n", int(stage.size()), stage.data(), in_stage,
                     total);
      else
        std::fprintf(stderr, "render: %.*s %3.0f %% (%.1f s)\n", int(stage.size()), stage.data(), 100 * fraction,
                     in_stage);
    };
  if (!o.quiet)
    std::fprintf(stderr, "render: %s, %d×%d pixels, RSM %d×%d, VSGL %s\n", o.job.scene_path.c_str(), scene.camera.width,
                 scene.camera.height, options.rsm_resolution, options.rsm_resolution, o.job.vsgl.c_str());
  const auto [r, layers, stats] = job.run(command);

  const std::string exr = render::encode_exr(
      r.width, r.height, layers, {{"sglab_command", command}, {"sglab_notes", stats["notes"].get<std::string>()}});
  runner::OutputSet outputs;
  outputs.add(o.out, exr);
  if (!o.stats.empty()) outputs.add(o.stats, stats.dump(2) + "\n");
  if (!o.dump_csv.empty()) outputs.add(o.dump_csv, "# Generated by `" + command + "`\n" + pixel_csv(r));
  outputs.commit();

  const auto& s = r.seconds;
  std::printf(
      "render %s: %d×%d, %zu VPLs, %zu VSGLs (%zu specular), %s\n"
      "  seconds: rsm %.3f, vsgl %.4f, shading %.3f, reference %.3f (speedup %.0f×)\n"
      "  indirect vs reference: relative L2 %.4g, SMAPE %.4g, RMSE %.4g\n"
      "  wrote %s%s%s\n",
      o.job.scene_path.c_str(), r.width, r.height, r.vpl_count, std::size_t(stats["vsgl_count"]),
      r.vsgls.stats.specular_vsgls,
      r.specular_shading ? ("specular shading (" + o.specular + ") on glossy receivers").c_str()
                         : "no specular shading (no glossy receiver or VSGL)",
      s.rsm, s.vsgl, s.shading, s.reference, stats["speedup_vsgl_over_reference"].get<double>(),
      r.error_metrics.relative_l2, r.error_metrics.smape, r.error_metrics.rmse, o.out.c_str(),
      o.stats.empty() ? "" : " and ", o.stats.c_str());
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto opts = std::make_shared<Options>();
  auto* sub = app.add_subcommand(
      "render", "Render a scene: direct, VSGL indirect, exact VPL-sum reference and error (EXR + stats JSON)");
  sub->add_option("scene", opts->job.scene_path, "scene JSON (schema: scenes/README.md)")->required();
  sub->add_option("--out", opts->out, "output OpenEXR image (layers direct, indirect, indirect_reference, error)");
  sub->add_option("--stats", opts->stats, "output stats JSON");
  sub->add_option("--dump-csv", opts->dump_csv, "also write every pixel's layers as CSV (for plots/render_images.py)");
  sub->add_flag("--quiet", opts->quiet, "no progress on stderr");
  frontend::add_specular_option(*sub, opts->specular);
  frontend::add_render_job_options(*sub, opts->job);
  sub->callback([opts] { run(*opts); });
}

}  // namespace sglab::cli
