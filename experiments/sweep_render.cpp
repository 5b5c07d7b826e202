// `sglab sweep render --scene S [--vary KEY=SPEC]… [--vsgl CONFIG]… [render options] --out DIR
//  [--table NAME] [--tables-dir DIR] [--shard i/N] [--threads N] [--fresh]`:
// the VSGL renderer's error against the exact VPL sum, and the cost of both, over a grid of scene
// parameters and VSGL configurations.
//
//  • --vary KEY=a:b:n        n values linearly spaced over [a, b] (n = 1: a alone);
//    --vary KEY=a:b:n:log    n values log-spaced (a, b > 0; the natural spacing for roughness);
//    --vary KEY=v1,v2,…      exactly these values.
//    KEY is any --set key (floor.roughness, light.distance, …), or vsgl.lambda_d: the diffuse VSGL's
//    vMF sharpness λ_d (default: the constant set's, `--constants`). Several --vary span their
//    Cartesian product, the last varying fastest; none: one point, the scene as given.
//  • --vsgl CONFIG           two | fis:N | kmeans:N, repeatable (default: two). Every configuration
//    is measured at every point against one shared reference: a point renders its G-buffer, RSM
//    and VPL sum once, then generates and shades each configuration's VSGLs. Consecutive points
//    whose scenes are equal (only vsgl.lambda_d varies) share one G-buffer, RSM and VPL sum, and
//    report the time it took. The direct layer is not rendered (--shadow-map has no effect here).
// A point is one parameter combination; its rows are its configurations. Points run one at a time
// (--threads 1 by default) because their timings are part of the result; each render uses all
// cores itself. Every point's scene is validated before anything runs (a bad value stops the
// sweep with the point's override and the field named, exit status 2).
// Outputs: DIR/NAME_points.csv (the runner's per-point CSV, sweep.hpp) and, derived from that file
// alone, TABLES/NAME.{md,csv} headed by the command (TABLES: --tables-dir, default DIR). NAME defaults to
// vsgl_error_vs_count without
// --vary, else vsgl_error_vs_ + the last component of each key ("vsgl_error_vs_roughness_distance").
#include "sweep_render.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <tbb/task_arena.h>

#include "atomic_file.hpp"
#include "table.hpp"
#include "option_checks.hpp"
#include "constant_sets.hpp"
#include "parse_number.hpp"
#include "resource_limits.hpp"
#include "sglab/text_limits.hpp"
#include "sweep.hpp"
#include "fit_all.hpp"
#include "registry.hpp"
#include "sglab/render/vsgl_generation.hpp"

