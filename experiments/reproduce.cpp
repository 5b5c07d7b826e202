#include "reproduce.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <exception>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <sys/resource.h>

#include "atomic_file.hpp"
#include "constant_sets.hpp"
#include "environment_render.hpp"
#include "input_error.hpp"
#include "names.hpp"
#include "plot_queue.hpp"
#include "sweep.hpp"
#include "table.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::experiments {
namespace {

using runner::fnv1a_hex;

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& a : v) s += (s.empty() ? "" : " ") + a;
  return s;
}

std::string file_fnv1a(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return fnv1a_hex(bytes.str());
}

// One line "file PATH FNV1A" per argument that names a regular file now (a scene, a script, an
// output; "NAME=PATH" arguments too) and per file of Step::reads that exists, for a step's marker.
// A constant set (--constants PATH, a directory too) by the contents of its records, and a scene by
// the files its environment reads: an edited record, map or mixture reruns the step.
std::string files_state(const std::vector<std::string>& command, const std::vector<std::string>& reads) {
  namespace fs = std::filesystem;
  std::vector<std::string> args = command;
  args.insert(args.end(), reads.begin(), reads.end());
  std::string state;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (i > 0 && args[i - 1] == "--constants") {
      std::string print;
      try {
        print = frontend::constants_fingerprint({a});
      } catch (const std::exception&) {
        print = "unreadable";  // the step itself reports it
      }
      state += "constants " + a + " " + print + "\n";
      continue;
    }
    const auto eq = a.find('=');
    for (const std::string& path : {a, eq == std::string::npos ? std::string() : a.substr(eq + 1)}) {
      std::error_code ec;
      if (path.empty() || !fs::is_regular_file(path, ec)) continue;
      state += "file " + path + " " + file_fnv1a(path) + "\n";
      if (fs::path(path).extension() == ".json")
        for (const auto& f : frontend::environment_files(path))
          state += "environment " + f + " " + (fs::is_regular_file(f, ec) ? file_fnv1a(f) : std::string("missing")) +
                   "\n";
    }
  }
  return state;
}

// Size and modification time of every regular file under `roots` (the files a step may write:
// OUT/ and paper_tables/), to find what a step wrote.
using Snapshot = std::map<std::string, std::pair<std::uintmax_t, std::filesystem::file_time_type>>;
// Files that are, or lie below, a path in `except` are left out, and so are the markers.
Snapshot snapshot(const std::vector<std::string>& roots, const std::vector<std::string>& except = {}) {
  namespace fs = std::filesystem;
  const auto excluded = [&](const std::string& path) {
    for (const auto& e : except)
      if (path == e || path.rfind(e + "/", 0) == 0) return true;
    return path.find("/.steps/") != std::string::npos;
  };
  Snapshot out;
  for (const auto& root : roots) {
    std::error_code ec;
    if (!fs::is_directory(root, ec)) continue;
    for (auto it = fs::recursive_directory_iterator(root, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec))
      if (it->is_regular_file(ec) && !excluded(it->path().string()))
        out[it->path().string()] = {it->file_size(ec), it->last_write_time(ec)};
  }
  return out;
}

