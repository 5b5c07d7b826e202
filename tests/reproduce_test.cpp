// `sglab reproduce` as a library (experiments/reproduce.hpp over the experiment registry):
// every step's command line, full and --quick, parses with the real `sglab` app (a renamed option
// breaks this test, not the main job), and where each mode writes.
#include <algorithm>
#include <chrono>
#include <csignal>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <gtest/gtest.h>

#include "commands.hpp"
#include "input_error.hpp"
#include "plot_queue.hpp"
#include "registry.hpp"
#include "reproduce.hpp"
#include "sglab/registry.hpp"
#include "test_util.hpp"

namespace ex = sglab::experiments;
namespace fs = std::filesystem;

namespace {

// Thrown by the app once every option and requirement is processed, before any command runs
// (CLI11 calls the main app's parse-complete callback before the subcommands' callbacks).
struct Parsed {};

std::vector<ex::Step> steps(const ex::ReproduceOptions& o) { return ex::all_steps(ex::reproduce_places(o)); }

void expect_every_step_parses(const ex::ReproduceOptions& o) {
  const sglab::runner::Places p = ex::reproduce_places(o);
  int parsed = 0;
  for (const ex::Step& s : ex::all_steps(p)) {
    if (s.python) continue;
    CLI::App app{"sglab"};
    app.require_subcommand(1);
    sglab::cli::add_all_commands(app, {.places = p});
    app.parse_complete_callback([] { throw Parsed{}; });
    std::vector<std::string> args = ex::step_args(s, o);
    const std::string line = [&] {
      std::string l;
      for (const auto& a : args) l += " " + a;
      return l;
    }();
    std::reverse(args.begin(), args.end());  // CLI11 takes the vector form last-argument-first
    try {
      app.parse(args);
      ADD_FAILURE() << s.name << ": parsed without reaching the end of parsing: sglab" << line;
    } catch (const Parsed&) {
    } catch (const sglab::runner::InputError& e) {
      // A constant set is read as its option is parsed (constant_sets.hpp): one an earlier step
      // writes (the fits' records) is not there yet. The option itself was taken.
      const std::string what = e.what();
      if (what.rfind("--constants ", 0) != 0 || what.find("no such file or directory") == std::string::npos)
        ADD_FAILURE() << s.name << ": sglab" << line << ": " << what;
    } catch (const std::exception& e) {
      ADD_FAILURE() << s.name << ": sglab" << line << ": " << e.what();
    }
    ++parsed;
  }
  EXPECT_GE(parsed, 25);
}

}  // namespace

TEST(Reproduce, EveryFullStepParses) { expect_every_step_parses({}); }

TEST(Reproduce, EveryQuickStepParsesWithConstants) {
  ex::ReproduceOptions o;
  o.quick = true;
  o.constants = {"published"};
  expect_every_step_parses(o);
}

TEST(Reproduce, StepNamesAreUniqueAndEveryExperimentHasSteps) {
  std::set<std::string> names;
  for (const ex::Step& s : steps({})) EXPECT_TRUE(names.insert(s.name).second) << "duplicate step " << s.name;
  for (const auto& e : ex::experiment_registry()) {
    EXPECT_FALSE(e.summary.empty()) << e.name;
    EXPECT_FALSE(e.steps(ex::reproduce_places({})).empty()) << e.name;
  }
}