namespace sglab::experiments {
namespace sweep_render {
namespace {

namespace fs = std::filesystem;

struct VsglConfig {
  std::string text;  // as given: "two", "fis:16"
  render::VsglMode mode = render::VsglMode::two;
  int count = 1;
  std::string label() const {
    return render::vsgl_mode_is_whole_rsm(mode) ? std::string(vsgl_mode_name(mode))
                                                : fmt::format("{} {}", vsgl_mode_name(mode), count);
  }
};

bool try_parse_decimal(const std::string& text, double& x) {
  try {
    x = runner::parse_decimal<double>(text);
    return true;
  } catch (const runner::NumberError&) {
    return false;
  }
}

double parse_value(const std::string& text, const std::string& where) {
  try {
    return runner::parse_decimal<double>(text);
  } catch (const runner::NumberError& e) {
    throw runner::InputError(fmt::format("{}: {} {}", where, quote(text), e.what()));
  }
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  for (std::size_t start = 0;;) {
    const auto at = text.find(separator, start);
    parts.push_back(text.substr(start, at == std::string::npos ? std::string::npos : at - start));
    if (at == std::string::npos) break;
    start = at + 1;
  }
  return parts;
}

Vary parse_vary(const std::string& text) {
  const std::string where = "--vary " + text;
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw runner::InputError(where + ": expected KEY=a:b:n[:log|:lin] or KEY=v1,v2,…");
  Vary v{text.substr(0, eq), text.substr(eq + 1), {}};
  if (v.spec.find(':') == std::string::npos) {
    for (const auto& item : split(v.spec, ',')) v.values.push_back(parse_value(item, where));
    return v;
  }
  std::vector<std::string> parts = split(v.spec, ':');
  bool log_spaced = false;
  if (parts.size() == 4) {
    if (parts[3] == "log") {
      log_spaced = true;
    } else if (parts[3] != "lin") {
      throw runner::InputError(fmt::format("{}: spacing {} is neither log nor lin", where, quote(parts[3])));
    }
    parts.pop_back();
  }
  if (parts.size() != 3) throw runner::InputError(where + ": expected KEY=a:b:n[:log|:lin]");
  const double a = parse_value(parts[0], where), b = parse_value(parts[1], where), nd = parse_value(parts[2], where);
  if (nd != std::floor(nd) || nd < 1 || nd > 1000)
    throw runner::InputError(fmt::format("{}: n = {} is not an integer in [1, 1000]", where, parts[2]));
  const int n = int(nd);
  if (log_spaced && !(a > 0 && b > 0)) throw runner::InputError(fmt::format("{}: log spacing needs a, b > 0", where));
  for (int i = 0; i < n; ++i) {
    const double t = n == 1 ? 0.0 : double(i) / (n - 1);
    double x = log_spaced ? std::exp(std::log(a) + t * (std::log(b) - std::log(a))) : a + t * (b - a);
    if (i == 0) x = a;  // the ends exactly as given
    if (i == n - 1 && n > 1) x = b;
    v.values.push_back(x);
  }
  return v;
}

// vsgl.lambda_d=v1,v2,… may name fit records (`sglab fit lambda-d --json FILE`) instead of numbers.
Vary parse_lambda_d_vary(const std::string& text, std::vector<std::string>& sources) {
  Vary l{kLambdaDKey, text.substr(kLambdaDKey.size() + 1), {}};
  for (const auto& item : split(l.spec, ',')) {
    double x;
    if (try_parse_decimal(item, x)) {
      sources.push_back(fmt::format("{} (given)", item));
    } else {
      const ConstantSet set = frontend::load_constant_sets({item});
      const ConstantValue* c = set.find("lambda-d", "lambda_d");
      if (!c) throw runner::InputError(fmt::format("--vary {}: {} holds no lambda-d fit", kLambdaDKey, quote(item)));
      x = c->value;
      sources.push_back(fmt::format("{:.10g} ({})", x, c->provenance));
    }
    l.values.push_back(x);
  }
  return l;
}

std::vector<Vary> parse_varies(const Options& o, std::vector<std::string>& lambda_d_sources) {
  std::vector<Vary> vary;
  for (const auto& v : o.vary)
    vary.push_back(v.rfind(kLambdaDKey + "=", 0) == 0 && v.find(':') == std::string::npos
                       ? parse_lambda_d_vary(v, lambda_d_sources)
                       : parse_vary(v));
  for (const auto& v : vary)
    if (v.key == kLambdaDKey)
      for (double x : v.values)
        if (!(std::isfinite(x) && x > 0))
          throw runner::InputError(fmt::format("--vary {}: λ_d = {} is not a positive number", v.key, x));
  return vary;
}

VsglConfig parse_vsgl_config(const std::string& text) {
  const std::string where = "--vsgl " + text;
  VsglConfig c;
  c.text = text;
  const auto colon = text.find(':');
  const auto mode = render::parse_vsgl_mode(text.substr(0, colon));
  if (!mode) throw runner::InputError(where + ": expected two, two-shared, fis:N or kmeans:N");
  c.mode = *mode;
  if (render::vsgl_mode_is_whole_rsm(c.mode)) {
    if (colon != std::string::npos)
      throw runner::InputError(where + ": `" + std::string(vsgl_mode_name(c.mode)) + "` takes no count");
    return c;
  }
  if (colon == std::string::npos) throw runner::InputError(where + ": fis and kmeans need a count (fis:16)");
  const double n = parse_value(text.substr(colon + 1), where);
  if (n != std::floor(n) || n < 1 || n > 65536)
    throw runner::InputError(
        fmt::format("{}: count {} is not an integer in [1, 65536]", where, text.substr(colon + 1)));
  c.count = int(n);
  return c;
}

std::string last_component(const std::string& key) {
  const auto dot = key.rfind('.');
  return dot == std::string::npos ? key : key.substr(dot + 1);
}

const std::vector<std::string> kColumns = {
    "vsgl",      "vsgl_mode",   "vsgl_requested", "vsgl_count",      "specular_vsgls",
    "vpl_count", "pixels_hit",  "relative_l2",    "smape",           "rmse",
    "max_abs",   "seconds_rsm", "seconds_vsgl",   "seconds_shading", "seconds_reference",
    "speedup"};

std::string quote_if_needed(const std::string& s) {
  if (!s.empty() && s.find_first_of(" \t'\"\\$`[]*?") == std::string::npos) return s;
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// NAME: --table, else vsgl_error_vs_count without --vary, else vsgl_error_vs_ + each key's last
// component. The table pair is checked before anything runs (it is written only after the sweep).
std::string checked_table_name(const Options& o, const std::vector<Vary>& vary) {
  std::string name = o.table;
  if (name.empty()) {
    name = "vsgl_error_vs_count";
    if (!vary.empty()) {
      name = "vsgl_error_vs";
      for (const auto& v : vary) name += "_" + last_component(v.key);
    }
  }
  if (name.find_first_of("/\\ ") != std::string::npos || name.empty())
    throw runner::InputError(fmt::format("--table {} is not a file name", quote(name)));
  std::vector<runner::NamedPath> inputs{{"--scene", o.job.scene_path}};
  for (const auto& c : o.job.constants.paths) inputs.push_back({"--constants", c});
  runner::check_output_paths({{"--table (CSV)", runner::tables_place(o.tables_dir, o.out) / (name + ".csv")},
                              {"--table (Markdown)", runner::tables_place(o.tables_dir, o.out) / (name + ".md")}},
                             inputs);
  return name;
}

// Each --vary must set its own field: two keys naming one field (floor.roughness and
// objects.0.roughness, or the same key twice) would label rows with one value and render
// another. Found by setting a marker through each key and seeing which field changed.
void check_distinct_fields(const std::vector<Vary>& vary, const nlohmann::json& base) {
  std::vector<std::string> targets;
  for (std::size_t i = 0; i < vary.size(); ++i) {
    if (vary[i].key == kLambdaDKey) {  // a render option, not a scene field
      targets.push_back(kLambdaDKey);
      for (std::size_t j = 0; j < i; ++j)
        if (targets[j] == kLambdaDKey) throw runner::InputError(fmt::format("--vary {} is given twice", kLambdaDKey));
      continue;
    }
    nlohmann::json doc = base;
    try {
      render::apply_override(doc, vary[i].key + "=\"\u0001sglab-vary\"");
    } catch (const render::SceneError& e) {
      throw runner::InputError(fmt::format("--vary {}: {}", clip_text(vary[i].key), e.what()));
    }
    const nlohmann::json patch = nlohmann::json::diff(base, doc);
    targets.push_back(patch.empty() ? vary[i].key : patch[0].value("path", vary[i].key));
    for (std::size_t j = 0; j < i; ++j)
      if (targets[j] == targets[i])
        throw runner::InputError(fmt::format("--vary {} and --vary {} set the same field ({}); give each field once",
                                             clip_text(vary[j].key), clip_text(vary[i].key), clip_text(targets[i])));
  }
}

// The grid's points: point k's values (the last --vary fastest) and its scene.
struct Grid {
  std::vector<Vary> vary;
  nlohmann::json base;  // the scene document after --set
  frontend::RenderJob job;

  std::size_t points() const {
    std::size_t n = 1;
    for (const auto& v : vary) n = runner::checked_mul(n, v.values.size(), "sweep render: the --vary point count");
    return n;
  }
  std::vector<double> values_of(std::size_t k) const {
    std::vector<double> x(vary.size());
    for (std::size_t i = vary.size(); i-- > 0;) {
      x[i] = vary[i].values[k % vary[i].values.size()];
      k /= vary[i].values.size();
    }
    return x;
  }
  std::string describe(std::size_t k) const {
    std::string s;
    const auto x = values_of(k);
    for (std::size_t i = 0; i < vary.size(); ++i)
      s += fmt::format("{}{}={:.4g}", s.empty() ? "" : " ", vary[i].key, x[i]);
    return s.empty() ? std::string("the scene") : s;
  }
  render::Scene scene_of(std::size_t k) const { return scene_from(document_of(k), k); }
  // Equal for two points whose scenes are equal (a varied λ_d is not part of the scene).
  std::string scene_key(std::size_t k) const { return document_of(k).dump(); }

 private:
  nlohmann::json document_of(std::size_t k) const {
    nlohmann::json doc = base;
    const auto x = values_of(k);
    for (std::size_t i = 0; i < vary.size(); ++i) {
      if (vary[i].key == kLambdaDKey) continue;  // not a scene field
      const std::string assignment = fmt::format("{}={}", vary[i].key, x[i]);
      try {
        render::apply_override(doc, assignment);
      } catch (const render::SceneError& e) {
        throw runner::InputError(fmt::format("--vary {}: {}", vary[i].key, e.what()));
      }
    }
    return doc;
  }
  render::Scene scene_from(const nlohmann::json& doc, std::size_t k) const {
    const auto x = values_of(k);
    try {
      return frontend::scene_from_document(doc, job);
    } catch (const runner::InputError& e) {
      std::string at;
      for (std::size_t i = 0; i < vary.size(); ++i)
        at += fmt::format("{}{}={}", at.empty() ? "" : ", ", vary[i].key, x[i]);
      throw runner::InputError(fmt::format("at {}: {}", at.empty() ? "the scene" : at, e.what()));
    }
  }
};

// The last common pass (G-buffer, RSM, VPL sum) and the scene it was made of: points that differ
// only in vsgl.lambda_d have one scene, and share it (with the times it took).
struct CommonPassMemo {
  std::mutex mutex;
  std::string scene_key;
  std::shared_ptr<const render::CommonPass> pass;

  std::shared_ptr<const render::CommonPass> get(const render::Scene& scene, const std::string& key,
                                                const render::RenderOptions& options) {
    {
      const std::lock_guard lock(mutex);
      if (pass && key == scene_key) return pass;
    }
    auto made = std::make_shared<const render::CommonPass>(render::render_common(scene, options));
    const std::lock_guard lock(mutex);
    scene_key = key;
    pass = made;
    return made;
  }
};

// Point k's rows: its G-buffer, RSM and VPL sum once (or the memo's), then each configuration's VSGLs.
std::vector<runner::SweepRow> point_rows(const Grid& g, const std::vector<VsglConfig>& configs,
                                         const render::RenderOptions& options, CommonPassMemo& memo, std::size_t k) {
  const render::Scene scene = g.scene_of(k);
  const auto x = g.values_of(k);
  std::vector<render::VsglOptions> variants;
  for (const auto& c : configs) {
    render::VsglOptions v;
    v.mode = c.mode;
    v.count = c.count;
    v.seed = g.job.seed;
    v.lambda_d = options.vsgl.lambda_d;  // the constant set's λ_d …
    for (std::size_t i = 0; i < g.vary.size(); ++i)
      if (g.vary[i].key == kLambdaDKey) v.lambda_d = x[i];  // … unless varied
    v.kmeans_space = options.vsgl.kmeans_space;
    variants.push_back(v);
  }
  // An arena of its own: the render's parallel loops use every core even when the runner runs
  // points one at a time.
  tbb::task_arena arena;
  const std::vector<render::RenderResult> results = arena.execute([&] {
    const auto common = memo.get(scene, g.scene_key(k), options);
    return render::render_scene_variants(scene, options, *common, variants);
  });
  std::vector<runner::SweepRow> rows;
  for (std::size_t c = 0; c < configs.size(); ++c) {
    const render::RenderResult& r = results[c];
    const auto& st = r.vsgls.stats;
    const double vsgl_seconds = r.seconds.vsgl + r.seconds.shading;
    runner::SweepRow row;
    for (const double v : x) row.push_back(runner::csv_number(v));
    row.insert(row.end(), {configs[c].label(), st.mode, std::to_string(st.requested),
                           std::to_string(st.diffuse_vsgls + st.specular_vsgls), std::to_string(st.specular_vsgls),
                           std::to_string(r.vpl_count), std::to_string(r.pixels_hit),
                           runner::csv_number(r.error_metrics.relative_l2), runner::csv_number(r.error_metrics.smape),
                           runner::csv_number(r.error_metrics.rmse), runner::csv_number(r.error_metrics.max_abs),
                           runner::csv_number(r.seconds.rsm), runner::csv_number(r.seconds.vsgl),
                           runner::csv_number(r.seconds.shading), runner::csv_number(r.seconds.reference),
                           runner::csv_number(vsgl_seconds > 0 ? r.seconds.reference / vsgl_seconds : 0.0)});
    rows.push_back(std::move(row));
  }
  return rows;
}

// The sweep's identity for the runner: its arguments, a complete description of its grid, columns.
runner::SweepDefinition definition(const Options& o, const Grid& g, const std::vector<VsglConfig>& configs,
                                   const std::string& name) {
  runner::SweepDefinition d;
  d.name = name;
  d.args = {"sweep", "render", "--scene", o.job.scene_path};
  for (const auto& v : g.vary) d.args.insert(d.args.end(), {"--vary", v.key + "=" + v.spec});
  for (const auto& c : configs) d.args.insert(d.args.end(), {"--vsgl", c.text});
  for (const auto& a : frontend::render_job_arguments(o.job, false)) d.args.push_back(a);
  d.args.insert(d.args.end(), {"--table", name});
  // The scene's contents (after --set), not only its path: an edited scene file is another grid.
  std::string grid = fmt::format("scene {} (contents fnv1a {}); overrides {{{}}}; ", o.job.scene_path,
                                 runner::fnv1a_hex(g.base.dump()), fmt::join(o.job.overrides, ", "));
  for (const auto& v : g.vary) grid += fmt::format("{} {{{}}} × ", v.key, fmt::join(v.values, ", "));
  std::string labels;
  for (const auto& c : configs) labels += (labels.empty() ? "" : ", ") + c.label();
  grid += fmt::format("VSGLs {{{}}}; diffuse {}; RSM {}; shadow map {}; seed {}", labels, o.job.diffuse, o.job.rsm,
                      o.job.shadow_map, o.job.seed);
  // The constant sets' contents, not only their paths: an edited record is another sweep.
  if (o.job.constants.given()) grid += "; constants fnv1a " + o.job.constants.fingerprint;
  d.grid = grid;
  d.point_count = g.points();
  for (const auto& v : g.vary) d.columns.push_back(v.key);
  d.columns.insert(d.columns.end(), kColumns.begin(), kColumns.end());
  return d;
}

}  // namespace

Result compute(const Options& o, const runner::RunContext& run) {
  if (o.job.scene_path.empty()) throw runner::InputError("sweep render needs --scene SCENE.json");
  Result r;
  r.options = o;
  auto grid = std::make_shared<Grid>();
  grid->vary = parse_varies(o, r.lambda_d_sources);
  grid->job = o.job;
  std::vector<VsglConfig> configs;
  for (const auto& c : o.vsgl.empty() ? std::vector<std::string>{"two"} : o.vsgl)
    configs.push_back(parse_vsgl_config(c));
  render::RenderOptions options = frontend::render_options(o.job);  // validates --rsm, --diffuse, …
  options.direct = false;                                           // the rows measure the indirect layer alone
  grid->base = frontend::load_scene_document(o.job.scene_path, o.job.overrides);
  r.name = checked_table_name(o, grid->vary);
  check_distinct_fields(grid->vary, grid->base);
  const std::size_t points = grid->points();
  if (points > 100000)
    throw runner::InputError(fmt::format("sweep render: {} points is too many (at most 100000)", points));
  for (std::size_t k = 0; k < points; ++k) grid->scene_of(k);  // every point's scene is valid before anything runs
  frontend::check_render_memory(grid->scene_of(0), options);

  runner::SweepDefinition d = definition(o, *grid, configs, r.name);
  d.describe = [grid](std::size_t k) { return grid->describe(k); };
  auto memo = std::make_shared<CommonPassMemo>();
  d.compute = [grid, configs, options, memo](std::size_t k) { return point_rows(*grid, configs, options, *memo, k); };
  // A row read back must be at point k's grid point (its --vary values) and of a configuration run.
  d.check_row = [grid, configs](std::size_t k, const runner::SweepRow& row) -> std::optional<std::string> {
    const auto x = grid->values_of(k);
    if (row.size() != x.size() + kColumns.size())
      return fmt::format("{} fields, expected {}", row.size(), x.size() + kColumns.size());
    for (std::size_t i = 0; i < x.size(); ++i)
      if (row[i] != runner::csv_number(x[i]))
        return fmt::format("{} {} is not the grid point's {} (moved off the grid)", grid->vary[i].key, quote(row[i]),
                           runner::csv_number(x[i]));
    const std::string& label = row[x.size()];
    if (std::none_of(configs.begin(), configs.end(), [&](const VsglConfig& c) { return c.label() == label; }))
      return fmt::format("VSGL configuration {} is not one this sweep runs", quote(label));
    return std::nullopt;
  };
  const runner::SweepRunResult swept = runner::run_sweep_command(d, o.out, o.shard, o.threads, o.fresh, run);
  r.vary = grid->vary;
  std::string command = "sglab";
  for (const auto& a : d.args) command += " " + quote_if_needed(a);
  r.provenance = runner::run_provenance(run, command);
  r.sharded = swept.sharded;
  if (!r.sharded) r.points = runner::read_sweep_points(swept.points_csv);
  return r;
}

}  // namespace sweep_render

void add_sweep_render(CLI::App& sweep, const runner::RunContext& run) {
  auto o = std::make_shared<sweep_render::Options>();
  auto* sub = sweep.add_subcommand(
      "render", "VSGL error against the exact VPL sum, and both times, over scene parameters × VSGL configurations");
  sub->add_option("--scene", o->job.scene_path, "scene JSON (schema: scenes/README.md)");
  sub->add_option("--vary", o->vary,
                  "KEY=a:b:n (linear), KEY=a:b:n:log, or KEY=v1,v2,… (repeatable: Cartesian product)");
  sub->add_option("--vsgl", o->vsgl, "VSGL configuration MODE or MODE:N (fis:64, kmeans:64; repeatable; default two)")
      ->check(frontend::one_of(render::vsgl_mode_names(), "VSGL mode", false, true));
  frontend::add_render_job_options(*sub, o->job, false);
  o->out = run.places.dir(sweep_render::kDir);
  o->tables_dir = run.places.tables;
  sub->add_option("--out", o->out, "directory for NAME_points.csv")->capture_default_str();
  sub->add_option("--table", o->table, "NAME of the table (default vsgl_error_vs_count, or vsgl_error_vs_<keys>)");
  sub->add_option("--tables-dir", o->tables_dir, "directory for NAME.{md,csv} (default: the --out directory)")
      ->capture_default_str();
  sub->add_option("--shard", o->shard, "compute only shard i of N (points k with k % N == i); join with `sglab merge`")
      ->check(frontend::shard_given());
  sub->add_option("--threads", o->threads,
                  "points computed at once (each render uses all cores; 1 keeps timings clean)")
      ->capture_default_str()
      ->check(frontend::unsigned_at_most(runner::kMaxThreads));
  sub->add_flag("--fresh", o->fresh, "ignore earlier output and checkpoints of this sweep (recompute everything)");
  sub->callback([o, run] { sweep_render::write(sweep_render::compute(*o, run)); });
}

std::vector<Step> sweep_render_steps(const runner::Places& p) {
  const std::string scene = "scenes/cornell-glossy.json";
  const std::vector<std::string> coarse = {"--width", "48", "--height", "48", "--rsm", "32"};
  const auto sweep = [&](std::string name, std::string what, std::vector<std::string> configuration,
                         std::vector<std::string> quick) {
    // A 128² RSM (13k VPLs) in every full sweep: the vectorized reference makes it affordable.
    std::vector<std::string> args = {"sweep", "render", "--scene", scene, "--rsm", "128"};
    args.insert(args.end(), configuration.begin(), configuration.end());
    return timed(sglab_step(std::move(name), std::move(what), std::move(args), std::move(quick), true));
  };
  // The VPL sum in float (`--reference-precision float`, which halves the reference's time or
  // better) in every sweep: it leaves every printed digit as in double (checked against double
  // runs); the tables say which. On the roughness × distance sweep's near-mirror floors (α = 0.01)
  // that holds since the float sum forms the NDF's sin²θ_h as |n × h|² (render_kernels_vpl.hpp
  // ggx_layer); with (1 − c)(1 + c) it moved the error metrics by up to 1e-4 relative, a printed
  // digit. The VSGLs' diffuse method stays in double everywhere: in float its far tails (e^{-2λ}
  // below 1e-38) flush to 0, which moves SMAPE where both images are that dark.
  const auto with_float_reference = [](std::vector<std::string> configuration) {
    configuration.insert(configuration.end(), {"--reference-precision", "float"});
    return configuration;
  };
  std::vector<Step> v = {
      sweep("sweep-render-count",
            "VSGL error and time against the VSGL count on cornell-glossy (paper_tables/vsgl_error_vs_count.*)",
            with_float_reference({"--vsgl", "two", "--vsgl", "fis:16", "--vsgl", "fis:64", "--vsgl", "kmeans:16",
                                  "--vsgl", "kmeans:64", "--width", "512", "--height", "512"}),
            {"--width", "64", "--height", "64", "--rsm", "32"}),
      sweep("sweep-render-roughness-distance",
            "VSGL error against floor roughness × light distance on cornell-glossy "
            "(paper_tables/vsgl_error_vs_roughness_distance.*)",
            with_float_reference({"--vary", "floor.roughness=0.01:1:12:log", "--vary", "light.distance=0.4:1.4:5",
                                  "--vsgl", "two", "--vsgl", "fis:64"}),
            coarse),
      sweep("sweep-render-lambda-d",
            "VSGL error against λ_d on cornell-glossy: the papers' 2, the L2 fit and the other objectives' fits "
            "(paper_tables/vsgl_error_vs_lambda_d.*)",
            {"--vary",
             "vsgl.lambda_d=2," + p.dir(fit_all::kDir) + "/lambda-d.json," + p.dir(fit_all::kObjectivesDir) +
                 "/lambda-d-l2-theta.json," + p.dir(fit_all::kObjectivesDir) + "/lambda-d-l2-hemisphere.json",
             "--vsgl", "two", "--width", "256", "--height", "256", "--table", "vsgl_error_vs_lambda_d",
             "--reference-precision", "float"},
            coarse)};
  // Tokuyoshi 2016 §4.1 visibility on cornell-glossy: the same configurations without and
  // with it (each against the reference that makes the same assumption).
  for (const bool vis : {false, true}) {
    const std::string on = vis ? "on" : "off";
    std::vector<std::string> configuration = {"--vsgl",   "two",    "--vsgl",  "fis:16",
                                              "--vsgl",   "fis:64", "--width", "128",
                                              "--height", "128",    "--table", "vsgl_visibility_" + on};
    if (vis) configuration.push_back("--visibility");
    configuration = with_float_reference(configuration);
    v.push_back(sweep("sweep-render-visibility-" + on,
                      std::string("VSGL error on cornell-glossy ") + (vis ? "with" : "without") +
                          " visibility (paper_tables/vsgl_visibility_" + on + ".*)",
                      configuration, coarse));
  }
  return v;
}

Experiment sweep_render_experiment() {
  return {"sweep-render",
          "`sglab sweep render`: VSGL error and time over VSGL counts, roughness × distance, λ_d, visibility",
          add_sweep_render, sweep_render_steps, "sweep"};
}

}  // namespace sglab::experiments
