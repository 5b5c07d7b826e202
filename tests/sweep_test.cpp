// The sweep runner of runner/sweep.hpp, through its library functions: --shard parsing,
// sharding partitions the points exactly, the per-point CSV is exactly the rows of every point in
// order, resume computes only what an interrupted run did not finish and gives the same bytes,
// merge joins shards into the unsharded bytes and refuses missing points, duplicated points,
// mismatched headers and mismatched grids, and the error statistics on hand-checkable numbers.
// The toy sweeps here compute their rows from the point index by formulas the test spells out
// again, independently, for the expected output.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "input_error.hpp"
#include "sweep.hpp"
#include "test_util.hpp"

namespace {

namespace fs = std::filesystem;
using sglab::runner::InputError;
using sglab::runner::parse_shard;
using sglab::runner::Shard;
using sglab::runner::SweepDefinition;
using sglab::runner::SweepRow;
using sglab::runner::SweepRunOptions;

using sglab::test::read_file;

// A fresh directory per test (dir_), removed afterwards.
class SweepTest : public sglab::test::TempDirTest {};

// Toy sweep: point k has 1 + k % 3 rows (j = 0, 1, …): x = k·k + j, label "p<k>,<j>" (a comma:
// the runner must quote it). Records every point it computes.
struct Toy {
  std::size_t n = 23;
  std::string grid = "toy grid v1";
  std::mutex mutex;
  std::multiset<std::size_t> computed;
  std::atomic<int> calls{0};
  int fail_on_call = -1;  // throw on this call (1-based); -1: never