// A --quick run writes under results/quick/ and never names paper_tables/; a full run puts its
// tables into paper_tables/. The places reach every step through its run context, not through its
// arguments: no sglab step names an --out or tables directory, and its printed line names the
// places as `sglab` takes them before the command.
TEST(Reproduce, QuickNeverTouchesPaperTables) {
  ex::ReproduceOptions o;
  o.quick = true;
  const sglab::runner::Places p = ex::reproduce_places(o);
  EXPECT_EQ(p.out, "results/quick");
  EXPECT_EQ(p.tables, "results/quick/tables");
  for (const ex::Step& s : ex::all_steps(p)) {
    for (const auto& a : ex::step_args(s, o))
      EXPECT_EQ(a.find("paper_tables"), std::string::npos) << s.name << ": " << a;
    if (s.python) continue;
    for (const char* place : {"--tables", "--tables-dir"})
      EXPECT_EQ(std::count(s.args.begin(), s.args.end(), place), 0) << s.name << " names " << place;
    // Only the general tools name their output files (a render's image, a map, a fit record).
    if (s.args[0] != "render" && s.args[0] != "filter" && s.args[0] != "fit" &&
        (s.args[0] != "envmap" || s.args.at(1) != "make")) {
      EXPECT_EQ(std::count(s.args.begin(), s.args.end(), "--out"), 0) << s.name << " names --out";
    }
    EXPECT_EQ(
        ex::step_line(s, o, p).rfind("sglab --results results/quick --tables results/quick/tables " + s.args[0], 0), 0u)
        << ex::step_line(s, o, p);
  }
  const sglab::runner::Places full = ex::reproduce_places({});
  EXPECT_EQ(full.out, "results");
  EXPECT_EQ(full.tables, "paper_tables");
  for (const ex::Step& s : ex::all_steps(full))
    if (!s.python) {
      EXPECT_EQ(ex::step_line(s, {}, full).rfind("sglab --tables paper_tables " + s.args[0], 0), 0u) << s.name;
    }
}

// The near-wall renders: one per diffuse method the renderer takes, but the reference; the
// output names keep the form renders/near-wall-METHOD.*.
TEST(Reproduce, NearWallRendersEveryRendererMethod) {
  std::set<std::string> rendered;
  for (const ex::Step& s : steps({}))
    if (s.name.rfind("render-near-wall-", 0) == 0) rendered.insert(s.name.substr(17));
  const sglab::Quantity* q = sglab::find_quantity("clamped-cosine");
  ASSERT_NE(q, nullptr);
  for (const auto& m : q->methods) {
    if (m.name == q->reference_method) continue;
    EXPECT_TRUE(rendered.count(m.name)) << m.name;
  }
  for (const char* m :
       {"sg-cosine", "punctual-approx", "hill-fitted", "meder", "tokuyoshi2022", "tokuyoshi2024", "sglab"})
    EXPECT_TRUE(rendered.count(m)) << m;
}

// ---- the experiment registry and the CLI ---------------------------------------------------------

namespace {

std::vector<std::string> subcommand_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names.push_back(sub->get_name());
  return names;
}

}  // namespace

// Every experiment with a command registers exactly one, under the parent its `under` names, and
// every command of the app is a general tool's (listed here: a new command is either a tool added
// to this list or a registered experiment) or exactly one experiment's.
TEST(ExperimentRegistry, EveryCommandIsRegisteredOnce) {
  // The general tools' own commands (cli/commands.hpp), per parent that takes experiments.
  const std::map<std::string, std::set<std::string>> tools = {
      {"", {"eval", "fit", "reproduce", "render", "sweep", "merge", "filter", "envmap", "export"}},
      {"sweep", {}},
      {"envmap", {"make", "render"}}};
  CLI::App app{"sglab"};
  sglab::cli::add_all_commands(app, {});
  std::map<std::string, std::multiset<std::string>> expected;
  for (const auto& [parent, names] : tools) expected[parent].insert(names.begin(), names.end());
  for (const ex::Experiment& e : ex::experiment_registry()) {
    if (!e.add_command) {
      EXPECT_EQ(e.under, "") << e.name << ": a parent but no command";
      continue;
    }
    ASSERT_TRUE(tools.count(e.under)) << e.name << ": under '" << e.under << "', which registers no experiments";
    CLI::App alone{"parent"};
    e.add_command(alone, {});
    const std::vector<std::string> own = subcommand_names(alone);
    ASSERT_EQ(own.size(), 1u) << e.name << " registers " << own.size() << " commands";
    expected[e.under].insert(own[0]);
  }
  for (const auto& [parent, names] : expected) {
    for (const auto& n : names)
      EXPECT_EQ(names.count(n), 1u) << "'" << n << "' under '" << parent << "' is registered twice";
    const CLI::App* p = parent.empty() ? &app : app.get_subcommand(parent);
    std::vector<std::string> got = subcommand_names(*p), want(names.begin(), names.end());
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, want) << "the commands under '" << parent << "'";
  }
}

