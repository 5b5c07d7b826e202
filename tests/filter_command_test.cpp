// `sglab filter` and `sglab filter-sweep` end to end: run the built binary
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
#include "test_util.hpp"

namespace {

namespace fs = std::filesystem;

using Result = sglab::test::CommandResult;
using sglab::test::read_file;

// A glossy floor and a Lambert wall under a spotlight.
const std::string kTinyScene = sglab::test::SmallScene{.width = 16,
                                                       .height = 12,
                                                       .light_target = "[0, 0.3, -0.6]",
                                                       .light_direction = "[0, -0.6, -1]",
                                                       .cone_angle = 35,
                                                       .crate = false}
                                   .json();

class FilterCommand : public sglab::test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    std::ofstream(path("scene.json")) << kTinyScene;
  }
  Result filter(const std::string& extra) const {
    return sglab(fmt::format("filter '{}' --out '{}' --stats '{}' --rsm 8 --quiet {}", path("scene.json").string(),
                             path("out.exr").string(), path("stats.json").string(), extra));
  }
};

TEST_F(FilterCommand, WritesLayersAndStats) {
  const Result r = filter("--weights lobe --scale 2 --beta 10 --kappa 50 --nu 0.3");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto image = sglab::render::read_exr(path("out.exr").string());
  EXPECT_EQ(image.width, 16);
  EXPECT_EQ(image.height, 12);
  EXPECT_GT(
      sglab::test::expect_error_layer(image, {"upsampled", "reference", "error", "low_res"}, "upsampled", "reference"),
      0);
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

TEST_F(FilterCommand, NoisyInputWritesNoisyFilteredExactAndErrorLayersAndStats) {
  const Result r = filter("--weights lobe --noisy interleaved:2 --noisy-seed 5");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto image = sglab::render::read_exr(path("out.exr").string());
  EXPECT_EQ(image.width, 16);
  EXPECT_GT(sglab::test::expect_error_layer(image, {"noisy", "filtered", "exact", "error"}, "filtered", "exact"), 0);
  const std::string command = image.attributes.at("sglab_command");
  EXPECT_NE(command.find("--noisy interleaved:2 --radius 2 --noisy-seed 5"), std::string::npos) << command;
  EXPECT_EQ(command.find("--scale"), std::string::npos) << command;
  const auto stats = nlohmann::json::parse(read_file(path("stats.json")));
  EXPECT_EQ(stats.at("noisy"), "interleaved:2");
  EXPECT_EQ(stats.at("radius"), 2);
  for (const char* image_kind : {"noisy", "filtered"})
    for (const char* e : {"smape", "relative_l2"}) {
      const double x = stats.at("error").at(image_kind).at("all").at(e).get<double>();
      EXPECT_TRUE(std::isfinite(x) && x > 0) << image_kind << " " << e;
    }
  EXPECT_GT(stats.at("filter_ns_per_pixel").get<double>(), 0);
  // The noisy layer is the noisy input: its error in the stats is its distance to the exact layer.
  double num = 0, den = 0;
  for (const char* c : {"R", "G", "B"}) {
    const auto &v = image.channels.at(std::string("noisy.") + c), &ref = image.channels.at(std::string("exact.") + c);
    for (std::size_t k = 0; k < v.size(); ++k)
      num += (double(v[k]) - ref[k]) * (double(v[k]) - ref[k]), den += double(ref[k]) * ref[k];
  }
  EXPECT_NEAR(stats.at("error").at("noisy").at("all").at("relative_l2").get<double>(), std::sqrt(num / den), 1e-5);
}

TEST_F(FilterCommand, SweepWritesTablesHeadedByTheCommand) {
  const Result r = sglab(
      fmt::format("filter-sweep --scene '{}' --roughness 0.1,0.5 --weights normal,lobe --rsm 8 --scale 2 "
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

TEST_F(FilterCommand, NoisySweepWritesTheDenoiseTablesIntoTheOutDirectory) {
  const Result r = sglab(
      fmt::format("filter-sweep --scene '{}' --noisy interleaved:2,random:2 --roughness 0.1,0.5 --weights normal,lobe "
                  "--rsm 8 --figure-roughness 0.5 --figure-noisy interleaved:2 --out '{}' --quiet",
                  path("scene.json").string(), path("sweep").string()));
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string md = read_file(path("sweep/filtering_denoise.md")),
                    csv = read_file(path("sweep/filtering_denoise.csv"));
  EXPECT_EQ(md.rfind("<!-- Generated by `sglab filter-sweep --scene", 0), 0u) << md.substr(0, 200);
  EXPECT_NE(md.find("--noisy interleaved:2,random:2"), std::string::npos);
  EXPECT_NE(md.find("| interleaved:2 | 2 | 0.5 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| random:2 | 4 | 0.1 |"), std::string::npos) << md;
  std::size_t lines = 0;
  for (char c : csv) lines += c == '\n';
  EXPECT_EQ(lines, 2u + 2u * 2u * 2u);  // header, columns, two inputs × two roughnesses × two weightings
  const std::string images = read_file(path("sweep/filtering_denoise_images.csv"));
  lines = 0;
  for (char c : images) lines += c == '\n';
  EXPECT_EQ(lines, 2u + 16u * 12u);  // one image: 16×12 pixels
  EXPECT_FALSE(fs::exists(path("paper_tables")));
}

TEST_F(FilterCommand, BadInputExitsTwoNamesItAndWritesNothing) {
  struct Case {
    std::string extra, expected;
  };
  const std::vector<Case> cases = {
      {"--weights bilateral", "--weights: unknown weights 'bilateral'"},
      {"", "--weights"},
      {"--weights lobe --beta 0", "--beta 0"},
      {"--weights lobe --kappa -3", "--kappa -3"},
      {"--weights lobe --nu -1", "--nu -1"},
      {"--weights normal --depth-sigma 0", "--depth-sigma 0"},
      {"--weights normal --scale 0", "--scale 0"},
      {"--weights normal --source photons", "--source: unknown source 'photons'"},
      {"--weights normal --set floor.roughness=-0.5", "objects[0].material.roughness: -0.5 is negative"},
      {"--weights normal --width 0", "--width 0"},
      {"--weights lobe --noisy interleaved:0", "--noisy 'interleaved:0' is not interleaved:M"},
      {"--weights lobe --noisy blue-noise:4", "--noisy 'blue-noise:4'"},
      {"--weights lobe --noisy interleaved:4 --radius 2", "--radius 2 is below M = 4"},
      {"--weights lobe --noisy interleaved:2 --scale 2", "--scale is the upsampling pass's"},
      {"--weights lobe --noisy random:4 --noisy-seed -1", "--noisy-seed"},
  };
  for (const auto& c : cases) expect_bad_input(filter(c.extra), c.extra, c.expected, {"out.exr", "stats.json"});
  const Result r = sglab(
      fmt::format("filter-sweep --scene '{}' --roughness 0.1,abc --out '{}' --tables-dir '{}' --quiet",
                  path("scene.json").string(), path("sweep").string(), path("tables").string()));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--roughness: 'abc'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("tables")));
}

}  // namespace