  SweepDefinition definition() {
    SweepDefinition d;
    d.name = "toy";
    d.args = {"sweep", "toy"};
    d.grid = grid;
    d.point_count = n;
    d.columns = {"x", "label"};
    d.compute = [this](std::size_t k) {
      if (++calls == fail_on_call) throw std::runtime_error("toy: interrupted");
      std::vector<SweepRow> rows;
      for (std::size_t j = 0; j < 1 + k % 3; ++j) {
        std::string label = "p";  // appends: GCC 12 reports a false -Wrestrict on `"p" + std::string&&`
        label += std::to_string(k);
        label += ",";
        label += std::to_string(j);
        rows.push_back({std::to_string(k * k + j), label});
      }
      std::lock_guard lock(mutex);
      computed.insert(k);
      return rows;
    };
    d.describe = [](std::size_t k) { return "toy point " + std::to_string(k); };
    return d;
  }
};

// The per-point CSV the toy sweep must produce for the points of `shard`, written out by hand.
std::string expected_toy_csv(std::size_t n, const Shard& shard = {}) {
  std::string s = "point,x,label\n";
  for (std::size_t k = 0; k < n; ++k) {
    if (k % shard.count != shard.index) continue;
    for (std::size_t j = 0; j < 1 + k % 3; ++j)
      s += std::to_string(k) + "," + std::to_string(k * k + j) + ",\"p" + std::to_string(k) + "," + std::to_string(j) +
           "\"\n";
  }
  return s;
}

SweepRunOptions quiet(const fs::path& dir, Shard shard = {}) { return {.out_dir = dir, .shard = shard, .quiet = true}; }

// ---- --shard ------------------------------------------------------------------------------------

TEST(ParseShard, AcceptsIOfN) {
  const Shard a = parse_shard("0/1");
  EXPECT_EQ(a.index, 0u);
  EXPECT_EQ(a.count, 1u);
  const Shard b = parse_shard("11/12");
  EXPECT_EQ(b.index, 11u);
  EXPECT_EQ(b.count, 12u);
  EXPECT_EQ(b.text(), "11/12");
  EXPECT_EQ(b.file_suffix(), ".shard-11-of-12");
  EXPECT_EQ(a.file_suffix(), "");
}

TEST(ParseShard, RejectsBadValuesNamingThem) {
  for (const std::string bad : {"0/0", "3/2", "2/2", "x", "", "1/", "/2", "-1/2", "1/-2", "1/2/3", "1.0/2", " 1/2",
                                "1/2x", "99999999999999999999999/2"}) {
    try {
      parse_shard(bad);
      ADD_FAILURE() << "accepted --shard '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("'" + bad + "'"), std::string::npos) << e.what();
    }
  }
}

TEST(ShardPoints, PartitionExactly) {
  for (std::size_t n : {0u, 1u, 7u, 100u})
    for (std::size_t count = 1; count <= 6; ++count) {
      std::vector<int> seen(n, 0);
      for (std::size_t i = 0; i < count; ++i) {
        const auto points = sglab::runner::shard_points(n, {i, count});
        EXPECT_TRUE(std::is_sorted(points.begin(), points.end()));
        for (std::size_t k : points) {
          ASSERT_LT(k, n);
          EXPECT_EQ(k % count, i);
          ++seen[k];
        }
      }
      for (std::size_t k = 0; k < n; ++k)
        EXPECT_EQ(seen[k], 1) << "point " << k << " of " << n << ", " << count << " shards";
    }
}

// ---- running ------------------------------------------------------------------------------------

TEST_F(SweepTest, WritesEveryPointInOrderOnce) {
  Toy toy;
  const auto r = sglab::runner::run_sweep(toy.definition(), quiet(dir_));
  EXPECT_EQ(read_file(r.points_csv), expected_toy_csv(toy.n));
  EXPECT_EQ(r.points_csv, dir_ / "toy_points.csv");
  EXPECT_TRUE(fs::exists(dir_ / "toy_sweep.json"));
  EXPECT_FALSE(fs::exists(sglab::runner::sweep_checkpoint_path(dir_, "toy", {})));
  EXPECT_EQ(r.computed, toy.n);
  EXPECT_EQ(r.resumed, 0u);
  EXPECT_EQ(toy.computed.size(), toy.n);
  for (std::size_t k = 0; k < toy.n; ++k) EXPECT_EQ(toy.computed.count(k), 1u);

  // Finished: a second run computes nothing and leaves the bytes as they were.
  Toy again;
  const auto r2 = sglab::runner::run_sweep(again.definition(), quiet(dir_));
  EXPECT_EQ(r2.computed, 0u);
  EXPECT_EQ(r2.resumed, toy.n);
  EXPECT_EQ(again.calls, 0);
  EXPECT_EQ(read_file(r2.points_csv), expected_toy_csv(toy.n));

  // A changed grid is a different sweep: recomputed.
  Toy changed;
  changed.grid = "toy grid v2";
  EXPECT_EQ(sglab::runner::run_sweep(changed.definition(), quiet(dir_)).computed, toy.n);
}

// `sglab reproduce --force` runs its steps in a fresh RunContext: in it a finished sweep is computed again
// (not found finished), outside it the same call computes nothing.
TEST_F(SweepTest, FreshRunRecomputesAFinishedSweep) {
  Toy first;
  EXPECT_EQ(sglab::runner::run_sweep_command(first.definition(), dir_.string(), "", 1, false, {}).computed, first.n);
  Toy again;
  EXPECT_EQ(sglab::runner::run_sweep_command(again.definition(), dir_.string(), "", 1, false, {}).computed, 0u);
  Toy forced;
  {
    const auto r = sglab::runner::run_sweep_command(forced.definition(), dir_.string(), "", 1, false, {.fresh = true});
    EXPECT_EQ(r.computed, forced.n);
    EXPECT_EQ(r.resumed, 0u);
    EXPECT_EQ(read_file(r.points_csv), expected_toy_csv(forced.n));
  }
  Toy after;
  EXPECT_EQ(sglab::runner::run_sweep_command(after.definition(), dir_.string(), "", 1, false, {}).computed, 0u);
}

TEST_F(SweepTest, ShardsWriteTheirOwnPoints) {
  Toy toy;
  for (std::size_t i = 0; i < 4; ++i) {
    const auto r = sglab::runner::run_sweep(toy.definition(), quiet(dir_, {i, 4}));
    EXPECT_TRUE(r.sharded);
    EXPECT_EQ(r.points_csv, dir_ / ("toy_points.shard-" + std::to_string(i) + "-of-4.csv"));
    EXPECT_EQ(read_file(r.points_csv), expected_toy_csv(toy.n, {i, 4}));
  }
  // Together the four shards computed every point exactly once.
  for (std::size_t k = 0; k < toy.n; ++k) EXPECT_EQ(toy.computed.count(k), 1u) << "point " << k;
}

TEST_F(SweepTest, ResumeSkipsFinishedPointsAndGivesIdenticalOutput) {
  // An uninterrupted run, for the bytes to compare with.
  Toy whole;
  const std::string uninterrupted = read_file(
      sglab::runner::run_sweep(whole.definition(), quiet(dir_ / "whole")).points_csv);

  // Interrupted on the 9th call; one thread, a checkpoint after every point.
  Toy first;
  first.fail_on_call = 9;
  SweepRunOptions o = quiet(dir_ / "run");
  o.threads = 1;
  o.checkpoint_seconds = 0;
  EXPECT_THROW(sglab::runner::run_sweep(first.definition(), o), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir_ / "run" / "toy_points.csv"));  // no partial output
  EXPECT_TRUE(fs::exists(sglab::runner::sweep_checkpoint_path(dir_ / "run", "toy", {})));
  const std::set<std::size_t> finished(first.computed.begin(), first.computed.end());
  EXPECT_EQ(finished.size(), 8u);

