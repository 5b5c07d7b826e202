// Where `sglab reproduce` writes, through the built binary (SGLAB_EXE) in a temporary directory:
// the command line of every step as `--list` resolves it — a --quick run writes only under
// results/quick/ and never into paper_tables/, a full run puts its tables and key figures into
// paper_tables/ — and two cheap steps of a --quick run actually run, to check the files land
// where the list says. Also `sglab sweep render --out DIR` writes its table into DIR. The whole
// --quick run (about a minute) is not run here.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_util.hpp"

namespace {

namespace fs = std::filesystem;

struct ListedStep {
  std::string name;
  std::vector<std::string> words;  // the command line, "sglab"/"python3" first
};

std::vector<ListedStep> parse_list(const std::string& text) {
  std::vector<ListedStep> steps;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty()) continue;
    const auto tab = line.find('\t');
    EXPECT_NE(tab, std::string::npos) << line;
    if (tab == std::string::npos) continue;
    ListedStep s{line.substr(0, tab), {}};
    std::istringstream words(line.substr(tab + 1));
    for (std::string w; words >> w;) s.words.push_back(w);
    steps.push_back(std::move(s));
  }
  return steps;
}

// The file or directory paths a step's command line names: every word with a '/', and the part
// after '=' of a NAME=PATH word (each item of a comma list); the inputs under scenes/ and plots/ are left out.
std::vector<std::string> output_paths(const ListedStep& s) {
  std::vector<std::string> paths;
  for (const auto& w : s.words) {
    // NAME=PATH, and NAME=A,B,… lists (`--vary KEY=2,FIT.json,…`): each item on its own.
    std::istringstream items(w.find('=') != std::string::npos ? w.substr(w.find('=') + 1) : w);
    for (std::string p; std::getline(items, p, ',');) {
      if (p.find('/') == std::string::npos || p.rfind("scenes/", 0) == 0 || p.rfind("plots/", 0) == 0) continue;
      paths.push_back(p);
    }
  }
  return paths;
}

// The word after `option` in the step's command line, or "" without it.
std::string option_value(const ListedStep& s, const std::string& option) {
  for (std::size_t i = 0; i + 1 < s.words.size(); ++i)
    if (s.words[i] == option) return s.words[i + 1];
  return "";
}

bool has_prefix(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

class ReproduceCommand : public sglab::test::TempDirTest {
 protected:
  // reproduce runs its steps with paths relative to the repository (scenes/, plots/): give dir_
  // the same inputs, and nothing else of the checkout.
  void link_inputs() const {
    for (const char* d : {"scenes", "plots"}) fs::create_directory_symlink(fs::path(SGLAB_SOURCE_DIR) / d, path(d));
  }
  // `sglab reproduce --quick --only STEP` ran and left its tables in results/quick/tables/, its
  // marker in results/quick/.steps/ and nothing in paper_tables/.
  void run_quick_step(const std::string& step, std::initializer_list<const char*> tables) const {
    const auto r = sglab("reproduce --quick --only " + step);
    ASSERT_EQ(r.status, 0) << r.err;
    for (const char* table : tables)
      EXPECT_TRUE(fs::exists(path("results/quick/tables") / table)) << table << "\n" << r.err;
    EXPECT_TRUE(fs::exists(path("results/quick/.steps/" + step + ".done")));
    EXPECT_FALSE(fs::exists(path("paper_tables"))) << r.err;
  }
};

TEST_F(ReproduceCommand, QuickListWritesOnlyUnderResultsQuick) {
  const auto r = sglab("reproduce --quick --list");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto steps = parse_list(r.out);
  ASSERT_GT(steps.size(), 10u) << r.out;
  int with_tables = 0;
  for (const auto& s : steps) {
    for (const auto& p : output_paths(s)) {
      EXPECT_TRUE(has_prefix(p, "results/quick/") || p == "results/quick") << s.name << " writes " << p;
      EXPECT_EQ(p.find("paper_tables"), std::string::npos) << s.name << " names " << p;
    }
    for (const char* option : {"--tables", "--tables-dir"})
      if (const auto t = option_value(s, option); !t.empty()) {
        EXPECT_EQ(t, "results/quick/tables") << s.name;
        ++with_tables;
      }
  }
  EXPECT_GE(with_tables, 6) << "the fit, error-vs-time, specular, stability, render and filtering tables";
  EXPECT_FALSE(fs::exists(path("results"))) << "--list runs nothing and writes nothing";
}

TEST_F(ReproduceCommand, FullListPutsTablesAndKeyFiguresInPaperTables) {
  const auto r = sglab("reproduce --list");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto steps = parse_list(r.out);
  ASSERT_GT(steps.size(), 10u) << r.out;
  int with_tables = 0, key_figures = 0;
  for (const auto& s : steps) {
    for (const auto& p : output_paths(s)) {
      EXPECT_TRUE((has_prefix(p, "results/") && !has_prefix(p, "results/quick")) || has_prefix(p, "paper_tables/") ||
                  p == "paper_tables")
          << s.name << " writes " << p;
      key_figures += p == "paper_tables/figures";
    }
    for (const char* option : {"--tables", "--tables-dir"})
      if (const auto t = option_value(s, option); !t.empty()) {
        EXPECT_EQ(t, "paper_tables") << s.name;
        ++with_tables;
      }
  }
  EXPECT_GE(with_tables, 6);
  EXPECT_GE(key_figures, 4) << "error vs time, specular, renders, near-wall SMAPE";
}

TEST_F(ReproduceCommand, ExplicitOutAndTablesDirAreObeyed) {
  const auto r = sglab("reproduce --quick --out elsewhere --tables-dir tables --list");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const auto& s : parse_list(r.out))
    for (const auto& p : output_paths(s))
      EXPECT_TRUE(has_prefix(p, "elsewhere/") || has_prefix(p, "tables/") || p == "tables")
          << s.name << " writes " << p;
}

