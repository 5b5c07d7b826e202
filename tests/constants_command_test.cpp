// `--constants` end to end through the built binary (SGLAB_EXE): a hand-written record changes what
// `sglab eval` prints by what the formula predicts and is named on stderr; directories and
// `published` compose in order; every malformed set exits 2 naming the file and the key, and
// writes no output.
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "test_util.hpp"

namespace {

namespace fs = std::filesystem;

using Outcome = sglab::test::CommandResult;
const auto read = sglab::test::read_file;

class ConstantsCommand : public sglab::test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    write("in.csv", "sharpness,cosine\n3,0.25\n");
  }
  void write(const std::string& name, const std::string& text) const {
    fs::create_directories(path(name).parent_path());
    std::ofstream(path(name)) << text;
  }
  // eval clamped-cosine METHOD at (λ = 3, c = 0.25) with the given --constants arguments.
  double value(const std::string& method, const std::string& constants, Outcome* run_out = nullptr) const {
    const Outcome run = sglab(
        fmt::format("eval clamped-cosine --method {} --in '{}' {}", method, path("in.csv").string(), constants));
    EXPECT_EQ(run.status, 0) << run.err;
    if (run_out) *run_out = run;
    const std::string last = run.out.substr(run.out.rfind(',') + 1);
    return std::strtod(last.c_str(), nullptr);
  }
};

// π/A(λ_d)·2πG(ξ; n, λλ_d/(λ+λ_d))/(λ + λ_d), A(λ) = 2π(1 − e^{−2λ})/λ, at λ = 3, c = 0.25.
double sg_cosine(double lambda_d) {
  const double pi = std::acos(-1.0), l = 3, c = 0.25;
  const double a = 2 * pi * (1 - std::exp(-2 * lambda_d)) / lambda_d;
  return pi / a * 2 * pi * std::exp(l * lambda_d / (l + lambda_d) * (c - 1)) / (l + lambda_d);
}

TEST_F(ConstantsCommand, HandWrittenRecordChangesTheValueAsTheFormulaPredicts) {
  write("ld.json", R"({"fit": "lambda-d", "parameters": {"lambda_d": 3.25}})");
  Outcome run;
  EXPECT_NEAR(value("sg-cosine", ""), sg_cosine(2), 1e-14);
  EXPECT_NEAR(value("sg-cosine", fmt::format("--constants '{}'", path("ld.json").string()), &run), sg_cosine(3.25),
              1e-14);
  // stderr names the constant, its value and where it came from.
  EXPECT_NE(run.err.find("lambda_d = 3.25"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("ld.json"), std::string::npos) << run.err;
  // Later sets override earlier ones; `published` resets.
  write("dir/ld.json", R"({"fit": "lambda-d", "parameters": {"lambda_d": 1.5}})");
  EXPECT_NEAR(value("sg-cosine",
                    fmt::format("--constants '{}' --constants '{}'", path("ld.json").string(), path("dir").string())),
              sg_cosine(1.5), 1e-14);
  EXPECT_NEAR(value("sg-cosine", fmt::format("--constants '{}' --constants published", path("ld.json").string())),
              sg_cosine(2), 1e-14);
}

TEST_F(ConstantsCommand, Tokuyoshi2024TakesRefitCoefficients) {
  // t(λ) = λ√(½((λ + A)λ + B)/(((λ + C)λ + D)λ + E)): scaling A…E as (A, B, C, D, E) → (A, B·k, C, D, E·k)
  // changes t at λ = 3, so the value changes; the published values give the published result.
  write("t24.json", R"({"fit": "tokuyoshi2024-t", "parameters": {"A": 2.7360831611272558, "B": 17.021297781741875,
      "C": 4.0100826728510421, "D": 15.219156263147211, "E": 76.087896272360737}})");
  EXPECT_EQ(value("tokuyoshi2024", ""),
            value("tokuyoshi2024", fmt::format("--constants '{}'", path("t24.json").string())));
  write("t24b.json", R"({"fit": "tokuyoshi2024-t", "parameters": {"A": 3, "B": 20, "C": 4, "D": 15, "E": 90}})");
  EXPECT_NE(value("tokuyoshi2024", ""),
            value("tokuyoshi2024", fmt::format("--constants '{}'", path("t24b.json").string())));
}

