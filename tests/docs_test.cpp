// The documents against the tree they describe, so that drift fails the suite:
//   - docs/math.md §12 lists every method of the registry (and nothing the registry lacks), and the
//     section each line cites exists and names that method (a quantity listed as `q/*`: the quantity),
//     so every registered method has its formula's entry in docs/math.md, not only an index line;
//   - the counts quoted in docs/architecture.md ("Counts") are those of the source tree and of the
//     registries, recounted here (the reference is the tree itself, not a number kept by hand);
//   - the files docs/architecture.md says a fitted method touches are the ones the build reads:
//     the list SGLAB_FITTERS of fit/CMakeLists.txt is the one place a fitter is named;
//   - no source file is over the 600 lines README and docs/architecture.md promise;
//   - the sources batched apart for a method's header are those that include one.
// On a mismatch the failure prints the line to write.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "driver.hpp"
#include "registry.hpp"
#include "sglab/registry.hpp"

namespace {

namespace fs = std::filesystem;

std::string read_doc(const std::string& relative) {
  std::ifstream in(fs::path(SGLAB_SOURCE_DIR) / relative);
  EXPECT_TRUE(in) << relative;
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The text of `doc` from the line starting with `heading` to the next heading of the same level.
std::string section(const std::string& doc, const std::string& heading) {
  const std::size_t start = doc.find("\n" + heading);
  if (start == std::string::npos) return "";
  const std::string level = heading.substr(0, heading.find(' ') + 1);  // "## "
  const std::size_t end = doc.find("\n" + level, start + 1);
  return doc.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

// Files directly in DIR whose names match the one-star pattern NAME ("*.cpp", "*_test.cpp").
std::size_t count_files(const std::string& pattern) {
  const fs::path p(pattern);
  const std::string name = p.filename().string();
  const std::size_t star = name.find('*');
  if (star == std::string::npos || name.find('*', star + 1) != std::string::npos) {
    ADD_FAILURE() << "pattern with one star in its last component expected: " << pattern;
    return 0;
  }
  const std::string prefix = name.substr(0, star), suffix = name.substr(star + 1);
  const fs::path dir = fs::path(SGLAB_SOURCE_DIR) / p.parent_path();
  if (!fs::is_directory(dir)) {
    ADD_FAILURE() << "no directory " << p.parent_path();
    return 0;
  }
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string f = e.path().filename().string();
    if (e.is_regular_file() && f.size() >= prefix.size() + suffix.size() && f.compare(0, prefix.size(), prefix) == 0 &&
        f.compare(f.size() - suffix.size(), suffix.size(), suffix) == 0)
      ++n;
  }
  return n;
}

// The numbered section "## N. …" of `doc`, up to the next "## " heading ("" if there is none).
std::string numbered_section(const std::string& doc, const std::string& number) {
  const std::size_t start = doc.find("\n## " + number + ". ");
  if (start == std::string::npos) return "";
  const std::size_t end = doc.find("\n## ", start + 1);
  return doc.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

std::size_t method_count() {
  std::size_t n = 0;
  for (const auto& q : sglab::quantities()) n += q.methods.size();
  return n;
}

TEST(Docs, MathIndexListsEveryRegisteredMethod) {
  const std::string index = section(read_doc("docs/math.md"), "## 12. Registry index");
  ASSERT_FALSE(index.empty()) << "docs/math.md has no section \"## 12. Registry index\"";
  // Every `quantity/method` (or `quantity/*`) the index names.
  std::set<std::string> listed;
  const std::regex entry("`([a-z0-9-]+/[A-Za-z0-9_*-]+)`");
  for (std::sregex_iterator it(index.begin(), index.end(), entry), end; it != end; ++it) listed.insert((*it)[1].str());
  std::set<std::string> registered;
  for (const auto& q : sglab::quantities()) {
    for (const auto& m : q.methods) {
      const std::string name = q.name + "/" + m.name;
      registered.insert(name);
      EXPECT_TRUE(listed.count(name) || listed.count(q.name + "/*"))
          << "docs/math.md §12 lacks `" << name << "` (its formula's section and its source)";
    }
  }
  for (const auto& name : listed) {
    const std::string q = name.substr(0, name.find('/'));
    if (name.substr(name.find('/') + 1) == "*") {
      EXPECT_NE(sglab::find_quantity(q), nullptr) << "docs/math.md §12 names a quantity the registry lacks: " << name;
    } else {
      EXPECT_TRUE(registered.count(name)) << "docs/math.md §12 names a method the registry lacks: " << name;
    }
  }
}

// Each §12 row "| `quantity/method` | 3 ("sglab diffuse") | source |" cites sections; one of them
// must name the method in backticks (a `quantity/*` row: the quantity), so the entry is more than
// an index line. Sections are cited by number, before any parenthesised title.
TEST(Docs, MathIndexCitesASectionThatNamesTheMethod) {
  const std::string doc = read_doc("docs/math.md");
  const std::string index = section(doc, "## 12. Registry index");
  ASSERT_FALSE(index.empty()) << "docs/math.md has no section \"## 12. Registry index\"";
  const std::regex row(R"(\n\| `([a-z0-9-]+)/([A-Za-z0-9_*-]+)` \| ([^|(]+))");
  const std::regex number("[0-9]+");
  std::size_t rows = 0;
  for (std::sregex_iterator it(index.begin(), index.end(), row), end; it != end; ++it) {
    ++rows;
    const std::string quantity = (*it)[1].str(), method = (*it)[2].str(), cited = (*it)[3].str();
    const std::string named = "`" + (method == "*" ? quantity : method) + "`";
    bool found = false;
    std::size_t sections = 0;
    for (std::sregex_iterator n(cited.begin(), cited.end(), number), nend; n != nend; ++n) {
      ++sections;
      const std::string text = numbered_section(doc, (*n)[0].str());
      EXPECT_FALSE(text.empty()) << "docs/math.md §12: `" << quantity << "/" << method << "` cites §" << (*n)[0].str()
                                 << ", which does not exist";
      if (text.find(named) != std::string::npos) found = true;
    }
    EXPECT_GT(sections, 0u) << "docs/math.md §12: `" << quantity << "/" << method << "` cites no section";
    EXPECT_TRUE(found) << "docs/math.md §12: `" << quantity << "/" << method << "` cites §" << cited
                       << "but no cited section names " << named << ": state its formula there";
  }
  EXPECT_GE(rows, sglab::quantities().size()) << "docs/math.md §12: the rows were not read";
}

TEST(Docs, ArchitectureCountsMatchTheTree) {
  const std::string counts = section(read_doc("docs/architecture.md"), "### Counts");
  ASSERT_FALSE(counts.empty()) << "docs/architecture.md has no section \"### Counts\"";
  const std::map<std::string, std::size_t> named{
      {"registry quantities", sglab::quantities().size()},
      {"registry methods", method_count()},
      {"experiments (`SGLAB_EXPERIMENTS`)", sglab::experiments::experiment_registry().size()},
      {"`sglab reproduce` steps (full run)", sglab::experiments::all_steps({"results", "paper_tables"}).size()},
  };
  // Rows "| what | N |": `DIR/PATTERN` (files) or one of the named counts.
  const std::regex row(R"(\n\| ([^|]+?) \| ([0-9]+) \|)");
  std::size_t rows = 0;
  std::set<std::string> seen;
  for (std::sregex_iterator it(counts.begin(), counts.end(), row), end; it != end; ++it) {
    const std::string what = (*it)[1].str();
    const std::size_t quoted = std::stoul((*it)[2].str());
    std::size_t actual = 0;
    if (named.count(what)) {
      actual = named.at(what);
      seen.insert(what);
    } else if (what.size() > 2 && what.front() == '`' && what.back() == '`') {
      actual = count_files(what.substr(1, what.size() - 2));
    } else {
      ADD_FAILURE() << "docs/architecture.md, Counts: a row this test cannot count: " << what;
      continue;
    }
    ++rows;
    EXPECT_EQ(quoted, actual) << "docs/architecture.md, Counts: write | " << what << " | " << actual << " |";
  }
  EXPECT_GE(rows, named.size());
  for (const auto& [what, n] : named)
    EXPECT_TRUE(seen.count(what)) << "docs/architecture.md, Counts: no row | " << what << " | " << n << " |";
}

// README ("the three-room layout") and docs/architecture.md promise no source file over 600 lines:
// every C++, Python, shell and CMake file of the project's folders, counted here.
TEST(Docs, NoSourceFileIsOver600Lines) {
  constexpr std::size_t kMaxLines = 600;
  const fs::path root(SGLAB_SOURCE_DIR);
  const std::set<std::string> extensions = {".cpp", ".hpp", ".h", ".py", ".sh", ".cmake", ".sbatch"};
  std::size_t files = 0;
  for (const char* folder : {"core", "fit", "experiments", "runner", "frontend", "shader", "cli", "python", "tests",
                             "benchmarks", "plots", "scripts"}) {
    if (!fs::exists(root / folder)) continue;
    for (const auto& e : fs::recursive_directory_iterator(root / folder)) {
      const fs::path& p = e.path();
      if (!e.is_regular_file() || (!extensions.count(p.extension().string()) && p.filename() != "CMakeLists.txt"))
        continue;
      std::ifstream in(p);
      std::size_t lines = 0;
      for (std::string line; std::getline(in, line);) ++lines;
      ++files;
      EXPECT_LE(lines, kMaxLines) << fs::relative(p, root).string() << " has " << lines << " lines";
    }
  }
  std::printf("%zu source files, each at most %zu lines\n", files, kMaxLines);
  EXPECT_GT(files, 100u);
}

// Adding a fitted method: its header, its registry entry, its fit file, its entry in SGLAB_FITTERS
// (fit/CMakeLists.txt), docs/math.md. The list the build reads is the one fitters() returns, each
// entry's file defines its registration function, no other file of fit/ names it, and the recipe
// of docs/architecture.md names exactly these files.
TEST(Docs, FittedMethodRecipeIsTheBuildsList) {
  const std::string cmake = read_doc("fit/CMakeLists.txt");
  const std::size_t start = cmake.find("set(SGLAB_FITTERS");
  ASSERT_NE(start, std::string::npos) << "fit/CMakeLists.txt has no list SGLAB_FITTERS";
  std::vector<std::string> names;
  std::istringstream lines(cmake.substr(start + std::string("set(SGLAB_FITTERS").size()));
  for (std::string line; std::getline(lines, line);) {
    line = line.substr(0, line.find('#'));
    const bool last = line.find(')') != std::string::npos;
    std::istringstream words(line.substr(0, line.find(')')));
    for (std::string w; words >> w;) names.push_back(w);
    if (last) break;
  }
  EXPECT_EQ(names.size(), sglab::fit::fitters().size()) << "SGLAB_FITTERS against fitters()";
  for (const auto& name : names) {
    const std::string own = "fit/" + name + ".cpp";
    EXPECT_NE(read_doc(own).find("Fitter " + name + "_fitter() {"), std::string::npos)
        << own << " defines no " << name << "_fitter()";
    for (const auto& e : fs::directory_iterator(fs::path(SGLAB_SOURCE_DIR) / "fit")) {
      const std::string f = "fit/" + e.path().filename().string();
      if (f == own || (e.path().extension() != ".cpp" && e.path().extension() != ".hpp")) continue;
      EXPECT_EQ(read_doc(f).find(name + "_fitter"), std::string::npos)
          << f << " names " << name << "_fitter: SGLAB_FITTERS should";
    }
  }
  const std::string arch = read_doc("docs/architecture.md");
  const std::size_t recipe = arch.find("- **A method with fitted constants**");
  ASSERT_NE(recipe, std::string::npos) << "docs/architecture.md has no recipe for a method with fitted constants";
  const std::string text = arch.substr(recipe, arch.find("\n- **", recipe + 1) - recipe);
  // The first path of each numbered step.
  std::set<std::string> steps;
  const std::regex step(R"(\n  [0-9]+\. (`[^`]+`|docs/math\.md))");
  for (std::sregex_iterator it(text.begin(), text.end(), step), end; it != end; ++it) steps.insert((*it)[1].str());
  EXPECT_EQ(steps, (std::set<std::string>{"`core/include/sglab/NAME.hpp`", "`core/src/registry_core.cpp`",
                                          "`fit/NAME.cpp`", "`fit/CMakeLists.txt`", "docs/math.md"}))
      << "docs/architecture.md's recipe for a fitted method";
  EXPECT_NE(text.find("SGLAB_FITTERS"), std::string::npos);
}

// The sources sglab_unity compiles in batches of their own (the APART lists of experiments/ and
// fit/CMakeLists.txt) are exactly those that include a method's formula header, directly or through
// the project's headers: one outside the list would drag its whole batch into every rebuild after an
// edit of a method (docs/testing.md, "Rebuilding after a method's header"), and a listed one that no
// longer includes any only costs a batch.
std::set<std::string> apart_sources(const std::string& cmake_file, const std::string& target) {
  const std::string cmake = read_doc(cmake_file);
  const std::size_t start = cmake.find("sglab_unity(" + target + " ");
  EXPECT_NE(start, std::string::npos) << cmake_file << " has no sglab_unity(" << target;
  if (start == std::string::npos) return {};
  std::istringstream words(cmake.substr(start, cmake.find(')', start) - start));
  std::set<std::string> files;
  for (std::string w; words >> w;)
    if (w.size() > 4 && w.substr(w.size() - 4) == ".cpp") files.insert(w);
  return files;
}

// The project headers FILE includes with quotes, followed through those headers (as "sglab/x.hpp").
void quoted_includes(const fs::path& file, std::set<std::string>& seen) {
  static const std::vector<std::string> dirs = {
      "core/include", "core/render/include", "fit", "experiments", "frontend", "runner", "core/src"};
  const std::regex include(R"re(#include "([^"]+)")re");
  const std::string text = read_doc(fs::relative(file, SGLAB_SOURCE_DIR).string());
  for (std::sregex_iterator it(text.begin(), text.end(), include), end; it != end; ++it) {
    const std::string name = (*it)[1].str();
    if (!seen.insert(name).second) continue;
    // As the compiler looks: beside the including file first, then the include directories.
    if (const fs::path here = file.parent_path() / name; fs::is_regular_file(here)) {
      quoted_includes(here, seen);
      continue;
    }
    for (const auto& d : dirs)
      if (const fs::path p = fs::path(SGLAB_SOURCE_DIR) / d / name; fs::is_regular_file(p)) {
        quoted_includes(p, seen);
        break;
      }
  }
}

std::set<std::string> sources_including(const std::string& dir, const std::set<std::string>& headers) {
  std::set<std::string> out;
  for (const auto& e : fs::directory_iterator(fs::path(SGLAB_SOURCE_DIR) / dir)) {
    if (e.path().extension() != ".cpp") continue;
    std::set<std::string> seen;
    quoted_includes(e.path(), seen);
    for (const auto& h : headers)
      if (seen.count(h)) out.insert(e.path().filename().string());
  }
  return out;
}

TEST(Docs, SourcesWithMethodHeadersAreBatchedApart) {
  const std::set<std::string> diffuse = {"sglab/clamped_cosine.hpp",       "sglab/clamped_cosine_meder.hpp",
                                         "sglab/clamped_cosine_sglab.hpp", "sglab/hemispherical.hpp",
                                         "sglab/hemispherical_bounds.hpp", "sglab/hemispherical_meder.hpp"};
  std::set<std::string> every = diffuse;
  every.insert({"sglab/specular.hpp", "sglab/specular_sglab.hpp", "sglab/gaussian_ndf.hpp"});
  EXPECT_EQ(apart_sources("experiments/CMakeLists.txt", "sglab_experiments"), sources_including("experiments", every))
      << "experiments/CMakeLists.txt: sglab_unity's APART list against the experiments that include a method's header";
  EXPECT_EQ(apart_sources("fit/CMakeLists.txt", "sglab_fit"), sources_including("fit", diffuse))
      << "fit/CMakeLists.txt: sglab_unity's APART lists against the fits that include a diffuse method's header";
}

}  // namespace