// Two steps of a real --quick run, each in a test of its own (so that ctest -j2 runs them side by
// side): their tables land in results/quick/tables/, nothing appears in paper_tables/.
// The fits: `sglab fit all --quick` end to end, its one run in the suite. Every fit's record in
// --json-dir says it converged from its default start: for sglab's and sglab-specular's fits this is
// the check (FitRegistry.EveryFitConvergesFromItsDefaultStart runs only the others), on their
// --quick grids (sglab's Lawson loop on 2175 of its 10139 points, 10 rounds; sglab-specular's IRLS
// on the 186 rows of `sglab sweep specular --quick`): the same solve, stopping rules and
// convergence test as the full fits, a sixth of the time.
TEST_F(ReproduceCommand, QuickFitStepWritesIntoResultsQuick) {
  link_inputs();
  run_quick_step("fit-all", {"constants.md", "constants.csv"});
  if (HasFatalFailure()) return;
  EXPECT_FALSE(fs::exists(path("results/fits"))) << "a --quick run keeps out of the full run's results/";
  // Every fit the constants table names (its first column, below the two header lines) has its
  // record, and the record says it converged.
  std::istringstream rows(sglab::test::read_file(path("results/quick/tables/constants.csv")));
  std::vector<std::string> fits;
  std::string line;
  for (int header = 0; header < 2 && std::getline(rows, line); ++header) {
  }
  while (std::getline(rows, line)) {
    const std::string fit = line.substr(0, line.find(','));
    if (std::find(fits.begin(), fits.end(), fit) == fits.end()) fits.push_back(fit);
  }
  for (const char* slow : {"sglab", "sglab-specular"})
    EXPECT_NE(std::find(fits.begin(), fits.end(), slow), fits.end()) << slow << " is missing from constants.csv";
  for (const auto& fit : fits) {
    const auto record = path("results/quick/fits/" + fit + ".json");
    ASSERT_TRUE(fs::exists(record)) << fit;
    EXPECT_NE(sglab::test::read_file(record).find("\"converged\": true"), std::string::npos)
        << fit << " did not converge";
  }
}

// The render sweep: its table and its per-point CSV.
TEST_F(ReproduceCommand, QuickRenderSweepStepWritesIntoResultsQuick) {
  link_inputs();
  run_quick_step("sweep-render-count", {"vsgl_error_vs_count.md", "vsgl_error_vs_count.csv"});
  if (HasFatalFailure()) return;
  EXPECT_TRUE(fs::exists(path("results/quick/render_sweep/vsgl_error_vs_count_points.csv")));
  EXPECT_FALSE(fs::exists(path("results/render_sweep"))) << "a --quick run keeps out of the full run's results/";
}

