// `sglab reproduce`: the main job. Runs the registry of experiment steps in order — each step is
// an ordinary `sglab` command line, run in-process, so that every table it writes is headed by the
// very command a user can run alone — and records a marker per finished step so that an
// interrupted run resumes where it stopped (a step's outputs are written atomically, so a step
// without its marker is simply redone).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "atomic_file.hpp"
#include "commands.hpp"

namespace sglab::cli {
namespace {

struct Step {
  std::string name;
  std::string what;
  std::vector<std::string> args;        // the sglab command line (without "sglab")
  std::vector<std::string> quick_args;  // appended with --quick
  bool python = false;                  // args are a python3 script and its arguments instead
};

// The figures README.md shows are committed beside the tables; the others stay in OUT/figures.
const std::string kKeyFigures = "paper_tables/figures";

// The poster's figure on the renderer (issue 6, item 4): the near-wall scene once per diffuse
// method, and one SMAPE map per method.
const std::vector<std::string> kNearWallMethods = {"sg-cosine", "punctual-approx", "hill-fitted", "meder",
                                                   "tokuyoshi2022", "tokuyoshi2024"};

std::vector<Step> near_wall_steps(const std::string& out) {
  std::vector<Step> v;
  std::vector<std::string> plot = {"plots/near_wall_smape.py", kKeyFigures};
  for (const auto& m : kNearWallMethods) {
    const std::string base = out + "/renders/near-wall-" + m;
    v.push_back({"render-near-wall-" + m, "near-wall scene with diffuse method " + m + " (for the SMAPE map per method)",
                 {"render", "scenes/sg-light-near-wall.json", "--diffuse", m, "--out", base + ".exr", "--stats", base + ".json",
                  "--dump-csv", base + ".csv", "--width", "160", "--height", "120"},
                 {"--width", "64", "--height", "48"}});
    plot.push_back(m + "=" + base + ".csv");
  }
  v.push_back({"plot-near-wall-smape", "SMAPE map of each diffuse method on the near-wall scene (the poster's figure)", plot, {}, true});
  return v;
}

std::vector<Step> steps(const std::string& out) {
  std::vector<Step> all = {
      {"fit-all", "re-derive every published constant (paper_tables/constants.*)",
       {"fit", "all", "--json-dir", out + "/fits"}, {}},
      // The other objectives of lambda-d, for the λ_d render sweep below (which reads them by path).
      {"fit-lambda-d-theta", "lambda-d under the l2-theta objective (a constant set for the λ_d render sweep)",
       {"fit", "lambda-d", "--objective", "l2-theta", "--json", out + "/fits-objectives/lambda-d-l2-theta.json"}, {}},
      {"fit-lambda-d-hemisphere", "lambda-d under the l2-hemisphere objective (a constant set for the λ_d render sweep)",
       {"fit", "lambda-d", "--objective", "l2-hemisphere", "--json", out + "/fits-objectives/lambda-d-l2-hemisphere.json"}, {}},
      {"error-vs-time", "diffuse methods, published and refit (the fit-all records) side by side (paper_tables/error_vs_time.*)",
       {"error-vs-time", "--out", out + "/error_vs_time", "--constants", out + "/fits"}, {"--quick"}},
      {"plot-error-vs-time", "Pareto figure of error against time",
       {"plots/error_vs_time.py", out + "/error_vs_time/error_vs_time.csv", kKeyFigures}, {}, true},
      {"sweep-specular", "specular methods against the GGX reference over roughness (paper_tables/specular_vs_roughness.*)",
       {"sweep", "specular", "--out", out + "/specular"}, {"--quick"}},
      {"plot-specular", "specular error against roughness, one line per method",
       {"plots/specular_vs_roughness.py", out + "/specular/specular_summary.csv", kKeyFigures}, {}, true},
      {"stability", "stability atlas: NaN/Inf/negative/>1 % counts and rounding error of every method (paper_tables/stability.*)",
       {"stability", "--out", out + "/stability"}, {"--quick"}},
      {"plot-stability", "stability heat map per method, float and double side by side",
       {"plots/stability_heatmap.py", out + "/stability/stability_cells.csv", out + "/figures/stability"}, {"--quick"}, true},
      {"error-map", "signed error of each diffuse method over (λ, c) against the reference",
       {"error-map", "--out", out + "/error_map"}, {"--quick"}},
      {"plot-error-maps", "error maps of the diffuse methods, one panel per method",
       {"plots/error_maps.py", out + "/error_map/error_map.csv", out + "/figures/error_maps"}, {"--quick"}, true},
      // The VSGL renderer (issue 5): the three scenes, each with its stats JSON, then the sweeps.
      {"render-cornell-glossy", "VSGL renderer: glossy Cornell box, 256×256, two VSGLs vs the exact VPL sum",
       {"render", "scenes/cornell-glossy.json", "--out", out + "/renders/cornell-glossy.exr", "--stats",
        out + "/renders/cornell-glossy.json", "--dump-csv", out + "/renders/cornell-glossy.csv", "--width", "256", "--height", "256"},
       {"--width", "64", "--height", "64"}},
      {"render-diffuse-only", "VSGL renderer: Lambert-only Cornell box (no specular VSGL, no ASG)",
       {"render", "scenes/diffuse-only.json", "--out", out + "/renders/diffuse-only.exr", "--stats",
        out + "/renders/diffuse-only.json", "--dump-csv", out + "/renders/diffuse-only.csv", "--width", "256", "--height", "256"},
       {"--width", "64", "--height", "64"}},
      {"render-sg-light-near-wall", "VSGL renderer: a spotlight close to a wall (a sharp VSGL)",
       {"render", "scenes/sg-light-near-wall.json", "--out", out + "/renders/sg-light-near-wall.exr", "--stats",
        out + "/renders/sg-light-near-wall.json", "--dump-csv", out + "/renders/sg-light-near-wall.csv", "--width", "256", "--height", "192"},
       {"--width", "64", "--height", "48"}},
      {"plot-renders", "figures of the three renders: VSGL and reference, indirect alone, signed error",
       {"plots/render_images.py", kKeyFigures, out + "/renders/cornell-glossy.csv",
        out + "/renders/diffuse-only.csv", out + "/renders/sg-light-near-wall.csv"},
       {}, true},
      {"sweep-render-count", "VSGL error and time against the VSGL count on cornell-glossy (paper_tables/vsgl_error_vs_count.*)",
       {"sweep", "render", "--scene", "scenes/cornell-glossy.json", "--vsgl", "two", "--vsgl", "fis:16", "--vsgl", "fis:64",
        "--vsgl", "kmeans:16", "--vsgl", "kmeans:64", "--width", "512", "--height", "512", "--out", out + "/render_sweep"},
       {"--width", "64", "--height", "64"}},
      {"sweep-render-roughness-distance",
       "VSGL error against floor roughness × light distance on cornell-glossy (paper_tables/vsgl_error_vs_roughness_distance.*)",
       {"sweep", "render", "--scene", "scenes/cornell-glossy.json", "--vary", "floor.roughness=0.01:1:8:log", "--vary",
        "light.distance=0.4:1.4:3", "--vsgl", "two", "--vsgl", "fis:64", "--out", out + "/render_sweep"},
       {"--width", "48", "--height", "48", "--rsm", "32"}},
      {"sweep-render-lambda-d",
       "VSGL error against λ_d on cornell-glossy: the papers' 2, the L2 fit and the other objectives' fits "
       "(paper_tables/vsgl_error_vs_lambda_d.*)",
       {"sweep", "render", "--scene", "scenes/cornell-glossy.json", "--vary",
        "vsgl.lambda_d=2," + out + "/fits/lambda-d.json," + out + "/fits-objectives/lambda-d-l2-theta.json," + out +
            "/fits-objectives/lambda-d-l2-hemisphere.json",
        "--vsgl", "two", "--width", "256", "--height", "256", "--out", out + "/render_sweep", "--table", "vsgl_error_vs_lambda_d"},
       {"--width", "48", "--height", "48", "--rsm", "32"}},
      // Lobe-aware filtering (issue 7): both weightings on cornell-glossy, then the roughness sweep.
      {"filter-cornell-glossy-normal", "upsampling 1/4-resolution indirect light with normal/depth weights (EXR + stats)",
       {"filter", "scenes/cornell-glossy.json", "--weights", "normal", "--out", out + "/filtering/cornell-glossy-normal.exr",
        "--stats", out + "/filtering/cornell-glossy-normal.json"},
       {"--width", "64", "--height", "64"}},
      {"filter-cornell-glossy-lobe", "upsampling 1/4-resolution indirect light with lobe-aware weights (EXR + stats)",
       {"filter", "scenes/cornell-glossy.json", "--weights", "lobe", "--out", out + "/filtering/cornell-glossy-lobe.exr",
        "--stats", out + "/filtering/cornell-glossy-lobe.json"},
       {"--width", "64", "--height", "64"}},
      {"filter-sweep", "upsampling error per weighting over the floor's roughness on cornell-glossy (paper_tables/filtering.*)",
       {"filter-sweep", "--scene", "scenes/cornell-glossy.json", "--out", out + "/filtering"},
       {"--width", "64", "--height", "64"}},
  };
  const auto near_wall = near_wall_steps(out);
  all.insert(all.end(), near_wall.begin(), near_wall.end());
  return all;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& a : v) s += (s.empty() ? "" : " ") + a;
  return s;
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

struct Options {
  std::string out = "results";
  bool quick = false;
  bool force = false;
  std::vector<std::string> only;
  std::vector<std::string> constants;  // --constants: appended to every sglab step but the fits
};

void run(const Options& o) {
  namespace fs = std::filesystem;
  const fs::path markers = fs::path(o.out) / ".steps";
  fs::create_directories(markers);
  const auto all = steps(o.out);
  for (const auto& name : o.only) {
    bool known = false;
    for (const auto& s : all) known = known || s.name == name;
    if (!known) throw UsageError("reproduce: unknown step '" + name + "'");
  }
  const auto t_start = std::chrono::steady_clock::now();
  int done = 0, skipped = 0;
  for (std::size_t k = 0; k < all.size(); ++k) {
    const Step& s = all[k];
    if (!o.only.empty() && std::find(o.only.begin(), o.only.end(), s.name) == o.only.end()) continue;
    std::vector<std::string> args = s.args;
    if (o.quick) args.insert(args.end(), s.quick_args.begin(), s.quick_args.end());
    if (!s.python && args.front() != "fit")
      for (const auto& c : o.constants) args.insert(args.end(), {"--constants", c});
    const std::string line = (s.python ? "python3 " : "sglab ") + join(args);
    const fs::path marker = markers / (s.name + ".done");
    if (!o.force && fs::exists(marker)) {
      std::ifstream in(marker);
      std::stringstream text;
      text << in.rdbuf();
      if (text.str() == line + "\n") {
        std::fprintf(stderr, "reproduce [%zu/%zu] %s: done earlier, skipped (%s)\n", k + 1, all.size(), s.name.c_str(), line.c_str());
        ++skipped;
        continue;
      }
    }
    std::fprintf(stderr, "reproduce [%zu/%zu] %s: %s\n  $ %s\n", k + 1, all.size(), s.name.c_str(), s.what.c_str(), line.c_str());
    const auto t0 = std::chrono::steady_clock::now();
    int status;
    if (s.python) {
      // Debian's interpreter, which has python3-matplotlib; a python3 earlier on PATH (pyenv,
      // a venv) may not.
      std::string cmd = std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
      for (const auto& a : args) cmd += " " + shell_quote(a);
      status = std::system(cmd.c_str());
    } else {
      status = run_sglab(args);
    }
    if (status != 0) throw std::runtime_error("reproduce: step '" + s.name + "' failed (" + line + ")");
    AtomicFile m(marker);
    m.write(line + "\n");
    m.commit();
    ++done;
    std::fprintf(stderr, "reproduce [%zu/%zu] %s: finished in %.1f s\n", k + 1, all.size(), s.name.c_str(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::printf("reproduce: %d steps run, %d already done, %.1f s; outputs in %s/ and paper_tables/\n", done, skipped,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count(), o.out.c_str());
}

}  // namespace

void add_reproduce_command(CLI::App& app) {
  auto opts = std::make_shared<Options>();
  auto* sub = app.add_subcommand("reproduce", "Regenerate every table and figure (resumes: finished steps are skipped)");
  sub->add_option("--out", opts->out, "directory for results and figures")->capture_default_str();
  sub->add_flag("--quick", opts->quick, "coarser grids");
  sub->add_flag("--force", opts->force, "redo finished steps");
  sub->add_option("--only", opts->only, "run only these steps");
  sub->add_option("--constants", opts->constants,
                  "constant set for every step but the fits (a fit record, a directory of them, or 'published'; "
                  "repeatable, later sets override earlier ones)")
      ->allow_extra_args(false);
  sub->callback([opts] { run(*opts); });
}

}  // namespace sglab::cli