// `sglab render --constants DIR` renders with the record's λ_d, and the stats JSON says so.
TEST_F(ConstantsCommand, RenderUsesTheSetsLambdaDAndSaysSo) {
  write("fits/lambda-d.json",
        R"({"fit": "lambda-d", "objective": "test objective", "parameters": {"lambda_d": 3.25}})");
  const std::string scene = std::string(SGLAB_SOURCE_DIR) + "/scenes/cornell-glossy.json";
  const Outcome run = sglab(
      fmt::format("render '{}' --width 16 --height 16 --rsm 8 --out '{}' --stats '{}' --constants '{}'", scene,
                  path("r.exr").string(), path("r.json").string(), path("fits").string()));
  ASSERT_EQ(run.status, 0) << run.err;
  const std::string stats = read(path("r.json"));
  EXPECT_NE(stats.find("\"lambda_d\": 3.25"), std::string::npos) << stats;
  EXPECT_NE(stats.find("lambda-d.json: fit lambda-d, objective test objective"), std::string::npos) << stats;
  // A bad set stops the render before anything is written.
  write("bad/lambda-d.json", R"({"fit": "lambda-d", "parameters": {"lambda_d": 0}})");
  const Outcome bad = sglab(fmt::format("render '{}' --width 16 --height 16 --rsm 8 --out '{}' --constants '{}'", scene,
                                        path("bad.exr").string(), path("bad").string()));
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("parameters.lambda_d"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(path("bad.exr")));
}

// `sglab sweep render --vary vsgl.lambda_d=NUMBER,RECORD` renders one row per λ_d, a number or a
// lambda-d fit record (vsgl.lambda_d is a render option, not a scene field).
TEST_F(ConstantsCommand, RenderSweepVariesLambdaDOverNumbersAndRecords) {
  write("ld.json", R"({"fit": "lambda-d", "parameters": {"lambda_d": 3.25}})");
  const std::string scene = std::string(SGLAB_SOURCE_DIR) + "/scenes/cornell-glossy.json";
  const Outcome run = sglab(
      fmt::format("sweep render --scene '{}' --vary vsgl.lambda_d=2,'{}' --vsgl two --width 16 --height 16 "
                  "--rsm 8 --out '{}' --table ld",
                  scene, path("ld.json").string(), path("sweep").string()));
  ASSERT_EQ(run.status, 0) << run.err;
  const std::string table = read(path("sweep/ld.md"));
  EXPECT_NE(table.find("| 2 | two |"), std::string::npos) << table;
  EXPECT_NE(table.find("| 3.25 | two |"), std::string::npos) << table;
}

TEST_F(ConstantsCommand, MalformedSetsAreRejectedNamingFileAndKey) {
  struct Case {
    std::string name, text, key;
  };
  const Case cases[] = {
      {"unknown_fit.json", R"({"fit": "lambda-x", "parameters": {"lambda_d": 2}})", "'fit'"},
      {"unknown_param.json", R"({"fit": "lambda-d", "parameters": {"lambda_d": 2, "mu": 1}})", "parameters.mu"},
      {"missing_param.json", R"({"fit": "tokuyoshi2024-t", "parameters": {"A": 1, "B": 1, "C": 1, "D": 1}})",
       "parameters.E"},
      {"not_number.json", R"({"fit": "lambda-d", "parameters": {"lambda_d": "2"}})", "parameters.lambda_d"},
      {"negative.json", R"({"fit": "lambda-d", "parameters": {"lambda_d": -1}})", "parameters.lambda_d"},
      {"negative_sharpness.json", R"({"fit": "cosine-lobe-sg", "parameters": {"amplitude": 1, "sharpness": -2}})",
       "parameters.sharpness"},
      {"no_parameters.json", R"({"fit": "lambda-d"})", "'parameters'"},
      {"not_json.json", "{fit: lambda-d", "not valid JSON"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    write(c.name, c.text);
    fs::remove(path("out.csv"));
    const Outcome run = sglab(
        fmt::format("eval clamped-cosine --method sg-cosine --in '{}' --out '{}' --constants '{}'",
                    path("in.csv").string(), path("out.csv").string(), path(c.name).string()));
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_NE(run.err.find(c.name), std::string::npos) << run.err;
    EXPECT_NE(run.err.find(c.key), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(path("out.csv")));
  }
  const Outcome missing = sglab(fmt::format("eval clamped-cosine --method sg-cosine --in '{}' --constants '{}'",
                                            path("in.csv").string(), path("absent.json").string()));
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("absent.json"), std::string::npos) << missing.err;
}

}  // namespace
