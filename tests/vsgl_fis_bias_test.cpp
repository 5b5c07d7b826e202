// The FIS VSGLs' total power on the shipped scenes must be no more biased than
// paper_tables/vsgl_fis_bias.csv says (written by `sglab vsgl-fis-bias`): the exact total
// ΣΦ(R_d + R_s) is summed here from the RSM's texels, independently of the VSGL code, and the
// mean of the FIS estimates over seeds 1 … 64 (the table's seeds) is compared with it. Fails if
// |bias| exceeds the table's |bias| + 3 of its standard errors, i.e. if a change makes FIS worse
// than what the committed table claims (regenerate the table with the full reproduce step).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "input_error.hpp"
#include "sglab/render/rsm.hpp"
#include "sglab/render/scene.hpp"
#include "sglab/render/vsgl_generation.hpp"
#include "test_util.hpp"
#include "vsgl_fis_bias.hpp"

namespace {

using namespace sglab::render;

using sglab::test::read_file;

struct TableRow {
  double bias = 0, se = 0;
  int seeds = 0;
};

// (rsm, n) → the total_power row of the committed table.
std::map<std::pair<std::string, int>, TableRow> committed_table() {
  std::map<std::pair<std::string, int>, TableRow> out;
  std::istringstream in(read_file(std::string(SGLAB_SOURCE_DIR) + "/paper_tables/vsgl_fis_bias.csv"));
  std::string line;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      EXPECT_EQ(line, "rsm,n,quantity,exact,mean_estimate,relative_bias,standard_error,seeds");
      header = false;
      continue;
    }
    std::vector<std::string> f;
    std::stringstream s(line);
    for (std::string x; std::getline(s, x, ',');) f.push_back(x);
    if (f.size() != 8 || f[2] != "total_power") continue;
    out[{f[0], std::stoi(f[1])}] = {std::stod(f[5]), std::stod(f[6]), std::stoi(f[7])};
  }
  return out;
}

TEST(VsglFisBias, ShippedScenesTotalPowerNoWorseThanTheTable) {
  const auto table = committed_table();
  for (const std::string name :
       {"scenes/cornell-glossy.json", "scenes/diffuse-only.json", "scenes/sg-light-near-wall.json"}) {
    const Scene scene = parse_scene(parse_scene_text(read_file(std::string(SGLAB_SOURCE_DIR) + "/" + name), name));
    const ReflectiveShadowMap rsm = render_rsm(scene, 64);
    double exact = 0;
    for (const Vpl& v : rsm.texels) {
      if (!v.valid) continue;
      exact += (v.flux * v.diffuse_reflectance).sum();
      if (v.glossy()) exact += (v.flux * v.specular_reflectance).sum();
    }
    ASSERT_GT(exact, 0) << name;
    for (const int n : {4, 16, 64}) {
      const auto it = table.find({name, n});
      ASSERT_NE(it, table.end()) << name << " N = " << n << " is missing from paper_tables/vsgl_fis_bias.csv";
      double sum = 0;
      for (int seed = 1; seed <= it->second.seeds; ++seed) {
        VsglOptions o;
        o.mode = VsglMode::fis;
        o.count = n;
        o.seed = std::uint64_t(seed);
        double estimate = 0;
        for (const auto& c : build_vsgls(rsm, o).clusters) estimate += (c.diffuse_power + c.specular_power).sum();
        sum += estimate;
      }
      const double bias = (sum / it->second.seeds - exact) / exact;
      EXPECT_LE(std::fabs(bias), std::fabs(it->second.bias) + 3 * it->second.se + 1e-12)
          << name << " N = " << n << ": bias " << bias << " over seeds 1 … " << it->second.seeds << ", table "
          << it->second.bias << " ± " << it->second.se;
    }
  }
}

// The experiment's compute() on small RSMs: the importance is exact by construction (every cluster
// gets W/N), and the exact total power is the texels' sum computed here independently.
TEST(VsglFisBias, ComputeAgainstTheTexelSums) {
  namespace fb = sglab::experiments::vsgl_fis_bias;
  std::filesystem::current_path(SGLAB_SOURCE_DIR);  // the experiment reads scenes/ relative to the checkout
  fb::Options o;
  o.seeds = 3;
  o.rsm = 16;
  const fb::Result r = fb::compute(o);
  ASSERT_EQ(r.rows.size(), 4u * 3u * 4u);  // 3 shipped scenes + a random RSM, N = 4, 16, 64, four sums
  for (const auto& row : r.rows)
    if (row.quantity == "importance") {
      EXPECT_LE(std::fabs(row.bias), 1e-12) << row.rsm << " N = " << row.n;
    }
  for (const std::string name :
       {"scenes/cornell-glossy.json", "scenes/diffuse-only.json", "scenes/sg-light-near-wall.json"}) {
    const Scene scene = parse_scene(parse_scene_text(read_file(name), name));
    double exact = 0;
    for (const Vpl& v : render_rsm(scene, o.rsm).texels) {
      if (!v.valid) continue;
      exact += (v.flux * v.diffuse_reflectance).sum();
      if (v.glossy()) exact += (v.flux * v.specular_reflectance).sum();
    }
    const auto it = std::find_if(r.rows.begin(), r.rows.end(),
                                 [&](const fb::Row& row) { return row.rsm == name && row.quantity == "total_power"; });
    ASSERT_NE(it, r.rows.end()) << name;
    EXPECT_NEAR(it->exact, exact, 1e-12 * exact) << name;
  }
  const fb::Tables t = fb::tables(r);
  EXPECT_EQ(std::count(t.csv.begin(), t.csv.end(), '\n'), 1 + 48);
  EXPECT_NE(t.markdown.find("| random 8×8 RSM"), std::string::npos);
  o.seeds = 1;
  EXPECT_THROW(fb::compute(o), sglab::runner::InputError);
}

}  // namespace