  Toy second;
  const auto r = sglab::runner::run_sweep(second.definition(), o);
  EXPECT_EQ(r.resumed, finished.size());
  EXPECT_EQ(r.computed, whole.n - finished.size());
  for (std::size_t k : second.computed) EXPECT_EQ(finished.count(k), 0u) << "point " << k << " was computed twice";
  for (std::size_t k = 0; k < whole.n; ++k)
    EXPECT_EQ(finished.count(k) + second.computed.count(k), 1u) << "point " << k;
  EXPECT_EQ(read_file(r.points_csv), uninterrupted);
  EXPECT_EQ(uninterrupted, expected_toy_csv(whole.n));
  EXPECT_FALSE(fs::exists(sglab::runner::sweep_checkpoint_path(dir_ / "run", "toy", {})));
}

TEST_F(SweepTest, CheckpointOfAnotherGridIsIgnored) {
  Toy first;
  first.fail_on_call = 5;
  SweepRunOptions o = quiet(dir_);
  o.threads = 1;
  o.checkpoint_seconds = 0;
  EXPECT_THROW(sglab::runner::run_sweep(first.definition(), o), std::runtime_error);
  Toy other;
  other.grid = "another grid";
  const auto r = sglab::runner::run_sweep(other.definition(), o);
  EXPECT_EQ(r.resumed, 0u);
  EXPECT_EQ(r.computed, other.n);
}

TEST_F(SweepTest, DamagedOutputIsRecomputedNotTrusted) {
  Toy toy;
  sglab::runner::run_sweep(toy.definition(), quiet(dir_));
  std::ofstream(dir_ / "toy_sweep.json") << "{ not json";
  Toy again;
  EXPECT_EQ(sglab::runner::run_sweep(again.definition(), quiet(dir_)).computed, toy.n);
  // A per-point CSV with a point missing (a row deleted by hand) is not finished either.
  std::string text = read_file(dir_ / "toy_points.csv");
  text.erase(text.find("\n0,") + 1, text.find("\n1,") - text.find("\n0,"));
  std::ofstream(dir_ / "toy_points.csv", std::ios::binary) << text;
  Toy third;
  EXPECT_EQ(sglab::runner::run_sweep(third.definition(), quiet(dir_)).computed, toy.n);
  EXPECT_EQ(read_file(dir_ / "toy_points.csv"), expected_toy_csv(toy.n));
}