// Plot steps run beside the sglab steps: each step's marker lists only what it wrote itself (the
// plots' figures, the sglab step's table and CSV), and the step times say which ran beside.
TEST_F(ReproduceCommand, PlotsRunBesideAndEachMarkerHoldsItsOwnOutputs) {
  link_inputs();
  const auto r = sglab("reproduce --quick --only error-map plot-error-maps plot-own-method render-cornell-glossy");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto marker = [&](const std::string& step) {
    std::ifstream in(path("results/quick/.steps/" + step + ".done"));
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  };
  const auto outputs = [&](const std::string& step) {
    std::vector<std::string> paths;
    std::istringstream lines(marker(step));
    for (std::string l; std::getline(lines, l);)
      if (l.rfind("output ", 0) == 0) paths.push_back(l.substr(7, l.rfind(' ') - 7));
    return paths;
  };
  for (const char* plot : {"plot-error-maps", "plot-own-method"}) {
    const auto written = outputs(plot);
    EXPECT_FALSE(written.empty()) << plot << "\n" << r.err;
    for (const auto& w : written) EXPECT_NE(w.find("/figures/"), std::string::npos) << plot << " claims " << w;
  }
  for (const char* step : {"error-map", "render-cornell-glossy"}) {
    const auto written = outputs(step);
    EXPECT_FALSE(written.empty()) << step << "\n" << r.err;
    for (const auto& w : written) {
      EXPECT_EQ(w.find("/figures/"), std::string::npos) << step << " claims " << w;
      EXPECT_EQ(w.find("reproduce_times.csv"), std::string::npos) << step << " claims " << w;
    }
  }
  std::ifstream times(path("results/quick/reproduce_times.csv"));
  std::stringstream text;
  text << times.rdbuf();
  EXPECT_NE(text.str().find("plot-error-maps,run beside,"), std::string::npos) << text.str();
  EXPECT_NE(text.str().find("render-cornell-glossy,run,"), std::string::npos) << text.str();
  // A second run finds every step done (no marker holds a file another step rewrote since).
  const auto again = sglab("reproduce --quick --only error-map plot-error-maps plot-own-method render-cornell-glossy");
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_NE(again.out.find("0 steps run, 4 already done"), std::string::npos) << again.out << again.err;
}

// The recommend step reads the tables of a directory its command names only as a directory: its
// marker fingerprints each table it reads (Step::reads), so a changed table, or one that appears,
// reruns it, and an unchanged one does not.
TEST_F(ReproduceCommand, RecommendRerunsWhenATableItReadsChanges) {
  fs::create_directories(path("t"));
  const auto table = [&](const std::string& file, const std::string& rows) {
    std::ofstream(path("t/" + file)) << "# Generated by `sglab test-table` (full run); do not edit by hand.\n" << rows;
  };
  const std::string header = "noisy,floor_roughness,weights,relative_l2,glossy_relative_l2,diffuse_relative_l2\n";
  table("filtering_denoise.csv", header + "interleaved:2,0.1,normal,0.2,0.3,0.1\n");
  const std::string run = "reproduce --only recommend --out res --tables-dir t";
  const auto first = sglab(run);
  ASSERT_EQ(first.status, 0) << first.err;
  EXPECT_NE(first.out.find("1 steps run, 0 already done"), std::string::npos) << first.out << first.err;
  EXPECT_NE(sglab::test::read_file(path("t/recommendations.md")).find("glossy 0.3, diffuse 0.1"), std::string::npos);
  const auto again = sglab(run);
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_NE(again.out.find("0 steps run, 1 already done"), std::string::npos) << again.out << again.err;
  // A table it read changes (a partial rerun of an earlier step): recommend runs again.
  table("filtering_denoise.csv", header + "interleaved:2,0.1,normal,0.2,0.25,0.1\n");
  const auto changed = sglab(run);
  ASSERT_EQ(changed.status, 0) << changed.err;
  EXPECT_NE(changed.out.find("1 steps run, 0 already done"), std::string::npos) << changed.out << changed.err;
  EXPECT_NE(sglab::test::read_file(path("t/recommendations.md")).find("glossy 0.25, diffuse 0.1"), std::string::npos);
  // A table it looks for appears.
  table("filtering.csv", "scale,floor_roughness,weights,relative_l2,glossy_relative_l2\n2,0.1,lobe,0.3,0.4\n");
  const auto appeared = sglab(run);
  ASSERT_EQ(appeared.status, 0) << appeared.err;
  EXPECT_NE(appeared.out.find("1 steps run, 0 already done"), std::string::npos) << appeared.out << appeared.err;
  EXPECT_NE(sglab::test::read_file(path("t/recommendations.md"))
                .find("**lobe** (lowest mean relative L2 over the sweep, 0.3;"),
            std::string::npos);
}

// `sglab sweep render --out DIR` without --tables-dir: the table goes into DIR too.
TEST_F(ReproduceCommand, SweepRenderTableGoesWhereOutSays) {
  link_inputs();
  const auto r = sglab(
      "sweep render --scene scenes/cornell-glossy.json --width 8 --height 6 --rsm 8 --shadow-map 32 --out sweep");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(path("sweep/vsgl_error_vs_count_points.csv")));
  EXPECT_TRUE(fs::exists(path("sweep/vsgl_error_vs_count.md")));
  EXPECT_TRUE(fs::exists(path("sweep/vsgl_error_vs_count.csv")));
  EXPECT_FALSE(fs::exists(path("paper_tables")));
}

}  // namespace

