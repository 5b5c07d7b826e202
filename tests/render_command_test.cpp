// `sglab render` end to end: runs the built binary (SGLAB_EXE) on a tiny scene and checks the EXR
// layers and the stats JSON it writes; then every kind of bad input — malformed JSON, an unknown
// key, a negative roughness, a zero-sized object, a light inside an object, bad options — must
// exit with status 2, name the field in its message, and write neither image nor stats.
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

// A glossy floor, a Lambert wall and a Lambert box under a spotlight.
const std::string kTinyScene = sglab::test::SmallScene{}.json();

class RenderCommand : public sglab::test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    std::ofstream(path("scene.json")) << kTinyScene;
  }
  // Renders `scene` (a file in dir_) with extra arguments into out.exr / stats.json.
  Result render(const std::string& scene_file, const std::string& extra = "") const {
    return sglab(fmt::format("render '{}' --out '{}' --stats '{}' --rsm 8 --shadow-map 64 --quiet {}",
                             path(scene_file).string(), path("out.exr").string(), path("stats.json").string(), extra));
  }
};

TEST_F(RenderCommand, WritesLayersAndStats) {
  const Result r = render("scene.json", "--vsgl fis --count 4 --set floor.roughness=0.2");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto image = sglab::render::read_exr(path("out.exr").string());
  EXPECT_EQ(image.width, 12);
  EXPECT_EQ(image.height, 10);
  // error = indirect − reference, pixel by pixel (float rounding of the stored layers only).
  EXPECT_GT(sglab::test::expect_error_layer(image, {"direct", "indirect", "indirect_reference", "error"}, "indirect",
                                            "indirect_reference"),
            0);
  EXPECT_NE(image.attributes.at("sglab_command").find("sglab render"), std::string::npos);

  const auto stats = nlohmann::json::parse(read_file(path("stats.json")));
  EXPECT_EQ(stats.at("pixels"), 120);
  EXPECT_GT(stats.at("vpl_count").get<int>(), 10);
  EXPECT_LE(stats.at("vpl_count").get<int>(), 64);
  EXPECT_GE(stats.at("vsgl_count").get<int>(), 2);
  EXPECT_GE(stats.at("specular_vsgls").get<int>(), 1);
  for (const char* s : {"rsm", "vsgl", "shading", "reference"})
    EXPECT_GE(stats.at("seconds").at(s).get<double>(), 0) << s;
  for (const char* e : {"rmse", "smape", "relative_l2"}) {
    const double x = stats.at("error").at(e).get<double>();
    EXPECT_TRUE(std::isfinite(x) && x >= 0) << e;
  }
  EXPECT_NE(stats.at("notes").get<std::string>().find("VSGL visibility ignored, as in the papers"), std::string::npos);
  EXPECT_EQ(stats.at("vsgl").at("mode"), "fis");
  EXPECT_EQ(stats.at("overrides"), nlohmann::json::array({"floor.roughness=0.2"}));
  EXPECT_TRUE(stats.at("built").at("asg_evaluated").get<bool>());
  EXPECT_NE(r.out.find("relative L2"), std::string::npos);
}

TEST_F(RenderCommand, DiffuseOnlySceneReportsNoSpecular) {
  const Result r = render("scene.json", "--set floor.f0=0");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto stats = nlohmann::json::parse(read_file(path("stats.json")));
  EXPECT_EQ(stats.at("specular_vsgls"), 0);
  EXPECT_EQ(stats.at("vsgl_count"), 1);
  EXPECT_FALSE(stats.at("built").at("specular_shading").get<bool>());
  EXPECT_FALSE(stats.at("built").at("asg_evaluated").get<bool>());
}

TEST_F(RenderCommand, BadInputExitsTwoNamesTheFieldAndWritesNothing) {
  std::ofstream(path("malformed.json")) << "{\n  \"camera\": {\"fov\": 40,\n";
  std::string scene = kTinyScene;
  std::ofstream(path("unknown-key.json")) << std::string(scene).insert(scene.find("\"objects\""), "\"lights\": [], ");
  struct Case {
    std::string scene, extra, expected;
  };
  const std::vector<Case> cases = {
      {"malformed.json", "", "malformed JSON: parse error at line 3"},
      {"unknown-key.json", "", "lights: unknown key"},
      {"scene.json", "--set floor.roughness=-0.1", "objects[0].material.roughness: -0.1 is negative"},
      {"scene.json", "--set 'crate.max=[0.7,0,-0.2]'", "objects[2].max:"},
      {"scene.json", "--set 'wall.edge_v=[0,0,0]'", "objects[1].edge_v: is the zero vector"},
      {"scene.json", "--set light.cone_angle=95", "light.cone_angle: 95 is outside"},
      {"scene.json", "--set lamp.power=1", "--set lamp.power: no top-level key or object named \"lamp\""},
      {"missing.json", "", "cannot open the scene file"},
      {"scene.json", "--vsgl three", "--vsgl: unknown VSGL mode 'three'"},
      {"scene.json", "--rsm 0", "--rsm 0 is outside"},
      {"scene.json", "--width 0", "--width 0 is outside"},
      {"scene.json", "--diffuse cosine", "--diffuse: unknown diffuse method 'cosine'"},
      {"scene.json", "--specular ggx", "--specular: unknown specular method 'ggx'"},
      {"scene.json", "--vsgl kmeans --count 0", "--count 0 is outside"},
  };
  for (const auto& c : cases)
    expect_bad_input(render(c.scene, c.extra), c.scene + " " + c.extra, c.expected, {"out.exr", "stats.json"});
  // The light inside the crate names the field that placed it.
  const Result r = render("scene.json", "--set 'light.target=[0.5,0.1,-0.4]' --set light.distance=0.05");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("light.distance: the light at"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("inside or on objects[2] (\"crate\")"), std::string::npos) << r.err;
  // No temporary files left behind either.
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_EQ(e.path().filename().string().find(".out.exr.tmp"), std::string::npos);
}

