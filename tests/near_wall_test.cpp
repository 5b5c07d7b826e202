// `sglab near-wall` end to end (the 2022 poster's near-wall figure): every pixel of the dump must
// equal `sglab eval clamped-cosine --method M` at the same (λ, c), for the reference and for every
// compared method; the compared methods must be exactly the registry's clamped-cosine methods
// (from `sglab eval --list --json`, so a method added to the registry appears with no edit); the
// table's mean/max SMAPE and pixel counts must be those recomputed here from the dump, ranked by
// mean; bad input exits 2 and writes nothing.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_util.hpp"

namespace {

namespace fs = std::filesystem;

using sglab::test::read_file;

// A plain CSV (no quoted fields: the near-wall outputs have none); lines starting with '#' skipped.
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::size_t col(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return std::size_t(it - header.begin());
  }
};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream s(line);
  std::string f;
  while (std::getline(s, f, ',')) out.push_back(f);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

Table read_table(const fs::path& p) {
  Table t;
  std::istringstream in(read_file(p));
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (t.header.empty()) t.header = split(line);
    else t.rows.push_back(split(line));
  }
  return t;
}

class NearWall : public sglab::test::TempDirTest {
 protected:
  // The exit status of `sglab ARGS`; its standard output is kept in out_, its standard error in *err.
  int sglab(const std::string& args, std::string* err = nullptr) {
    const auto r = TempDirTest::sglab(args);
    out_ = r.out;
    if (err) *err = r.err;
    return r.status;
  }
  std::string scene() const { return std::string(SGLAB_SOURCE_DIR) + "/scenes/sg-light-near-wall-poster.json"; }
  std::string out_;
};

TEST_F(NearWall, EveryPixelIsEvalAndTheTableIsTheDumps) {
  std::string err;
  ASSERT_EQ(sglab(fmt::format("near-wall --scene '{}' --width 20 --height 15 --dump '{}' --tables-dir '{}'", scene(),
                              path("dump.csv").string(), path("tables").string()),
                  &err),
            0)
      << err;
  const Table dump = read_table(path("dump.csv"));
  ASSERT_GT(dump.rows.size(), 100u);  // most of the 300 pixels see the wall or the floor

  // The compared methods are the registry's clamped-cosine methods, all of them.
  ASSERT_EQ(sglab("eval --list --json"), 0);
  const auto list = nlohmann::json::parse(out_);
  std::vector<std::string> registry;
  std::string reference;
  for (const auto& q : list.at("quantities"))
    if (q.at("name") == "clamped-cosine") {
      reference = q.at("reference_method").get<std::string>();
      for (const auto& m : q.at("methods")) registry.push_back(m.at("name").get<std::string>());
    }
  ASSERT_FALSE(registry.empty());
  const std::vector<std::string> columns(dump.header.begin() + 6, dump.header.end());
  EXPECT_EQ(columns.front(), reference);
  std::vector<std::string> sorted_columns = columns, sorted_registry = registry;
  std::sort(sorted_columns.begin(), sorted_columns.end());
  std::sort(sorted_registry.begin(), sorted_registry.end());
  EXPECT_EQ(sorted_columns, sorted_registry);

  // Every pixel of every method = `sglab eval clamped-cosine` at the same (λ, c), to the last bit
  // (both print round-trip digits of the same double).
  for (const std::string& m : registry) {
    ASSERT_EQ(sglab(fmt::format("eval clamped-cosine --method '{}' --in '{}' --out '{}'", m, path("dump.csv").string(),
                                path("eval.csv").string()),
                    &err),
              0)
        << m << ": " << err;
    const Table eval = read_table(path("eval.csv"));
    ASSERT_EQ(eval.rows.size(), dump.rows.size());
    const std::size_t mine = dump.col(m), theirs = eval.col("value");
    for (std::size_t r = 0; r < dump.rows.size(); ++r)
      ASSERT_EQ(std::stod(dump.rows[r][mine]), std::stod(eval.rows[r][theirs]))
          << m << " at pixel (" << dump.rows[r][0] << ", " << dump.rows[r][1] << "), λ = " << dump.rows[r][3]
          << ", c = " << dump.rows[r][4];
  }

  // The table: mean/max SMAPE and pixel counts recomputed from the dump, ranked by mean.
  const Table table = read_table(path("tables/near_wall_smape.csv"));
  EXPECT_EQ(table.header, (std::vector<std::string>{"method", "mean_smape", "max_smape", "pixels"}));
  ASSERT_EQ(table.rows.size(), registry.size() - 1);
  const std::size_t ref = dump.col(reference);
  double last_mean = -1;
  for (const auto& row : table.rows) {
    const std::size_t c = dump.col(row[0]);
    double sum = 0, max = 0;
    std::size_t n = 0;
    for (const auto& p : dump.rows) {
      if (p[c].empty()) continue;  // outside the method's domain
      const double v = std::stod(p[c]), r = std::stod(p[ref]);
      const double s = std::fabs(v) + std::fabs(r) > 0 ? 2 * std::fabs(v - r) / (std::fabs(v) + std::fabs(r)) : 0.0;
      sum += s;
      max = std::max(max, s);
      ++n;
    }
    EXPECT_EQ(std::stoul(row[3]), n) << row[0];
    EXPECT_NEAR(std::stod(row[1]), sum / double(n), 1e-12) << row[0];
    EXPECT_EQ(std::stod(row[2]), max) << row[0];
    EXPECT_LE(std::stod(row[2]), 2.0) << row[0];
    EXPECT_GE(std::stod(row[1]), last_mean) << row[0] << ": the table is not ranked by mean SMAPE";
    last_mean = std::stod(row[1]);
  }
}

TEST_F(NearWall, BadInputExitsTwoAndWritesNothing) {
  for (const char* bad : {"--set sg_light.sharpness=-1", "--set sg_light.distance=0", "--set 'sg_light.axis=[0,0,0]'",
                          "--set sg_light.colour=1", "--sweep-distance 0.1,-0.1", "--sweep-width 0"}) {
    std::string err;
    EXPECT_EQ(sglab(fmt::format("near-wall --scene '{}' --width 8 --height 6 {} --dump '{}' --tables-dir '{}'", scene(),
                                bad, path("dump.csv").string(), path("tables").string()),
                    &err),
              2)
        << bad << ": " << err;
    EXPECT_FALSE(err.empty()) << bad;
    EXPECT_FALSE(fs::exists(path("dump.csv"))) << bad;
    EXPECT_FALSE(fs::exists(path("tables"))) << bad;
  }
}

}  // namespace