// "output PATH FNV1A" for every file written or changed between two snapshots; with `only`, of
// those whose absolute path is in it (a plot's: the files it says it wrote, since the plots
// running beside it write into the same directories meanwhile).
std::string outputs_state(const Snapshot& before, const Snapshot& after, const std::set<std::string>* only = nullptr) {
  std::string state;
  for (const auto& [path, stamp] : after) {
    const auto it = before.find(path);
    if (it != before.end() && it->second == stamp) continue;
    if (only && !only->count(std::filesystem::absolute(path).lexically_normal().string())) continue;
    state += "output " + path + " " + file_fnv1a(path) + "\n";
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

// CPU seconds (user + system) used so far by this process's threads (the sglab steps), or with
// RUSAGE_CHILDREN by its finished children: the programs sglab steps run (shader-export's
// compilers) and, once stopped, the plot interpreter (each plot also timed by PlotServer::run).
double seconds_of(const rusage& u) {
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}
double cpu_seconds(int who = RUSAGE_SELF) {
  rusage u{};
  getrusage(who, &u);
  return seconds_of(u);
}

// Whether the step's marker says it is done: the command, and every file it named (inputs and
// outputs), are as the marker recorded them (an edited scene or a deleted output reruns it).
bool done_earlier(const std::filesystem::path& marker, const std::string& line, const std::vector<std::string>& args,
                  const std::vector<std::string>& reads) {
  if (!std::filesystem::exists(marker)) return false;
  std::ifstream in(marker);
  std::stringstream text;
  text << in.rdbuf();
  std::string recorded;  // the marker without its "output" lines
  std::istringstream lines(text.str());
  for (std::string l; std::getline(lines, l);)
    if (l.rfind("output ", 0) != 0) recorded += l + "\n";
  return recorded == line + "\n" + files_state(args, reads) && outputs_intact(text.str());
}

// OUT/reproduce_times.csv: one row per step of this run (wall and CPU seconds; a step done earlier
// has status "skipped"), rewritten after every step so that an interrupted run keeps its times.
struct StepTimes {
  std::string rows;
  void add(const std::string& step, const char* status, double wall, double cpu) {
    rows += step + "," + status + "," + (wall >= 0 ? fmt_seconds(wall) + "," + fmt_seconds(cpu) : ",") + "\n";
  }
  static std::string fmt_seconds(double s) {
    char b[32];
    std::snprintf(b, sizeof b, "%.2f", s);
    return b;
  }
  void write(const std::filesystem::path& path, const std::string& command, bool quick) const {
    runner::AtomicFile f(path);
    f.write(runner::csv_header(runner::Provenance{command, quick}) + "step,status,wall_seconds,cpu_seconds\n" + rows);
    f.commit();
  }
};

}  // namespace

runner::Places reproduce_places(const ReproduceOptions& o) {
  runner::Places p;  // a plain run's: results/
  p.out = !o.out.empty() ? o.out : o.quick ? p.dir("quick") : p.out;
  p.tables = !o.tables_dir.empty() ? o.tables_dir : o.quick ? p.dir("tables") : std::string(runner::kPaperTables);
  return p;
}

std::vector<std::string> step_args(const Step& s, const ReproduceOptions& o) {
  std::vector<std::string> args = s.args;
  if (o.quick) args.insert(args.end(), s.quick_args.begin(), s.quick_args.end());
  if (s.takes_constants)
    for (const auto& c : o.constants) args.insert(args.end(), {"--constants", c});
  return args;
}

std::string step_line(const Step& s, const ReproduceOptions& o, const runner::Places& p) {
  if (s.python) return "python3 " + join(step_args(s, o));
  return runner::command_line(p, step_args(s, o));
}

namespace {

// One run of the steps: the markers, the step times, and the plots running beside.
class StepRun {
 public:
  StepRun(const ReproduceOptions& o, const SglabRunner& run_sglab, const runner::Places& p,
          const std::vector<Step>& all)
      : o_(o),
        run_sglab_(run_sglab),
        p_(p),
        all_(all),
        markers_(std::filesystem::path(p.out) / ".steps"),
        times_csv_(std::filesystem::path(p.out) / "reproduce_times.csv"),
        figures_{p.key_figures(), p.dir(kFiguresDir)} {
    std::filesystem::create_directories(markers_);
    command_ = "sglab reproduce";
    if (o.quick) command_ += " --quick";
    if (o.force) command_ += " --force";
    for (const auto& name : o.only) command_ += " --only " + name;
  }

  // Step k: skipped if done earlier, else run now (an sglab step) or queued (a plot).
  void schedule(std::size_t k) {
    const Step& s = all_[k];
    const std::vector<std::string> args = step_args(s, o_);
    const std::string line = step_line(s, o_, p_);
    const std::filesystem::path marker = markers_ / (s.name + ".done");
    if (!o_.force && done_earlier(marker, line, args, s.reads)) {
      const std::lock_guard guard(lock_);
      std::fprintf(stderr, "reproduce [%zu/%zu] %s: done earlier, skipped (%s)\n", k + 1, all_.size(), s.name.c_str(),
                   line.c_str());
      ++skipped_;
      times_.add(s.name, "skipped", -1, -1);
      return;
    }
    if (s.timed) {
      plots_.hold();  // its tables carry times: nothing runs beside it (plots paused, queued ones wait)
    } else if (!s.python) {
      plots_.release(waiting_);  // they run beside this step
    }
    if (s.python)
      waiting_.push_back([this, k, args, line, marker](PlotServer& python) { run(k, args, line, marker, &python); });
    else run(k, args, line, marker, nullptr);
  }

  // Runs what is left, then writes the total: the wall and CPU time since `start` (CPU: this
  // process and its finished children).
  void finish_since(std::chrono::steady_clock::time_point start, double cpu_start) {
    plots_.drain(waiting_);  // the interpreters' CPU (their start, the imports) then counts in the total
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double cpu = cpu_seconds() + cpu_seconds(RUSAGE_CHILDREN) - cpu_start;
    times_.add("steps-run-alone", "", alone_wall_, alone_cpu_);
    times_.add("total", "", wall, cpu);
    times_.write(times_csv_, command_, o_.quick);
    std::printf(
        "reproduce: %d steps run, %d already done, %.1f s (CPU %.1f s; the timed steps, run alone: %.1f s); outputs in "
        "%s/, tables in %s/, step times in %s\n",
        done_, skipped_, wall, cpu, alone_wall_, p_.out.c_str(), p_.tables.c_str(), times_csv_.string().c_str());
  }

 private:
  // Runs step k and records its marker and times. What each kind of step writes: the plots only
  // figures, the sglab steps everything else, so that steps running side by side keep apart.
  void run(std::size_t k, const std::vector<std::string>& args, const std::string& line,
           const std::filesystem::path& marker, PlotServer* python) {
    const Step& s = all_[k];
    {
      const std::lock_guard guard(lock_);
      std::fprintf(stderr, "reproduce [%zu/%zu] %s: %s\n  $ %s\n", k + 1, all_.size(), s.name.c_str(), s.what.c_str(),
                   line.c_str());
    }
    const auto t0 = std::chrono::steady_clock::now();
    // The step times are written by either thread at any time: nobody's output.
    const std::vector<std::string> roots = s.python ? figures_ : std::vector<std::string>{p_.out, p_.tables};
    std::vector<std::string> except = {times_csv_.string()};
    if (!s.python) except.insert(except.end(), figures_.begin(), figures_.end());
    const Snapshot before = snapshot(roots, except);
    // An sglab step's CPU: this process's and that of the programs it ran and waited for (the
    // plot interpreter is waited for only at the end of the run).
    const auto own_and_children = [] { return cpu_seconds() + cpu_seconds(RUSAGE_CHILDREN); };
    const double cpu0 = own_and_children();
    int status;
    double cpu;
    std::optional<std::set<std::string>> wrote;  // a plot's own outputs
    double paused = 0.0;                         // and the seconds it was paused
    if (s.python) {
      PlotServer::Outcome plot = python->run(args);
      status = plot.status;
      cpu = plot.cpu;
      paused = plot.paused;
      wrote = std::move(plot.wrote);
    } else {
      // Every table a --quick run writes says so, whatever the step's own options; --force
      // recomputes the sweeps too, not only reruns their commands (which would resume); the
      // step's outputs go to the run's places.
      status = run_sglab_(args, {.quick = o_.quick, .fresh = o_.force, .places = p_});
      cpu = own_and_children() - cpu0;  // the plot threads' own CPU is negligible (they wait)
    }
    if (status != 0) throw std::runtime_error("reproduce: step '" + s.name + "' failed (" + line + ")");
    runner::AtomicFile m(marker);
    m.write(line + "\n" + files_state(args, s.reads) +
            outputs_state(before, snapshot(roots, except), wrote ? &*wrote : nullptr));
    m.commit();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() - paused;
    const std::lock_guard guard(lock_);
    ++done_;
    std::fprintf(stderr, "reproduce [%zu/%zu] %s: finished in %.1f s (CPU %.1f s)\n", k + 1, all_.size(),
                 s.name.c_str(), wall, cpu);
    // "run alone": a timed step, with nothing beside it; their sum is the part of the run's wall
    // time that no scheduling of the other steps can hide.
    times_.add(s.name, s.python ? "run beside" : s.timed ? "run alone" : "run", wall, cpu);
    if (s.timed && !s.python) {
      alone_wall_ += wall;
      alone_cpu_ += cpu;
    }
    times_.write(times_csv_, command_, o_.quick);
  }

  const ReproduceOptions& o_;
  const SglabRunner& run_sglab_;
  const runner::Places& p_;
  const std::vector<Step>& all_;
  const std::filesystem::path markers_, times_csv_;
  const std::vector<std::string> figures_;
  std::string command_;
  std::mutex lock_;  // times, the counters and the log lines, shared with the plot threads
  StepTimes times_;
  int done_ = 0, skipped_ = 0;
  double alone_wall_ = 0, alone_cpu_ = 0;  // the timed steps' (run alone) wall and CPU seconds
  PlotQueue plots_{kPlotWorkers};
  std::vector<PlotQueue::Job> waiting_;  // plots not started yet: they start beside the next untimed sglab step
};

}  // namespace

void run_reproduce(const ReproduceOptions& o, const SglabRunner& run_sglab) {
  const runner::Places p = reproduce_places(o);
  const auto all = all_steps(p);
  if (o.list) {  // the steps of this mode and their command lines; nothing is run or written
    for (const auto& s : all) std::printf("%s\t%s\n", s.name.c_str(), step_line(s, o, p).c_str());
    return;
  }
  std::vector<std::string> names;
  for (const auto& s : all) names.push_back(s.name);
  for (const auto& name : o.only) {
    if (std::find(names.begin(), names.end(), name) != names.end()) continue;
    // The steps are too many to list in a bounded message: the closest one, and where the list is.
    const std::string near = runner::closest_name(name, names);
    throw runner::InputError("reproduce: --only: unknown step '" + clip_text(name) + "' (" +
                             (near.empty() ? "" : "did you mean '" + near + "'?; ") +
                             "`sglab reproduce --list` lists the steps)");
  }
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = cpu_seconds() + cpu_seconds(RUSAGE_CHILDREN);
  StepRun run(o, run_sglab, p, all);
  for (std::size_t k = 0; k < all.size(); ++k)
    if (o.only.empty() || std::find(o.only.begin(), o.only.end(), all[k].name) != o.only.end()) run.schedule(k);
  run.finish_since(start, cpu_start);
}

}  // namespace sglab::experiments