// ---- a run's places ----------------------------------------------------------------------------

// A command run in a context whose places point elsewhere writes there and nothing into a plain
// run's places (run in-process, as `sglab reproduce` runs its steps).
TEST(RunContextPlaces, SteerWhereACommandWrites) {
  const fs::path dir = fs::path(testing::TempDir()) / "sglab_run_context_places";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path cwd = fs::current_path();
  fs::current_path(dir);
  const sglab::runner::Places places{"elsewhere/out", "elsewhere/tables"};
  EXPECT_EQ(sglab::cli::run_sglab({"error-map", "--quick", "--size", "8"}, {.places = places}), 0);
  EXPECT_EQ(sglab::cli::run_sglab({"error-vs-time", "--quick", "--quantity", "hemispherical"}, {.places = places}), 0);
  const std::set<std::string> written = [&] {
    std::set<std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(dir))
      if (e.is_regular_file()) files.insert(fs::relative(e.path(), dir).string());
    return files;
  }();
  fs::current_path(cwd);
  const std::set<std::string> expected = {
      "elsewhere/out/error_map/error_map.csv", "elsewhere/out/error_map/error_map_summary.csv",
      "elsewhere/out/error_map/error_map.md",  "elsewhere/out/error_vs_time/error_vs_time.csv",
      "elsewhere/tables/error_vs_time.csv",    "elsewhere/tables/error_vs_time.md"};
  EXPECT_EQ(written, expected);
  fs::remove_all(dir);
}

// The places as `sglab` takes them before the command: only those that differ from a plain run's.
TEST(RunContextPlaces, ArgumentsNameOnlyWhatDiffersFromAPlainRun) {
  using sglab::runner::Places;
  EXPECT_TRUE(sglab::runner::places_arguments(Places{}).empty());
  EXPECT_EQ(sglab::runner::places_arguments(Places{"results", "paper_tables"}),
            (std::vector<std::string>{"--tables", "paper_tables"}));
  EXPECT_EQ(sglab::runner::places_arguments(Places{"r", "t"}),
            (std::vector<std::string>{"--results", "r", "--tables", "t"}));
  EXPECT_EQ(Places{}.dir("error_vs_time"), "results/error_vs_time");
  EXPECT_EQ(Places{}.tables_or_dir("near_wall"), "results/near_wall");
  EXPECT_EQ((Places{"r", "t"}.tables_or_dir("near_wall")), "t");
  EXPECT_EQ(Places{}.tables_read(), "paper_tables");
}

// ---- the plot interpreters end with sglab ---------------------------------------------------------
// A stand-in for plots/_serve.py (PlotServer runs the _serve.py beside the script it is asked to
// run): each request forks a worker process, as a plot's multiprocessing pool does, writes both
// PIDs to `pids`, then answers at once ("answer" mode) or keeps running (a plot that is not done).
constexpr const char* kFakeServer = R"(import os, socket, time
here = os.path.dirname(os.path.abspath(__file__))
channel = socket.socket(fileno=3)
requests, answers = channel.makefile("rb"), channel.makefile("wb")
for request in requests:
    worker = os.fork()
    if worker == 0:
        time.sleep(60)
        os._exit(0)
    with open(os.path.join(here, "pids.tmp"), "w") as f:
        f.write("%d %d\n" % (os.getpid(), worker))
    os.rename(os.path.join(here, "pids.tmp"), os.path.join(here, "pids"))
    if open(os.path.join(here, "mode")).read() == "answer":
        answers.write(b'{"status": 0, "cpu": 0, "wrote": []}\n')
        answers.flush()
    else:
        time.sleep(60)
)";