TEST_F(SweepTest, RejectsRowsOfTheWrongWidth) {
  Toy toy;
  SweepDefinition d = toy.definition();
  d.compute = [](std::size_t) { return std::vector<SweepRow>{{"only one field"}}; };
  EXPECT_THROW(sglab::runner::run_sweep(d, quiet(dir_)), std::logic_error);
  d.compute = [](std::size_t) { return std::vector<SweepRow>{}; };
  EXPECT_THROW(sglab::runner::run_sweep(d, quiet(dir_)), std::logic_error);
}

// ---- merging ------------------------------------------------------------------------------------

// Runs shards `which` of `count` of the toy sweep into dir.
void run_toy_shards(const fs::path& dir, std::size_t count, const std::vector<std::size_t>& which,
                    const std::string& grid = "toy grid v1") {
  for (std::size_t i : which) {
    Toy toy;
    toy.grid = grid;
    sglab::runner::run_sweep(toy.definition(), quiet(dir, {i, count}));
  }
}

std::string merge_error(const std::vector<fs::path>& inputs, const fs::path& out) {
  try {
    sglab::runner::merge_sweep_shards(inputs, out);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST_F(SweepTest, MergeJoinsShardsIntoTheUnshardedBytes) {
  run_toy_shards(dir_ / "a", 3, {0, 2});
  run_toy_shards(dir_ / "b", 3, {1});
  const auto merged = sglab::runner::merge_sweep_shards({dir_ / "a", dir_ / "b"}, dir_ / "out");
  ASSERT_EQ(merged.size(), 1u);
  EXPECT_EQ(merged[0].name, "toy");
  EXPECT_EQ(merged[0].shards, 3u);
  EXPECT_EQ(merged[0].args, (std::vector<std::string>{"sweep", "toy"}));
  EXPECT_EQ(read_file(dir_ / "out" / "toy_points.csv"), expected_toy_csv(23));
  // The merged output is what an unsharded run writes: that run finds it finished.
  Toy toy;
  const auto r = sglab::runner::run_sweep(toy.definition(), quiet(dir_ / "out"));
  EXPECT_EQ(r.computed, 0u);
  EXPECT_EQ(toy.calls, 0);
}

TEST_F(SweepTest, MergeRefusesAMissingPoint) {
  run_toy_shards(dir_, 3, {0, 2});
  const std::string e = merge_error({dir_}, dir_ / "out");
  EXPECT_NE(e.find("missing"), std::string::npos) << e;
  EXPECT_NE(e.find("first: 1, 4, 7"), std::string::npos) << e;  // the points k % 3 == 1
  EXPECT_FALSE(fs::exists(dir_ / "out" / "toy_points.csv"));
}

// Rewrites a shard's per-point CSV and updates its manifest's record of it (row count and
// fingerprint), as a deliberate forger would: the checks behind the fingerprint still hold.
void forge_shard_points(const fs::path& csv, const std::string& text) {
  std::ofstream(csv, std::ios::binary) << text;
  std::string name = csv.filename().string();
  name.replace(name.find("_points"), 7, "_sweep");
  name.replace(name.rfind(".csv"), 4, ".json");
  const fs::path manifest = csv.parent_path() / name;
  auto m = nlohmann::json::parse(read_file(manifest));
  std::istringstream in(text);
  m["rows"] = sglab::runner::read_csv(in, csv.string()).rows.size();
  m["points_fnv1a"] = sglab::runner::fnv1a_hex(text);
  std::ofstream(manifest) << m.dump();
}

TEST_F(SweepTest, MergeRefusesADuplicatedPoint) {
  run_toy_shards(dir_ / "a", 2, {0, 1});
  run_toy_shards(dir_ / "b", 2, {1});  // shard 1 again, elsewhere
  const std::string e = merge_error({dir_ / "a", dir_ / "b"}, dir_ / "out");
  EXPECT_NE(e.find("point 1 appears twice"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "toy_points.csv"));

  // A point repeated inside one shard's file (rows not contiguous) is a duplicate too.
  const fs::path shard0 = dir_ / "a" / "toy_points.shard-0-of-2.csv";
  std::string text = read_file(shard0);
  text += "0,0,\"p0,0\"\n";
  forge_shard_points(shard0, text);
  const std::string e2 = merge_error({dir_ / "a"}, dir_ / "out");
  EXPECT_NE(e2.find("point 0 appears twice"), std::string::npos) << e2;
}

TEST_F(SweepTest, MergeRefusesAHeaderMismatch) {
  run_toy_shards(dir_, 2, {0, 1});
  const fs::path shard1 = dir_ / "toy_points.shard-1-of-2.csv";
  std::string text = read_file(shard1);
  text.replace(0, text.find('\n'), "point,x,name");
  forge_shard_points(shard1, text);
  const std::string e = merge_error({dir_}, dir_ / "out");
  EXPECT_NE(e.find("header mismatch"), std::string::npos) << e;
  EXPECT_NE(e.find("'name'"), std::string::npos) << e;
  EXPECT_NE(e.find("shard-1-of-2"), std::string::npos) << e;
}

TEST_F(SweepTest, MergeRefusesShardsOfDifferentGrids) {
  run_toy_shards(dir_ / "a", 2, {0});
  run_toy_shards(dir_ / "b", 2, {1}, "another grid");
  const std::string e = merge_error({dir_ / "a", dir_ / "b"}, dir_ / "out");
  EXPECT_NE(e.find("'grid' differs"), std::string::npos) << e;
}

TEST_F(SweepTest, MergeRefusesAPointOutsideItsShard) {
  run_toy_shards(dir_, 2, {0, 1});
  const fs::path shard0 = dir_ / "toy_points.shard-0-of-2.csv";
  std::string text = read_file(shard0);
  text += "23,0,x\n";  // 23 ≥ n
  std::ofstream(shard0, std::ios::binary) << text;
  // An edited CSV differs from its manifest's record, and is refused as such …
  EXPECT_NE(merge_error({dir_}, dir_ / "out").find("differ from what"), std::string::npos);
  // … and one whose manifest was edited to match is still checked row by row.
  forge_shard_points(shard0, text);
  EXPECT_NE(merge_error({dir_}, dir_ / "out").find("point '23' is not an index"), std::string::npos);
}

TEST_F(SweepTest, MergeNeedsShards) {
  EXPECT_NE(merge_error({dir_}, dir_ / "out").find("no shard manifest"), std::string::npos);
  // Names near NAME_sweep.shard-i-of-N.json that are not one are not taken for a manifest …
  for (const char* near :
       {"_sweep.shard-0-of-2.json", "toy_sweep.shard-0-of-2.json.bak", "toy_sweep.shard-a-of-2.json",
        "toy_sweep.shard-0-of-.json", "toy_sweep.shard--of-2.json", "toy_sweep.shard-0-2.json",
        "toy_sweep.shard-0-of-2json", "toy_sweep-shard-0-of-2.json", "toy_sweep.shard-0-of-2-of-3.json"})
    std::ofstream(dir_ / near) << "{}";
  EXPECT_NE(merge_error({dir_}, dir_ / "out").find("no shard manifest"), std::string::npos);
  // … while a NAME that itself holds the pattern is one (its last occurrence is the shard's).
  std::ofstream(dir_ / "a_sweep.shard-0-of-2_sweep.shard-1-of-2.json") << "[]";
  EXPECT_NE(merge_error({dir_}, dir_ / "out").find("not a sweep manifest"), std::string::npos);
  EXPECT_NE(merge_error({dir_ / "nonexistent"}, dir_ / "out").find("neither a directory nor a file"),
            std::string::npos);
}

// ---- numbers ------------------------------------------------------------------------------------

TEST(CsvNumber, NaNIsEmptyAndNumbersRoundTrip) {
  EXPECT_EQ(sglab::runner::csv_number(std::numeric_limits<double>::quiet_NaN()), "");
  EXPECT_EQ(sglab::runner::csv_number(0.1), "0.1");
}

}  // namespace