// Only `sglab reproduce` writes paper_tables/ by default: the table-writing commands run from a
// copy of the repository root (its committed paper_tables/ beside them) write their tables next to
// their --out, leave every committed table byte for byte as it was, and head the table with a
// command line that says where it went.
TEST_F(ReproduceCommand, ToolsRunFromTheRepositoryRootLeavePaperTablesAlone) {
  link_inputs();
  fs::copy(fs::path(SGLAB_SOURCE_DIR) / "paper_tables", path("paper_tables"), fs::copy_options::recursive);
  std::vector<std::pair<fs::path, std::string>> before;
  for (const auto& e : fs::recursive_directory_iterator(path("paper_tables")))
    if (e.is_regular_file()) before.emplace_back(e.path(), sglab::test::read_file(e.path()));
  ASSERT_FALSE(before.empty());
  // The hemispherical quantity: the same table-writing path as every quantity's, in a quarter of
  // clamped-cosine's time (fewer methods).
  const auto r = sglab("error-vs-time --quick --quantity hemispherical");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const auto& [p, text] : before) EXPECT_EQ(sglab::test::read_file(p), text) << p << " was rewritten";
  EXPECT_FALSE(fs::exists(path("paper_tables/error_vs_time.md.tmp")));
  const std::string md = sglab::test::read_file(path("results/error_vs_time/error_vs_time.md"));
  EXPECT_NE(md.find("Generated by `sglab error-vs-time --quantity hemispherical --quick`"), std::string::npos)
      << md.substr(0, 300);
  // With --tables the header names the directory, so that it reproduces the table where it is.
  const auto t = sglab("error-vs-time --quick --quantity hemispherical --out elsewhere --tables mine");
  ASSERT_EQ(t.status, 0) << t.err;
  EXPECT_NE(sglab::test::read_file(path("mine/error_vs_time.csv")).find("--tables mine`"), std::string::npos);
  EXPECT_TRUE(fs::exists(path("elsewhere/error_vs_time.csv")));
  for (const auto& [p, text] : before) EXPECT_EQ(sglab::test::read_file(p), text) << p << " was rewritten";
}

// A run's places steer where every command writes (runner::Places in the RunContext): `sglab
// --results R --tables T COMMAND` puts the command's outputs into R/ITS_DIR and its tables into T,
// and nothing into a plain run's results/ or into paper_tables/; the table's header names the
// directory as the command's own option, so that the header's command alone writes it there too.
TEST_F(ReproduceCommand, PlacesBeforeTheCommandSteerWhereItWrites) {
  const auto r = sglab("--results mine --tables tabs error-vs-time --quick --quantity hemispherical");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(path("mine/error_vs_time/error_vs_time.csv")));
  const std::string md = sglab::test::read_file(path("tabs/error_vs_time.md"));
  EXPECT_NE(md.find("Generated by `sglab error-vs-time --quantity hemispherical --quick --tables tabs`"),
            std::string::npos)
      << md.substr(0, 300);
  EXPECT_TRUE(fs::exists(path("tabs/error_vs_time.csv")));
  // Without a tables directory the tables stay beside the outputs; OPTION=DIR is the same option.
  const auto m = sglab("--results=other error-map --quick --size 8");
  ASSERT_EQ(m.status, 0) << m.err;
  for (const char* f : {"error_map.csv", "error_map_summary.csv", "error_map.md"})
    EXPECT_TRUE(fs::exists(path("other/error_map") / f)) << f;
  // An option of the command still wins over the run's places.
  const auto o = sglab("--results other error-map --quick --size 8 --out own");
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_TRUE(fs::exists(path("own/error_map.csv")));
  EXPECT_FALSE(fs::exists(path("results")));
  EXPECT_FALSE(fs::exists(path("paper_tables")));
  // An empty place is bad input: exit status 2 and nothing written.
  refused(sglab("--results '' error-map --quick --size 8"), "--results '': expected a directory", {"results"});
  refused(sglab("--tables= error-map --quick --size 8"), "--tables '': expected a directory", {"results"});
}

// `sglab reproduce --list` prints each step as a line that runs alone where the step runs: its
// places before the command. A quick step run so writes where the quick run would.
TEST_F(ReproduceCommand, ListedLinesRunAloneInTheirPlaces) {
  const auto r = sglab("reproduce --quick --list");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const auto& s : parse_list(r.out)) {
    if (s.name != "error-map") continue;
    std::string line;
    for (std::size_t i = 1; i < s.words.size(); ++i) line += " " + s.words[i];
    EXPECT_EQ(line, " --results results/quick --tables results/quick/tables error-map --quick");
    const auto run = sglab(line.substr(1) + " --size 8");
    ASSERT_EQ(run.status, 0) << run.err;
    EXPECT_TRUE(fs::exists(path("results/quick/error_map/error_map.csv")));
    EXPECT_FALSE(fs::exists(path("results/error_map")));
    return;
  }
  ADD_FAILURE() << "no error-map step in\n" << r.out;
}