class PlotServerEnd : public sglab::test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    std::ofstream(path("_serve.py")) << kFakeServer;
    std::ofstream(path("plot.py")) << "";
  }
  void TearDown() override {
    for (const pid_t p : pids_)  // what a failing case left behind (ours, still there)
      if (p > 0 && state(p) != '-' && state(p) != 'Z') ::kill(p, SIGKILL);
    TempDirTest::TearDown();
  }
  // Waits up to `seconds` for `file` to appear.
  bool wait_for(const std::string& file, double seconds) const {
    for (auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
         std::chrono::steady_clock::now() < until; std::this_thread::sleep_for(std::chrono::milliseconds(20)))
      if (fs::exists(path(file))) return true;
    return false;
  }
  // The state letter of `pid` in /proc (R, S, T, Z, …), or '-' when there is no such process.
  static char state(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string stat;
    if (!std::getline(in, stat) || stat.rfind(')') == std::string::npos) return '-';
    return stat[stat.rfind(')') + 2];
  }
  // Runs `owner` in a child process (the sglab that started the interpreter), waits for it to
  // end by `signal`, then expects the interpreter and its worker to end within 10 s (gone, or a
  // zombie for init to reap).
  template <class F>
  void expect_interpreter_ends_with_owner(F owner, int signal) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      owner();
      ::_exit(4);  // not reached: the owner ends by its signal
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(wait_for("pids", 5)) << "the interpreter never ran the plot";
    std::ifstream(path("pids")) >> pids_[0] >> pids_[1];
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal) << "owner status " << status;
    const auto ended = [&] {
      for (const pid_t p : pids_)
        if (state(p) != '-' && state(p) != 'Z') return false;
      return true;
    };
    for (int i = 0; i < 500 && !ended(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_TRUE(ended()) << "interpreter " << pids_[0] << " in state " << state(pids_[0]) << ", worker " << pids_[1]
                         << " in state " << state(pids_[1]) << " 10 s after their sglab ended";
  }
  pid_t pids_[2] = {0, 0};
};

// Paused (SIGSTOP) and then left by an sglab killed outright: the interpreter's own process group,
// orphaned, gets SIGHUP and SIGCONT from the kernel. In the test process's group it stayed stopped.
// (The kernel looks at the moment the group is orphaned: the owner waits until both processes have
// stopped, as they have long before in a real run's timed step.)
TEST_F(PlotServerEnd, APausedInterpreterAndItsWorkerEndWhenSglabIsKilled) {
  std::ofstream(path("mode")) << "answer";
  expect_interpreter_ends_with_owner(
      [&] {
        ex::PlotServer server;
        if (server.run({path("plot.py").string()}).status != 0) ::_exit(3);
        server.pause();
        pid_t pids[2] = {0, 0};
        std::ifstream(path("pids")) >> pids[0] >> pids[1];
        for (int i = 0; i < 500 && (state(pids[0]) != 'T' || state(pids[1]) != 'T'); ++i)
          std::this_thread::sleep_for(std::chrono::milliseconds(10));
        ::raise(SIGKILL);
      },
      SIGKILL);
}

// In the middle of a plot when sglab gets SIGTERM (or SIGINT: a Ctrl-C reaches the plots this way):
// the handler ends the interpreter's group before sglab dies, rather than let the plot run on.
TEST_F(PlotServerEnd, ARunningInterpreterAndItsWorkerEndWhenSglabIsTerminated) {
  std::ofstream(path("mode")) << "run";
  expect_interpreter_ends_with_owner(
      [&] {
        ::signal(SIGTERM, SIG_DFL);  // as in a shell's background job, whatever this test inherited
        ex::PlotServer server;
        std::thread plot([&] { server.run({path("plot.py").string()}); });
        plot.detach();
        if (!wait_for("pids", 5)) ::_exit(3);
        ::raise(SIGTERM);
      },
      SIGTERM);
}
