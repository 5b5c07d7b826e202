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

std::vector<Step> steps(const std::string& out) {
  return {
      {"fit-all", "re-derive every published constant (paper_tables/constants.*)",
       {"fit", "all", "--json-dir", out + "/fits"}, {}},
      {"error-vs-time", "diffuse methods: error, rounding error and ns/eval (paper_tables/error_vs_time.*)",
       {"error-vs-time", "--out", out + "/error_vs_time"}, {"--quick"}},
      {"plot-error-vs-time", "Pareto figure of error against time",
       {"plots/error_vs_time.py", out + "/error_vs_time/error_vs_time.csv", out + "/figures"}, {}, true},
  };
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
  sub->callback([opts] { run(*opts); });
}

}  // namespace sglab::cli