TEST_F(RenderCommand, AnExistingImageIsNotClobberedByAFailedRun) {
  std::ofstream(path("out.exr")) << "previous";
  const Result r = render("scene.json", "--set floor.roughness=2");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(read_file(path("out.exr")), "previous");
}

// `sglab sweep render`: the per-point CSV has one row per (point, VSGL configuration), the grids
// are the documented ones, the table is headed by the command; a bad value of a --vary is caught
// before anything runs.
TEST_F(RenderCommand, SweepWritesPointsAndTable) {
  const std::string common = fmt::format(
      "--scene '{}' --width 8 --height 6 --rsm 8 --shadow-map 32 --out '{}' --tables-dir '{}'",
      path("scene.json").string(), path("sweep").string(), path("tables").string());
  Result r = sglab("sweep render " + common +
                   " --vary floor.roughness=0.01:1:3:log --vary light.distance=0.8,1.2 --vsgl two --vsgl fis:4");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string points = read_file(path("sweep") / "vsgl_error_vs_roughness_distance_points.csv");
  std::istringstream lines(points);
  std::string header, line;
  std::getline(lines, header);
  EXPECT_EQ(header.rfind("point,floor.roughness,light.distance,vsgl,", 0), 0u) << header;
  std::vector<std::string> rows;
  while (std::getline(lines, line))
    if (!line.empty()) rows.push_back(line);
  ASSERT_EQ(rows.size(), 3u * 2u * 2u);
  // Point order: the last --vary fastest; rows of a point: the configurations in order.
  EXPECT_EQ(rows[0].rfind("0,0.01,0.8,two,", 0), 0u) << rows[0];
  EXPECT_EQ(rows[1].rfind("0,0.01,0.8,fis 4,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[2].rfind("1,0.01,1.2,two,", 0), 0u) << rows[2];
  EXPECT_EQ(rows[11].rfind("5,1,1.2,fis 4,", 0), 0u) << rows[11];
  const double middle = std::stod(rows[4].substr(rows[4].find(',') + 1));  // log-spaced: √(0.01·1)
  EXPECT_NEAR(middle, 0.1, 1e-15);
  const std::string md = read_file(path("tables") / "vsgl_error_vs_roughness_distance.md");
  EXPECT_EQ(md.rfind("<!-- Generated by `sglab sweep render --scene ", 0), 0u) << md.substr(0, 200);
  EXPECT_NE(md.find("| floor.roughness | light.distance | VSGLs |"), std::string::npos);
  EXPECT_EQ(
      read_file(path("tables") / "vsgl_error_vs_roughness_distance.csv").rfind("# Generated by `sglab sweep render", 0),
      0u);

  // Linear spacing, and the default table name without --vary.
  r = sglab("sweep render " + common + " --vary light.distance=0.6:1.2:3 --table distances");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(read_file(path("sweep") / "distances_points.csv").find("\n2,1.2,two,"), std::string::npos);
  EXPECT_NE(read_file(path("sweep") / "distances_points.csv").find("\n1,0.8999999999999999,two,"), std::string::npos);
  r = sglab("sweep render " + common + " --vsgl kmeans:2");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(path("tables") / "vsgl_error_vs_count.md"));
}

TEST_F(RenderCommand, SweepRejectsBadInputBeforeRunning) {
  const std::string common = fmt::format("--scene '{}' --width 8 --height 6 --rsm 8 --out '{}' --tables-dir '{}'",
                                         path("scene.json").string(), path("sweep").string(), path("tables").string());
  struct Case {
    std::string args, expected;
  };
  for (const auto& c : std::vector<Case>{
           {"--vary floor.roughness=-1:1:3", "at floor.roughness=-1: " + path("scene.json").string() +
                                                 ": objects[0].material.roughness: -1 is negative"},
           {"--vary floor.roughness=0:1:3:log", "--vary floor.roughness=0:1:3:log: log spacing needs a, b > 0"},
           {"--vary floor.roughness=0.1:1:2.5", "n = 2.5 is not an integer"},
           {"--vary floor.roughness=0.1:x:3", "--vary floor.roughness=0.1:x:3: 'x' is not a number"},
           {"--vary lamp.power=1,2", "--vary lamp.power: --set lamp.power: no top-level key or object named \"lamp\""},
           {"--vsgl fis", "--vsgl fis: fis and kmeans need a count"},
           {"--vsgl three:4", "--vsgl: unknown VSGL mode 'three'"},
       })
    expect_bad_input(sglab("sweep render " + common + " " + c.args), c.args, c.expected, {"tables"});
}

}  // namespace
