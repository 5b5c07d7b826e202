// `sglab reproduce`: the main job. Runs the registry of experiment steps in order — each step is
// an ordinary `sglab` command line, run in-process, so that every table it writes is headed by the
// very command a user can run alone — and records a marker per finished step so that an
// interrupted run resumes where it stopped (a step's outputs are written atomically, so a step
// without its marker is simply redone). The marker records the fingerprint of every file the step
// names and of every file it wrote under OUT/ and paper_tables/, so a changed input or a deleted
// or altered output also reruns it.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "atomic_file.hpp"
#include "commands.hpp"
#include "sweep.hpp"

namespace sglab::cli {
namespace {

struct Step {
  std::string name;
  std::string what;
  std::vector<std::string> args;        // the sglab command line (without "sglab")
  std::vector<std::string> quick_args;  // appended with --quick
  bool python = false;                  // args are a python3 script and its arguments instead
};

// Where a run writes: a full run writes its tables and the figures README.md shows into
// paper_tables/ (the others into OUT/figures); a --quick run writes everything under
// results/quick/ (tables in results/quick/tables/) and never touches paper_tables/.
struct Places {
  std::string out;     // per-step outputs: CSVs, renders, fit records, other figures
  std::string tables;  // the tables, and the key figures in TABLES/figures
  std::string key_figures() const { return tables + "/figures"; }
};

// The one-VSGL renderer against the exact VPL sum on the spotlight-near-a-wall scene, once per
// diffuse method, and one SMAPE map per method (near_wall_vsgl_vs_vpl_sum.png). Not the poster's
// figure: that is `near-wall` below (each method against the exact integral).
const std::vector<std::string> kNearWallMethods = {"sg-cosine", "punctual-approx", "hill-fitted", "meder",
                                                   "tokuyoshi2022", "tokuyoshi2024", "sglab"};

std::vector<Step> near_wall_steps(const Places& places) {
  const std::string& out = places.out;
  const std::string key_figures = places.key_figures();
  std::vector<Step> v;
  std::vector<std::string> plot = {"plots/near_wall_vsgl_vs_vpl_sum.py", key_figures};
  for (const auto& m : kNearWallMethods) {
    const std::string base = out + "/renders/near-wall-" + m;
    v.push_back({"render-near-wall-" + m, "near-wall scene with diffuse method " + m + " (one VSGL against the VPL sum)",
                 {"render", "scenes/sg-light-near-wall.json", "--diffuse", m, "--out", base + ".exr", "--stats", base + ".json",
                  "--dump-csv", base + ".csv", "--width", "160", "--height", "120"},
                 {"--width", "64", "--height", "48"}});
    plot.push_back(m + "=" + base + ".csv");
  }
  v.push_back({"plot-near-wall-vsgl-vs-vpl-sum", "SMAPE map of the one-VSGL render against the VPL sum per diffuse method", plot, {}, true});
  // The poster's figure (Tokuyoshi 2022, Fig. b-d): every clamped-cosine method of the registry
  // against the exact integral per pixel, and the sweep over the light's sharpness and distance.
  v.push_back({"near-wall", "sharp SG light near a wall: each diffuse method against the exact integral (paper_tables/near_wall_smape*)",
               {"near-wall", "--scene", "scenes/sg-light-near-wall-poster.json", "--dump", out + "/near_wall/pixels.csv",
                "--sweep-sharpness", "10,100,1000", "--sweep-distance", "0.05,0.1,0.2,0.4"},
               {"--width", "64", "--height", "48", "--sweep-width", "32", "--sweep-height", "24"}});
  v.push_back({"poster-plots", "Tokuyoshi 2022 poster's plots: cosine-term error vs float bound, hemispherical RMSE (paper_tables/*.csv)",
               {"poster-plots"}, {}});
  v.push_back({"plot-poster-plots", "figures of the poster's two plots", {"plots/poster_plots.py", places.tables, key_figures}, {}, true});
  v.push_back({"plot-near-wall-smape", "SMAPE map of each diffuse method against the exact integral (the poster's figure)",
               {"plots/near_wall_smape.py", out + "/near_wall/pixels.csv", key_figures, places.tables + "/near_wall_smape.csv"}, {}, true});
  return v;
}

// SG environment maps: the three generated environments, the fits and renders against N
// (paper_tables/envmap_lobes.*), and the figures.
std::vector<Step> envmap_steps(const Places& places) {
  const std::string& out = places.out;
  std::vector<Step> v;
  std::vector<std::string> lobes = {"envmap", "lobes", "--out", out + "/envmap"};
  for (const char* kind : {"sky", "studio", "mixture"}) {
    const std::string path = out + "/envmap/" + kind + ".exr";
    v.push_back({std::string("envmap-make-") + kind, std::string("generated environment: ") + kind + " (512×256 EXR)",
                 {"envmap", "make", kind, "--out", path}, {}});
    lobes.insert(lobes.end(), {"--env", std::string(kind) + "=" + path});
  }
  v.push_back({"envmap-lobes", "SG mixture fits and shading error against N (paper_tables/envmap_lobes.*)", lobes, {"--quick"}});
  v.push_back({"plot-envmap", "environment error against N, and each map beside its reconstructions",
               {"plots/envmap_lobes.py", places.tables + "/envmap_lobes.csv", out + "/envmap/envmap_images.csv", places.key_figures()}, {}, true});
  return v;
}

std::vector<Step> steps(const Places& places) {
  const std::string& out = places.out;
  const std::string kKeyFigures = places.key_figures();
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
      {"sweep-specular-gaussian",
       "specular methods of the Gaussian-angle NDF BRDF against that BRDF's own reference (paper_tables/specular_gaussian_vs_roughness.*)",
       {"sweep", "specular", "--brdf", "gaussian", "--out", out + "/specular"}, {"--quick"}},
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
      {"plot-own-method", "sglab's own method against tokuyoshi2024: error maps and the frontier of the forms tried (paper_tables/own_method.md)",
       {"plots/own_method.py", out + "/error_map/error_map.csv", "plots/own_method_forms.csv", kKeyFigures}, {}, true},
      // The VSGL renderer: the three scenes, each with its stats JSON, then the sweeps.
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
      // Lobe-aware filtering: both weightings on cornell-glossy, then the roughness sweep.
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
  all.push_back({"vsgl-fis-bias", "bias of the FIS VSGLs' sums against the exact sums over 64 seeds (paper_tables/vsgl_fis_bias.*)",
                 {"vsgl-fis-bias"}, {"--seeds", "8", "--rsm", "16"}});
  // Two VSGLs as in Tokuyoshi 2015 (own Gaussian per component, λ_d = 2): the receiver's cosine
  // pulled out against the poster's SG cosine with A(λ_d) ≈ π (after its Fig. 1).
  for (const auto& [name, extra] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"punctual", {"--diffuse", "punctual"}}, {"sg-cosine", {"--diffuse", "sg-cosine", "--sg-cosine-a-pi"}}}) {
    const std::string base = out + "/renders/two-vsgls-" + name;
    std::vector<std::string> args = {"render", "scenes/diffuse-only.json", "--vsgl", "two", "--out", base + ".exr", "--stats",
                                     base + ".json", "--dump-csv", base + ".csv", "--width", "192", "--height", "192"};
    args.insert(args.end(), extra.begin(), extra.end());
    all.push_back({"render-two-vsgls-" + name, "diffuse-only scene, two VSGLs, diffuse " + name, args, {"--width", "64", "--height", "64"}});
  }
  all.push_back({"plot-two-vsgls-cosine", "two VSGLs: cosine pulled out vs SG cosine (after Tokuyoshi 2015 Fig. 1)",
                 {"plots/two_vsgls_cosine.py", kKeyFigures, out + "/renders/two-vsgls-punctual.csv", out + "/renders/two-vsgls-sg-cosine.csv"},
                 {}, true});
  // Tokuyoshi 2016 §4.1 visibility on cornell-glossy: the same configurations without and with it
  // (each against the reference that makes the same assumption).
  for (const bool vis : {false, true}) {
    std::vector<std::string> args = {"sweep", "render", "--scene", "scenes/cornell-glossy.json", "--vsgl", "two", "--vsgl", "fis:16",
                                     "--vsgl", "fis:64", "--width", "128", "--height", "128", "--out", out + "/render_sweep",
                                     "--table", vis ? "vsgl_visibility_on" : "vsgl_visibility_off"};
    if (vis) args.push_back("--visibility");
    all.push_back({vis ? "sweep-render-visibility-on" : "sweep-render-visibility-off",
                   std::string("VSGL error on cornell-glossy ") + (vis ? "with" : "without") +
                       " visibility (paper_tables/vsgl_visibility_" + (vis ? "on" : "off") + ".*)",
                   args, {"--width", "48", "--height", "48", "--rsm", "32"}});
  }
  const auto near_wall = near_wall_steps(places);
  all.insert(all.end(), near_wall.begin(), near_wall.end());
  const auto envmap = envmap_steps(places);
  all.insert(all.end(), envmap.begin(), envmap.end());
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

// The option through which a step's sglab command takes the directory of its tables; empty for a
// command that writes no table (every table-writing command gets it explicitly, so that no step
// relies on a default that points into paper_tables/).
std::string tables_option(const Step& s) {
  if (s.python || s.args.empty()) return "";
  const std::string& command = s.args[0];
  if (command == "error-vs-time" || command == "stability") return "--tables";
  if (command == "sweep" || command == "filter-sweep" || command == "near-wall" || command == "poster-plots" ||
      command == "vsgl-fis-bias" ||
      (command == "envmap" && s.args.size() > 1 && s.args[1] == "lobes") || (command == "fit" && s.args.size() > 1 && s.args[1] == "all"))
    return "--tables-dir";
  return "";
}

std::string file_fnv1a(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return fnv1a_hex(bytes.str());
}

// One line "file PATH FNV1A" per argument that names a regular file now (a scene, a script, an
// output; "NAME=PATH" arguments too), for a step's marker.
std::string files_state(const std::vector<std::string>& args) {
  namespace fs = std::filesystem;
  std::string state;
  for (const auto& a : args) {
    const auto eq = a.find('=');
    for (const std::string& path : {a, eq == std::string::npos ? std::string() : a.substr(eq + 1)}) {
      std::error_code ec;
      if (path.empty() || !fs::is_regular_file(path, ec)) continue;
      state += "file " + path + " " + file_fnv1a(path) + "\n";
    }
  }
  return state;
}

// Size and modification time of every regular file under `roots` (the files a step may write:
// OUT/ and paper_tables/), to find what a step wrote.
using Snapshot = std::map<std::string, std::pair<std::uintmax_t, std::filesystem::file_time_type>>;
Snapshot snapshot(const std::vector<std::string>& roots) {
  namespace fs = std::filesystem;
  Snapshot out;
  for (const auto& root : roots) {
    std::error_code ec;
    if (!fs::is_directory(root, ec)) continue;
    for (auto it = fs::recursive_directory_iterator(root, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
      if (it->is_regular_file(ec) && it->path().string().find("/.steps/") == std::string::npos)
        out[it->path().string()] = {it->file_size(ec), it->last_write_time(ec)};
  }
  return out;
}

// "output PATH FNV1A" for every file written or changed between two snapshots.
std::string outputs_state(const Snapshot& before, const Snapshot& after) {
  std::string state;
  for (const auto& [path, stamp] : after) {
    const auto it = before.find(path);
    if (it == before.end() || it->second != stamp) state += "output " + path + " " + file_fnv1a(path) + "\n";
  }
  return state;
}

// Whether every "output PATH FNV1A" line of a marker still holds.
bool outputs_intact(const std::string& marker) {
  std::istringstream in(marker);
  for (std::string l; std::getline(in, l);) {
    if (l.rfind("output ", 0) != 0) continue;
    const auto space = l.rfind(' ');
    const std::string path = l.substr(7, space - 7);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec) || file_fnv1a(path) != l.substr(space + 1)) return false;
  }
  return true;
}

struct Options {
  std::string out;         // default: results, or results/quick with --quick
  std::string tables_dir;  // default: paper_tables, or OUT/tables with --quick
  bool quick = false;
  bool force = false;
  bool list = false;
  std::vector<std::string> only;
  std::vector<std::string> constants;  // --constants: appended to every sglab step but the fits
};

Places places(const Options& o) {
  Places p;
  p.out = !o.out.empty() ? o.out : o.quick ? "results/quick" : "results";
  p.tables = !o.tables_dir.empty() ? o.tables_dir : o.quick ? p.out + "/tables" : "paper_tables";
  return p;
}

// The command line of step `s` in this mode (without "sglab" / "python3").
std::vector<std::string> step_args(const Step& s, const Options& o, const Places& p) {
  std::vector<std::string> args = s.args;
  if (o.quick) args.insert(args.end(), s.quick_args.begin(), s.quick_args.end());
  if (const std::string option = tables_option(s); !option.empty()) args.insert(args.end(), {option, p.tables});
  // --constants: to every step whose command takes a constant set.
  static const std::vector<std::string> kTakeConstants = {"error-vs-time", "stability", "error-map", "render",
                                                          "sweep", "filter", "filter-sweep"};
  if (!s.python && std::find(kTakeConstants.begin(), kTakeConstants.end(), args.front()) != kTakeConstants.end())
    for (const auto& c : o.constants) args.insert(args.end(), {"--constants", c});
  return args;
}

void run(const Options& o) {
  namespace fs = std::filesystem;
  const Places p = places(o);
  const auto all = steps(p);
  if (o.list) {  // the steps of this mode and their command lines; nothing is run or written
    for (const auto& s : all) std::printf("%s\t%s%s\n", s.name.c_str(), s.python ? "python3 " : "sglab ", join(step_args(s, o, p)).c_str());
    return;
  }
  const fs::path markers = fs::path(p.out) / ".steps";
  fs::create_directories(markers);
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
    const std::vector<std::string> args = step_args(s, o, p);
    const std::string line = (s.python ? "python3 " : "sglab ") + join(args);
    const fs::path marker = markers / (s.name + ".done");
    if (!o.force && fs::exists(marker)) {
      std::ifstream in(marker);
      std::stringstream text;
      text << in.rdbuf();
      // Done only if the command, and every file it named (inputs and outputs), are as the
      // marker recorded them: an edited scene or a deleted output reruns the step.
      std::string recorded;  // the marker without its "output" lines
      std::istringstream lines(text.str());
      for (std::string l; std::getline(lines, l);)
        if (l.rfind("output ", 0) != 0) recorded += l + "\n";
      if (recorded == line + "\n" + files_state(args) && outputs_intact(text.str())) {
        std::fprintf(stderr, "reproduce [%zu/%zu] %s: done earlier, skipped (%s)\n", k + 1, all.size(), s.name.c_str(), line.c_str());
        ++skipped;
        continue;
      }
    }
    std::fprintf(stderr, "reproduce [%zu/%zu] %s: %s\n  $ %s\n", k + 1, all.size(), s.name.c_str(), s.what.c_str(), line.c_str());
    const auto t0 = std::chrono::steady_clock::now();
    const Snapshot before = snapshot({p.out, p.tables});
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
    m.write(line + "\n" + files_state(args) + outputs_state(before, snapshot({p.out, p.tables})));
    m.commit();
    ++done;
    std::fprintf(stderr, "reproduce [%zu/%zu] %s: finished in %.1f s\n", k + 1, all.size(), s.name.c_str(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::printf("reproduce: %d steps run, %d already done, %.1f s; outputs in %s/, tables in %s/\n", done, skipped,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count(), p.out.c_str(), p.tables.c_str());
}

}  // namespace

void add_reproduce_command(CLI::App& app) {
  auto opts = std::make_shared<Options>();
  auto* sub = app.add_subcommand("reproduce", "Regenerate every table and figure (resumes: finished steps are skipped)");
  sub->add_option("--out", opts->out, "directory for results and figures (default: results, or results/quick with --quick)");
  sub->add_option("--tables-dir", opts->tables_dir,
                  "directory for the tables and key figures (default: paper_tables, or OUT/tables with --quick)");
  sub->add_flag("--quick", opts->quick, "coarser grids; writes under results/quick/, never into paper_tables/");
  sub->add_flag("--list", opts->list, "print each step and its command line in this mode, run nothing");
  sub->add_flag("--force", opts->force, "redo finished steps");
  sub->add_option("--only", opts->only, "run only these steps");
  sub->add_option("--constants", opts->constants,
                  "constant set for every step but the fits (a fit record, a directory of them, or 'published'; "
                  "repeatable, later sets override earlier ones)")
      ->allow_extra_args(false);
  sub->callback([opts] { run(*opts); });
}

}  // namespace sglab::cli
