// The `sglab` command as a user meets it, through the built binary: every option that takes a name
// lists the valid names in its --help (checked against the registries the names come from), and an
// unknown name is refused with exit status 2, the value, and the closest valid name.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "driver.hpp"
#include "names.hpp"
#include "sglab/registry.hpp"
#include "sglab/render/filtering.hpp"
#include "sglab/render/vsgl_generation.hpp"
#include "sglab/render/vsgl_shading.hpp"
#include "sglab/render/vsgl_specular_methods.hpp"
#include "test_util.hpp"

#include <cctype>
#include <filesystem>
#include <regex>

namespace {

using sglab::test::TempDirTest;

class Cli : public TempDirTest {
 protected:
  // `sglab ARGS --help` succeeds and names every one of `names`.
  void expect_help_lists(const std::string& args, const std::vector<std::string>& names) const {
    const auto r = sglab(args + " --help");
    ASSERT_EQ(r.status, 0) << args << "\n" << r.err;
    for (const auto& n : names)
      EXPECT_NE(r.out.find(n), std::string::npos) << "`sglab " << args << " --help` does not list " << n;
  }
  // `sglab ARGS` refused: exit 2, the bad value quoted and `closest` suggested, nothing on stdout.
  void expect_suggestion(const std::string& args, const std::string& value, const std::string& closest) const {
    const auto r = sglab(args);
    EXPECT_EQ(r.status, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("'" + value + "'"), std::string::npos) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("did you mean '" + closest + "'"), std::string::npos) << args << "\n" << r.err;
  }
};

std::vector<std::string> method_names(const std::string& quantity) {
  std::vector<std::string> names;
  for (const auto& m : sglab::find_quantity(quantity)->methods) names.push_back(m.name);
  return names;
}

TEST_F(Cli, HelpListsEveryName) {
  std::vector<std::string> fits = {"all"}, objectives;
  for (const auto& f : sglab::fit::fitters()) {
    fits.push_back(f.name);
    objectives.insert(objectives.end(), f.objectives.begin(), f.objectives.end());
  }
  expect_help_lists("fit", fits);
  expect_help_lists("fit", objectives);
  std::vector<std::string> quantities, methods;
  for (const auto& q : sglab::quantities()) {
    quantities.push_back(q.name);
    for (const auto& m : q.methods) methods.push_back(m.name);
  }
  expect_help_lists("eval", quantities);
  expect_help_lists("eval", methods);
  expect_help_lists("stability", quantities);
  expect_help_lists("error-vs-time", {"clamped-cosine", "specular"});
  expect_help_lists("render", sglab::render::vsgl_mode_names());
  expect_help_lists("render", sglab::render::diffuse_method_names());
  expect_help_lists("render", sglab::render::specular_method_names());
  expect_help_lists("filter", sglab::render::filter_weights_names());
  expect_help_lists("filter", sglab::render::indirect_source_names());
  expect_help_lists("filter-sweep", sglab::render::filter_weights_names());
  expect_help_lists("sweep render", sglab::render::vsgl_mode_names());
  expect_help_lists("sweep specular", {"ggx", "gaussian"});
  expect_help_lists("envmap render", method_names("clamped-cosine"));
  expect_help_lists("envmap render", {"sphere", "plane"});
  expect_help_lists("fit envmap", {"fibonacci", "kmeans", "l2", "log-l2", "ceres", "vmf-em"});
  expect_help_lists("reproduce", {"fit-all", "error-vs-time", "stability"});
}

TEST_F(Cli, UnknownNameSuggestsTheClosest) {
  expect_suggestion("fit lamda-d", "lamda-d", "lambda-d");
  expect_suggestion("fit lambda-d --objective l2-hemispher", "l2-hemispher", "l2-hemisphere");
  expect_suggestion("eval clamped-cosin --method exact", "clamped-cosin", "clamped-cosine");
  expect_suggestion("eval clamped-cosine --method tokuyosi2024", "tokuyosi2024", "tokuyoshi2024");
  expect_suggestion("render scene.json --vsgl tw0-shared", "tw0-shared", "two-shared");
  expect_suggestion("render scene.json --specular sg-wrap", "sg-wrap", "sg-warp");
  expect_suggestion("filter scene.json --weights lobes", "lobes", "lobe");
  expect_suggestion("filter-sweep --scene s.json --weights normal,lbe-depth", "lbe-depth", "lobe-depth");
  expect_suggestion("sweep render --scene s.json --vsgl kmean:8", "kmean", "kmeans");
  expect_suggestion("error-vs-time --quantity specullar", "specullar", "specular");
  expect_suggestion("reproduce --only fit-al --list", "fit-al", "fit-all");
  // Far from every name: no suggestion, but the list.
  const auto r = sglab("render scene.json --vsgl zzzzzzzzzz");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(r.err.find("did you mean"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("two-shared"), std::string::npos) << r.err;
}

TEST(Names, EditDistanceAndClosest) {
  using sglab::runner::closest_name;
  using sglab::runner::edit_distance;
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("Lobe", "lobe"), 0u);
  EXPECT_EQ(closest_name("tokuyoshi2042", {"meder", "tokuyoshi2022", "tokuyoshi2024"}), "tokuyoshi2022");
  EXPECT_EQ(closest_name("lob", {"normal", "lobe", "lobe-depth"}), "lobe");
  EXPECT_EQ(closest_name("xyz", {"normal", "lobe"}), "");
  EXPECT_EQ(closest_name(std::string(1000, 'a'), {"a"}), "") << "no quadratic work on a long value";
}

}  // namespace

// Generated tables and docs speak of the project only: none of the project-management phrases of
// the pattern below in paper_tables/, docs/, README.md or scenes/README.md.
TEST(RepositoryText, NoTrackerWording) {
  namespace fs = std::filesystem;
  const fs::path root = SGLAB_SOURCE_DIR;
  const std::regex tracker(
      R"(\b(the|this|that|an?) issue\b|\bissues? ?#?[0-9]+|\btickets?\b|\bcan (be )?closed?\b|\bpull request|\bPR ?#|\btracker\b|closing note)",
      std::regex::icase);
  std::vector<fs::path> files = {root / "README.md", root / "scenes/README.md"};
  for (const char* dir : {"paper_tables", "docs"})
    for (const auto& e : fs::recursive_directory_iterator(root / dir))
      if (e.is_regular_file() &&
          (e.path().extension() == ".md" || e.path().extension() == ".csv" || e.path().extension() == ".tex"))
        files.push_back(e.path());
  // Every alternative of the pattern holds one of these words (case aside): a line without any of
  // them cannot match, and skips the regex (std::regex on every line was most of this test's time).
  const auto may_match = [](std::string line) {
    for (char& ch : line) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    for (const char* word : {"issue", "ticket", "clos", "pull request", "#", "tracker"})
      if (line.find(word) != std::string::npos) return true;
    return false;
  };
  ASSERT_GT(files.size(), 20u);
  for (const auto& f : files) {
    std::istringstream lines(sglab::test::read_file(f));
    int n = 0;
    for (std::string line; std::getline(lines, line);) {
      ++n;
      std::smatch m;
      if (may_match(line) && std::regex_search(line, m, tracker))
        ADD_FAILURE() << f.string() << ":" << n << ": tracker wording '" << m.str() << "': " << line.substr(0, 200);
    }
  }
}
