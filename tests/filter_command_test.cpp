// `sglab filter` and `sglab filter-sweep` end to end (issue #7, item 3): run the built binary
// (SGLAB_EXE) on a tiny scene; check the EXR layers, the stats JSON and the sweep's tables with
// their command header; every bad input exits with status 2, names the option or field, and
// writes nothing.
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sglab/render/exr.hpp"

namespace {

namespace fs = std::filesystem;

struct Result {
  int status = -1;
  std::string out, err;
};

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

const char* kTinyScene = R"({
  "camera": {"position": [0, 1, 2.5], "look_at": [0, 0.4, 0], "fov": 50, "width": 16, "height": 12},
  "light": {"target": [0, 0.3, -0.6], "direction": [0, -0.6, -1], "distance": 1.2, "cone_angle": 35, "falloff": 4, "power": 5},
  "objects": [
    {"name": "floor", "type": "rectangle", "corner": [-1, 0, -1], "edge_u": [0, 0, 2], "edge_v": [2, 0, 0],
     "material": {"albedo": 0.4, "f0": 0.5, "roughness": 0.3}},
    {"name": "wall", "type": "rectangle", "corner": [-1, 0, -1], "edge_u": [2, 0, 0], "edge_v": [0, 2, 0],
     "material": {"albedo": [0.7, 0.6, 0.5]}}
  ]
})";

class FilterCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "sglab-filter-test-XXXXXX").string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
    std::ofstream(path("scene.json")) << kTinyScene;
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path path(const std::string& name) const { return dir_ / name; }
  Result sglab(const std::string& args) const {
    const std::string command = fmt::format("'{}' {} > '{}' 2> '{}'", SGLAB_EXE, args, path("stdout").string(), path("stderr").string());
    const int raw = std::system(command.c_str());
    Result r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = read_file(path("stdout"));
    r.err = read_file(path("stderr"));
    return r;
  }
  Result filter(const std::string& extra) const {
    return sglab(fmt::format("filter '{}' --out '{}' --stats '{}' --rsm 8 --quiet {}", path("scene.json").string(),
                             path("out.exr").string(), path("stats.json").string(), extra));
  }
  fs::path dir_;
};

TEST_F(FilterCommand, WritesLayersAndStats) {
  const Result r = filter("--weights lobe --scale 2 --beta 10 --kappa 50 --nu 0.3");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto image = sglab::render::read_exr(path("out.exr").string());
  EXPECT_EQ(image.width, 16);
  EXPECT_EQ(image.height, 12);
  for (const char* layer : {"upsampled", "reference", "error", "low_res"})
    for (const char* c : {"R", "G", "B"}) EXPECT_TRUE(image.channels.count(std::string(layer) + "." + c)) << layer << c;
  double energy = 0;
  for (const char* c : {"R", "G", "B"}) {
    const auto& e = image.channels.at(std::string("error.") + c);
    const auto& v = image.channels.at(std::string("upsampled.") + c);
    const auto& ref = image.channels.at(std::string("reference.") + c);
    for (std::size_t k = 0; k < e.size(); ++k) {
      EXPECT_NEAR(e[k], v[k] - ref[k], 1e-6 * (std::fabs(v[k]) + std::fabs(ref[k])) + 1e-30);
      energy += ref[k];
    }
  }
  EXPECT_GT(energy, 0);
  const std::string command = image.attributes.at("sglab_command");
  EXPECT_NE(command.find("sglab filter"), std::string::npos);
  EXPECT_NE(command.find("--weights lobe"), std::string::npos);
  EXPECT_NE(command.find("--beta 10"), std::string::npos);

  const auto stats = nlohmann::json::parse(read_file(path("stats.json")));
  EXPECT_EQ(stats.at("weights"), "lobe");
  EXPECT_EQ(stats.at("scale"), 2);
  EXPECT_EQ(stats.at("low_width"), 8);
  EXPECT_EQ(stats.at("low_height"), 6);
  EXPECT_EQ(stats.at("parameters").at("beta"), 10.0);
  EXPECT_EQ(stats.at("parameters").at("kappa"), 50.0);
  EXPECT_EQ(stats.at("parameters").at("nu_scene_units"), 0.3);
  for (const char* subset : {"all", "glossy_receivers", "diffuse_receivers"})
    for (const char* e : {"rmse", "smape", "relative_l2"}) {
      const double x = stats.at("error").at(subset).at(e).get<double>();
      EXPECT_TRUE(std::isfinite(x) && x >= 0) << subset << " " << e;
    }
  EXPECT_GT(stats.at("glossy_receivers").get<int>(), 0);
}

TEST_F(FilterCommand, SweepWritesTablesHeadedByTheCommand) {
  const Result r = sglab(fmt::format("filter-sweep --scene '{}' --roughness 0.1,0.5 --weights normal,lobe --rsm 8 --scale 2 "
                                     "--out '{}' --tables-dir '{}' --table t --quiet",
                                     path("scene.json").string(), path("sweep").string(), path("tables").string()));
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string md = read_file(path("tables/t.md")), csv = read_file(path("tables/t.csv"));
  EXPECT_EQ(md.rfind("<!-- Generated by `sglab filter-sweep --scene", 0), 0u) << md.substr(0, 200);
  EXPECT_EQ(csv.rfind("# Generated by `sglab filter-sweep --scene", 0), 0u);
  EXPECT_NE(md.find("lobe vs normal"), std::string::npos);
  EXPECT_NE(md.find("| 0.5 |"), std::string::npos);
  // Header, column names, two roughnesses × two weightings.
  std::size_t lines = 0;
  for (char c : csv) lines += c == '\n';
  EXPECT_EQ(lines, 2u + 4u);
  EXPECT_TRUE(fs::exists(path("sweep/t_points.csv")));
}

TEST_F(FilterCommand, BadInputExitsTwoNamesItAndWritesNothing) {
  struct Case {
    std::string extra, expected;
  };
  const std::vector<Case> cases = {
      {"--weights bilateral", "--weights 'bilateral'"},
      {"", "--weights"},
      {"--weights lobe --beta 0", "--beta 0"},
      {"--weights lobe --kappa -3", "--kappa -3"},
      {"--weights lobe --nu -1", "--nu -1"},
      {"--weights normal --depth-sigma 0", "--depth-sigma 0"},
      {"--weights normal --scale 0", "--scale 0"},
      {"--weights normal --source photons", "--source 'photons'"},
      {"--weights normal --set floor.roughness=-0.5", "objects[0].material.roughness: -0.5 is negative"},
      {"--weights normal --width 0", "--width 0"},
  };
  for (const auto& c : cases) {
    const Result r = filter(c.extra);
    EXPECT_EQ(r.status, 2) << c.extra << ": " << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.extra << ": " << r.err;
    EXPECT_FALSE(fs::exists(path("out.exr"))) << c.extra;
    EXPECT_FALSE(fs::exists(path("stats.json"))) << c.extra;
  }
  const Result r = sglab(fmt::format("filter-sweep --scene '{}' --roughness 0.1,abc --out '{}' --tables-dir '{}' --quiet",
                                     path("scene.json").string(), path("sweep").string(), path("tables").string()));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--roughness: 'abc'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("tables")));
}

}  // namespace
