// A corpus of hostile and careless inputs, one test per group of failures they used to cause:
// stack overflows on deep JSON, manifests run as commands, an unbounded reference quadrature,
// outputs overwriting inputs or special files, partial output sets, temporaries left by a signal,
// wrong values at extreme sharpness, silent Inf in renders, aliased sweep keys, trusted on-disk
// state, unchecked options, CLI11 exit codes, long or wrong messages, unchecked sizes and minor
// message faults. Every case runs the built `sglab` (SGLAB_EXE) or the library code it runs, and
// asserts the exit status, that the message is short and names the value, and that existing files
// are left as they were. Expected values come from closed forms, never from the code under test.
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "atomic_file.hpp"
#include "input_error.hpp"
#include "sglab/asg_integral.hpp"
#include "sglab/clamped_cosine.hpp"
#include "sglab/hemispherical.hpp"
#include "sweep.hpp"

#include "test_util.hpp"

namespace {

namespace fs = std::filesystem;

using sglab::test::read_file;

struct Result {
  int status = -1;
  std::string out, err;
  double seconds = 0;
};

// A glossy floor and a Lambert wall under a spotlight.
const std::string kScene = sglab::test::SmallScene{.light_direction = "[0, -1, -0.7]", .crate = false}.json();

// The longest message any rejected case may print (before the limits, 50 MB of input gave 50 MB of message).
using sglab::test::kShortMessage;

class Hardening : public sglab::test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    std::ofstream(path("scene.json")) << kScene;
  }
  std::string p(const std::string& name) const { return fmt::format("'{}'", path(name).string()); }

  // Runs `sglab ARGS` (ARGS is shell text) with `stdin_text` on standard input.
  Result sglab(const std::string& args, const std::string& stdin_text = "") const {
    std::ofstream(path("stdin"), std::ios::binary) << stdin_text;
    const std::string command = fmt::format("cd '{}' && '{}' {} < '{}' > '{}' 2> '{}'", dir_.string(), SGLAB_EXE, args,
                                            path("stdin").string(), path("stdout").string(), path("stderr").string());
    const auto t0 = std::chrono::steady_clock::now();
    const int raw = std::system(command.c_str());
    Result r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + (WIFSIGNALED(raw) ? WTERMSIG(raw) : 0);
    r.out = read_file(path("stdout"));
    r.err = read_file(path("stderr"));
    return r;
  }
  std::string render_args(const std::string& scene = "scene.json") const {
    return fmt::format("render {} --rsm 8 --shadow-map 64 --quiet", p(scene));
  }
  // No hidden temporary (".NAME.tmp-XXXXXX") left in the directory.
  void expect_no_temporaries() const {
    for (const auto& e : fs::directory_iterator(dir_))
      EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
  }
};

#define EXPECT_REFUSED(r, needle)                                                  \
  do {                                                                             \
    EXPECT_EQ((r).status, 2) << (r).err.substr(0, 2000);                           \
    EXPECT_LT((r).err.size(), kShortMessage) << (r).err.substr(0, 2000);           \
    EXPECT_NE((r).err.find(needle), std::string::npos) << (r).err.substr(0, 2000); \
  } while (0)

// 1. Deeply nested JSON: exit 2 with a short message, not a stack overflow (exit 139).
TEST_F(Hardening, Group01_DeepJsonIsRefused) {
  for (const int depth : {65000, 50000, 65}) {
    std::ofstream(path("deep.txt")) << std::string(depth, '[') << std::string(depth, ']');
    const Result r = sglab(render_args() + " --out out.exr --set \"camera.fov=$(cat deep.txt)\"");
    EXPECT_REFUSED(r, "nested deeper than 64");
    std::ofstream(path("deep.json")) << "{\"description\": " << std::string(depth, '[') << std::string(depth, ']')
                                     << "}";
    const Result s = sglab(render_args("deep.json") + " --out out.exr");
    EXPECT_REFUSED(s, "nested deeper than 64");
  }
  EXPECT_FALSE(fs::exists(path("out.exr")));
}

// 2. A shard manifest is data: its args are never run as a command, its sweep name never a path.
TEST_F(Hardening, Group02_ManifestsAreNotCommands) {
  fs::create_directories(path("shards"));
  const auto manifest = [&](const std::string& file, const nlohmann::json& m) {
    std::ofstream(path("shards") / file) << m.dump();
  };
  nlohmann::json m = {{"sweep", "toy"}, {"args", {"merge", path("shards").string()}},
                      {"grid", "g"},    {"points", 2},
                      {"shard", "0/2"}, {"columns", {"point", "x"}},
                      {"rows", 1},      {"points_fnv1a", "0"}};
  manifest("toy_sweep.shard-0-of-2.json", m);
  Result r = sglab("merge --out merged shards");
  EXPECT_REFUSED(r, "is not a `sweep specular` or `sweep render` command line");

  fs::remove_all(path("shards"));
  fs::create_directories(path("shards"));
  m["args"] = {"sweep", "specular", "--quick"};
  m["sweep"] = path("elsewhere").string();  // an absolute path
  manifest("toy_sweep.shard-0-of-2.json", m);
  r = sglab("merge --out merged shards");
  EXPECT_REFUSED(r, "is not a plain file name");
  m["sweep"] = "../up";
  manifest("toy_sweep.shard-0-of-2.json", m);
  EXPECT_REFUSED(sglab("merge --out merged shards"), "is not a plain file name");
  EXPECT_FALSE(fs::exists(path("elsewhere")));
  EXPECT_FALSE(fs::exists(path("merged")));
}

// 3. The specular reference refuses roughness below its minimum at once instead of running for
// minutes (α = 1e-8 at grazing view took > 200 s).
TEST_F(Hardening, Group03_SpecularReferenceCostIsBounded) {
  const Result r = sglab("eval specular -m reference",
                         "roughness,light_sharpness,light_cos,view_cos,light_azimuth,f0\n"
                         "1e-8,0.5,0,0.5,3.141592653589793,0\n");
  EXPECT_REFUSED(r, "roughness '1e-8'");
  EXPECT_LT(r.seconds, 10);
}

// 4. An output equal to an input or to another output is refused; the files are untouched.
TEST_F(Hardening, Group04_OutputsNeverOverwriteInputsOrEachOther) {
  const std::string scene = read_file(path("scene.json"));
  EXPECT_REFUSED(sglab(render_args() + " --out " + p("scene.json")), "refusing to overwrite an input");
  EXPECT_REFUSED(sglab(render_args() + " --out " + p("./scene.json")), "refusing to overwrite an input");
  EXPECT_REFUSED(sglab("filter " + p("scene.json") + " --weights normal --out " + p("scene.json")),
                 "refusing to overwrite an input");
  EXPECT_EQ(read_file(path("scene.json")), scene);
  EXPECT_REFUSED(sglab(render_args() + " --out x --stats x"), "each output needs its own file");
  EXPECT_FALSE(fs::exists(path("x")));
  std::ofstream(path("in.csv")) << "sharpness\n1\n";
  EXPECT_REFUSED(sglab("eval sg-integral -m exact --in in.csv --out in.csv"), "refusing to overwrite an input");
  EXPECT_EQ(read_file(path("in.csv")), "sharpness\n1\n");
}

// 5. An output set is committed as a whole: a later output that cannot be written leaves the
// earlier ones as they were.
TEST_F(Hardening, Group05_OutputSetIsAllOrNothing) {
  std::ofstream(path("keep.exr")) << "old image";
  fs::create_directories(path("somedir"));
  EXPECT_REFUSED(sglab(render_args() + " --out keep.exr --stats somedir"), "is a directory");
  EXPECT_EQ(read_file(path("keep.exr")), "old image");

  // In the library: the second file's directory cannot be created (a file is in the way), so
  // the first, already written to its temporary, must not be published.
  std::ofstream(path("blocker")) << "x";
  sglab::runner::OutputSet set;
  set.add(path("keep.exr"), "new image");
  set.add(path("blocker") / "stats.json", "{}");
  EXPECT_ANY_THROW(set.commit());
  EXPECT_EQ(read_file(path("keep.exr")), "old image");
  expect_no_temporaries();
}

// 5, continued: the commands with several outputs check them all before computing anything, so
// a second output that cannot be written leaves the first untouched and writes nothing at all.
TEST_F(Hardening, Group05_TablePairsAreOneSet) {
  // `sweep render`: NAME.csv exists, NAME.md is a directory.
  fs::create_directories(path("tables") / "t.md");
  std::ofstream(path("tables") / "t.csv") << "old table";
  Result r = sglab("sweep render --scene " + p("scene.json") +
                   " --rsm 8 --shadow-map 64 --out sw --tables-dir tables --table t");
  EXPECT_REFUSED(r, "is a directory");
  EXPECT_LT(r.seconds, 10);
  EXPECT_EQ(read_file(path("tables") / "t.csv"), "old table");
  EXPECT_FALSE(fs::exists(path("sw"))) << "the sweep ran before its outputs were checked";
  // A table that would replace the scene it reads.
  std::ofstream(path("tables") / "s.csv") << read_file(path("scene.json"));
  r = sglab("sweep render --scene tables/s.csv --rsm 8 --shadow-map 64 --out sw --tables-dir tables --table s");
  EXPECT_REFUSED(r, "refusing to overwrite an input");
  EXPECT_EQ(read_file(path("tables") / "s.csv"), read_file(path("scene.json")));
  EXPECT_FALSE(fs::exists(path("sw")));

  // `error-vs-time`: --out's CSV exists, the tables' Markdown is a directory; then --out and
  // --tables the same directory (the two CSVs would be one file).
  std::ofstream(path("keep.csv")) << "old";
  fs::create_directories(path("evt"));
  std::ofstream(path("evt") / "error_vs_time.csv") << "old per-method table";
  fs::create_directories(path("evt_tables") / "error_vs_time.md");
  r = sglab("error-vs-time --quick --quantity clamped-cosine --out evt --tables evt_tables");
  EXPECT_REFUSED(r, "is a directory");
  EXPECT_LT(r.seconds, 10);
  EXPECT_EQ(read_file(path("evt") / "error_vs_time.csv"), "old per-method table");
  EXPECT_FALSE(fs::exists(path("evt_tables") / "error_vs_time.csv"));
  r = sglab("error-vs-time --quick --quantity clamped-cosine --out evt --tables evt");
  EXPECT_REFUSED(r, "each output needs its own file");
  EXPECT_EQ(read_file(path("evt") / "error_vs_time.csv"), "old per-method table");
  expect_no_temporaries();
}

// 6. Special files (symbolic links, FIFOs, devices, directories) are never replaced.
TEST_F(Hardening, Group06_SpecialFilesAreNotReplaced) {
  std::ofstream(path("target")) << "target";
  fs::create_symlink(path("target"), path("link.exr"));
  EXPECT_REFUSED(sglab(render_args() + " --out link.exr"), "is a symbolic link");
  EXPECT_TRUE(fs::is_symlink(path("link.exr")));
  EXPECT_EQ(read_file(path("target")), "target");
  ASSERT_EQ(::mkfifo(path("fifo.exr").c_str(), 0600), 0);
  EXPECT_REFUSED(sglab(render_args() + " --out fifo.exr"), "is a FIFO");
  EXPECT_TRUE(fs::is_fifo(path("fifo.exr")));
  EXPECT_REFUSED(sglab(render_args() + " --out /dev/full"), "is a character device");
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
  EXPECT_REFUSED(sglab("eval sg-integral -m exact --out /dev/null", "sharpness\n1\n"), "is a character device");
  expect_no_temporaries();
}

// 7. SIGINT or SIGTERM while an output is being written removes its temporary.
// The test sets the disposition it needs: `sglab` started from a shell has SIGINT and SIGTERM at
// their defaults, and installs its handler only then (an ignored signal stays ignored). A job
// started in the background inherits SIGINT ignored, so this binary resets both to the default
// before main, ahead of any temporary file (the handler is installed once per process).
const bool kDefaultTerminationSignals = [] {
  for (const int sig : {SIGINT, SIGTERM}) ::signal(sig, SIG_DFL);
  return true;
}();

TEST_F(Hardening, Group07_SignalRemovesTemporaries) {
  ASSERT_TRUE(kDefaultTerminationSignals);
  for (const int sig : {SIGINT, SIGTERM}) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      sglab::runner::AtomicFile f(path("big.exr"));
      f.write(std::string(1 << 20, 'x'));  // a partial output
      ::raise(sig);
      ::_exit(0);  // not reached
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << status;
    EXPECT_FALSE(fs::exists(path("big.exr")));
    expect_no_temporaries();
  }
}

// 8. The diffuse methods at extreme sharpness, up to the largest finite value of each type,
// against the closed-form limits: for c = 0.5 and λ ≥ 1e6, H(λ, c) = 2π/λ and
// D(λ, c) = 2πc/λ·(1 − 1/λ) to far below 1e-6 (the parts below the horizon are e^{−λc²}-small;
// the vMF mean cosine is coth λ − 1/λ), and the share of the normalised vMF above the horizon is
// 1. The ASG integral with ηx = ηy = η is π(1 − e^{−η})/η exactly.
template <class T>
void check_extreme_sharpness(const char* type) {
  const double two_pi = 2 * std::numbers::pi;
  const double max = double(std::numeric_limits<T>::max());
  for (const double lambda : {1e6, 1e13, 1e20, 1e38, 1e120, 1e155, 1e160, 1e300, max}) {
    if (lambda > max) continue;
    const T l = T(lambda);
    const double ld = double(l);
    const auto rel = [](double v, double ref) { return std::fabs(v - ref) / std::fabs(ref); };
    const double c = 0.5;
    EXPECT_LT(rel(double(sglab::clamped_cosine_tokuyoshi2024(l, T(c))), two_pi * c / ld), 0.01)
        << type << " λ=" << lambda;
    EXPECT_LT(rel(double(sglab::hemispherical_tokuyoshi2022(l, T(c))), two_pi / ld), 0.01) << type << " λ=" << lambda;
    EXPECT_LT(rel(double(sglab::hemispherical_vmf_tokuyoshi2024(l, T(c))), 1.0), 0.01) << type << " λ=" << lambda;
    EXPECT_LT(rel(double(sglab::tokuyoshi2024_t(l)), std::sqrt(ld / 2)), 1e-3) << type << " λ=" << lambda;
  }
}

TEST(HardeningNumerics, Group08_ExtremeSharpness) {
  check_extreme_sharpness<float>("float");
  check_extreme_sharpness<double>("double");
  for (const double eta : {1e10, 1e100, 1e300, 4.5e307, 1.797e308, std::numeric_limits<double>::max()}) {
    const double exact = std::numbers::pi * (-std::expm1(-eta)) / eta;
    EXPECT_LT(std::fabs(sglab::asg_integral_exact(eta, eta) / exact - 1), 1e-6) << "η=" << eta;
  }
  // ηx → ∞ squeezes the ASG onto the great circle x = 0: ∫ → √(π/ηx)·∫_{−1}^{1} e^{−ηy s²} ds
  // = √(π/ηx)·√(π/ηy)·erf(√ηy) (2√(π/ηx) at ηy = 0), relatively exact to O(1/ηx).
  for (const double eta_x : {1e20, 1e300, 1.797e308, std::numeric_limits<double>::max()})
    for (const double eta_y : {0.0, 1.0, 100.0}) {
      const double pi = std::numbers::pi;
      const double limit = eta_y == 0 ? 2 * std::sqrt(pi / eta_x)
                                      : std::sqrt(pi / eta_x) * std::sqrt(pi / eta_y) * std::erf(std::sqrt(eta_y));
      EXPECT_LT(std::fabs(sglab::asg_integral_exact(eta_x, eta_y) / limit - 1), 1e-6)
          << "ηx=" << eta_x << " ηy=" << eta_y;
    }
}

// 9. Renders: an output holding Inf is an error naming the pixel and stage; huge or tiny vectors
// are normalised without overflow; a perpendicularity check that overflowed is exact.
TEST_F(Hardening, Group09_RenderExtremes) {
  Result r = sglab(render_args() + " --out out.exr --set light.power=1e300");
  EXPECT_REFUSED(r, "light.power");
  EXPECT_NE(r.err.find("nothing written"), std::string::npos);
  EXPECT_FALSE(fs::exists(path("out.exr")));

  // A direction of [0, −1e200, −0.7e200] is the direction [0, −1, −0.7]: the same VPLs.
  r = sglab(render_args() + " --out a.exr --stats a.json --set 'light.direction=[0,-1,-0.7]'");
  ASSERT_EQ(r.status, 0) << r.err;
  r = sglab(render_args() + " --out b.exr --stats b.json --set 'light.direction=[0,-1e200,-0.7e200]'");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto a = nlohmann::json::parse(read_file(path("a.json"))), b = nlohmann::json::parse(read_file(path("b.json")));
  EXPECT_GT(a.at("vpl_count").get<int>(), 0);
  EXPECT_EQ(a.at("vpl_count"), b.at("vpl_count"));
  const double ra = a.at("error").at("rmse").get<double>(), rb = b.at("error").at("rmse").get<double>();
  EXPECT_NEAR(rb, ra, 1e-9 * ra);  // the scaled direction may differ from [0, −1, −0.7] in the last bit

  // Edges 45° apart are not perpendicular at any scale.
  EXPECT_REFUSED(
      sglab(render_args() + " --out out.exr --set 'floor.edge_u=[1e200,0,0]' --set 'floor.edge_v=[1e200,0,1e200]'"),
      "is not perpendicular");
}

// 10. `sweep render --vary`: aliased and duplicate keys, and a point count that overflows, are
// refused before anything is computed.
TEST_F(Hardening, Group10_SweepVaryKeys) {
  const std::string sweep = "sweep render --scene " + p("scene.json") + " --rsm 8 --shadow-map 64 --out sw ";
  Result r = sglab(sweep + "--vary floor.roughness=0.1,0.2 --vary objects.0.roughness=0.3,0.4");
  EXPECT_REFUSED(r, "set the same field");
  EXPECT_LT(r.seconds, 10);
  r = sglab(sweep + "--vary floor.roughness=0.1,0.2 --vary floor.roughness=0.3,0.4");
  EXPECT_REFUSED(r, "set the same field");
  std::string eight;
  for (const char* key : {"floor.roughness", "wall.albedo", "floor.albedo", "floor.f0", "light.distance", "light.power",
                          "light.cone_angle", "camera.fov"})
    eight += fmt::format("--vary {}=0.1:0.9:256 ", key);
  r = sglab(sweep + eight);
  EXPECT_REFUSED(r, "too large to count");
  EXPECT_FALSE(
      fs::exists(path("sw") / "vsgl_error_vs_roughness_albedo_albedo_f0_distance_power_cone_angle_fov_points.csv"));
}

// 11. Resume and merge check what is on disk: a deleted row, an altered checkpoint, an edited
// scene are noticed and recomputed (or refused by merge).
TEST_F(Hardening, Group11_OnDiskStateIsChecked) {
  using sglab::runner::SweepDefinition;
  using sglab::runner::SweepRow;
  std::atomic<int> calls{0};
  int fail_on = -1;
  SweepDefinition d;
  d.name = "toy";
  d.args = {"sweep", "toy"};
  d.grid = "g";
  d.point_count = 12;
  d.columns = {"x"};
  d.compute = [&](std::size_t k) {
    if (++calls == fail_on) throw std::runtime_error("interrupted");
    return std::vector<SweepRow>{{std::to_string(k)}, {std::to_string(k + 100)}};  // two rows a point
  };
  sglab::runner::SweepRunOptions o{
      .out_dir = path("run"), .shard = {}, .threads = 1, .checkpoint_seconds = 0, .quiet = true};

  // A deleted row of a point that keeps its other row: recomputed, not summarised.
  auto r = sglab::runner::run_sweep(d, o);
  const std::string whole = read_file(r.points_csv);
  std::string text = whole;
  text.erase(text.find("3,103\n"), 6);
  std::ofstream(r.points_csv, std::ios::binary) << text;
  calls = 0;
  r = sglab::runner::run_sweep(d, o);
  EXPECT_EQ(r.computed, 12u);
  EXPECT_EQ(read_file(r.points_csv), whole);

  // A deleted row in a checkpoint: the checkpoint is not trusted.
  fs::remove_all(path("run"));
  calls = 0;
  fail_on = 6;
  EXPECT_THROW(sglab::runner::run_sweep(d, o), std::runtime_error);
  const fs::path checkpoint = sglab::runner::sweep_checkpoint_path(path("run"), "toy", {});
  text = read_file(checkpoint);
  text.erase(text.find("2,102\n"), 6);
  std::ofstream(checkpoint, std::ios::binary) << text;
  calls = 0;
  fail_on = -1;
  r = sglab::runner::run_sweep(d, o);
  EXPECT_EQ(r.resumed, 0u);
  EXPECT_EQ(read_file(r.points_csv), whole);

  // A deleted row in a shard: merge refuses.
  for (std::size_t i = 0; i < 2; ++i)
    sglab::runner::run_sweep(d, {.out_dir = path("shards"), .shard = {i, 2}, .quiet = true});
  const fs::path shard0 = sglab::runner::sweep_points_path(path("shards"), "toy", {0, 2});
  text = read_file(shard0);
  text.erase(text.find("4,104\n"), 6);
  std::ofstream(shard0, std::ios::binary) << text;
  EXPECT_THROW(sglab::runner::merge_sweep_shards({path("shards")}, path("merged")), sglab::runner::InputError);
  EXPECT_FALSE(fs::exists(path("merged")));

  // An edited scene file is another sweep: `sweep render` recomputes instead of republishing.
  const std::string sweep = "sweep render --scene " + p("scene.json") +
                            " --rsm 8 --shadow-map 64 --out sw --tables-dir tables";
  Result first = sglab(sweep);
  ASSERT_EQ(first.status, 0) << first.err;
  std::string scene = read_file(path("scene.json"));
  scene.replace(scene.find("\"power\": 5"), 10, "\"power\": 6");
  std::ofstream(path("scene.json")) << scene;
  Result second = sglab(sweep);
  ASSERT_EQ(second.status, 0) << second.err;
  EXPECT_EQ(second.err.find("finished earlier"), std::string::npos) << second.err;

  // `reproduce` reruns a step whose output was deleted (and skips it while it is intact).
  const std::string step = "reproduce --quick --only error-map --out r";
  ASSERT_EQ(sglab(step).status, 0);
  Result again = sglab(step);
  EXPECT_NE(again.err.find("done earlier, skipped"), std::string::npos) << again.err;
  fs::remove(path("r") / "error_map" / "error_map.csv");
  again = sglab(step);
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(again.err.find("done earlier, skipped"), std::string::npos) << again.err;
  EXPECT_TRUE(fs::exists(path("r") / "error_map" / "error_map.csv"));
}

// 12. Out-of-range options are refused (they used to wrap or give negative/null results).
TEST_F(Hardening, Group12_OptionRanges) {
  for (const char* beta : {"-1", "0", "nan"})
    EXPECT_REFUSED(sglab(std::string("fit lambda-c --beta ") + beta), "--beta");
  EXPECT_REFUSED(sglab(render_args() + " --out out.exr --seed -1"), "not an integer in [0, 18446744073709551615]");
  EXPECT_REFUSED(sglab(render_args() + " --out out.exr --seed 18446744073709551616"), "18446744073709551616");
  EXPECT_REFUSED(sglab("sweep specular --quick --out sw --threads -1"), "--threads");
  EXPECT_REFUSED(sglab("error-map --quick --out em --size 0"), "--size must be in [2, 2000], got 0");
  EXPECT_REFUSED(sglab(render_args() + " --out out.exr --reference-precision half"),
                 "--reference-precision: unknown precision 'half'");
  EXPECT_FALSE(fs::exists(path("out.exr")));
}

// 13. Every CLI parse error exits 2 with CLI11's message; an unknown command says so.
TEST_F(Hardening, Group13_ParseErrorsExit2) {
  EXPECT_REFUSED(sglab("nosuch"), "unknown command 'nosuch'");
  EXPECT_REFUSED(sglab(render_args() + " --out o.exr --nosuch"), "nosuch");
  EXPECT_REFUSED(sglab("eval sg-integral --precision"), "--precision");
  EXPECT_REFUSED(sglab("render"), "scene");
  EXPECT_REFUSED(sglab("render x.json --width abc --out o.exr"), "abc");
  EXPECT_EQ(sglab("--help").status, 0);
  // The vector-unit override is input too: a bad SGLAB_SIMD exits 2 naming it, before any work.
  const auto simd = run_shell("SGLAB_SIMD=avx9000 '" + std::string(SGLAB_EXE) + "' eval sg-integral --method exact");
  EXPECT_EQ(simd.status, 2) << simd.err;
  EXPECT_NE(simd.err.find("SGLAB_SIMD='avx9000'"), std::string::npos) << simd.err;
}

// 14. Messages name the right value and the right cause.
TEST_F(Hardening, Group14_MessagesNameTheValue) {
  EXPECT_REFUSED(sglab(render_args() + " --out out.exr --set camera.width=18446744073709551615"),
                 "18446744073709551615 is outside");
  // A tiny direction is a direction, and a huge up vector is not parallel to anything.
  Result r = sglab(render_args() + " --out t.exr --set 'light.direction=[0,-1e-200,-0.7e-200]'");
  EXPECT_EQ(r.status, 0) << r.err;
  r = sglab(render_args() + " --out u.exr --set 'camera.up=[0,1e300,0]'");
  EXPECT_EQ(r.status, 0) << r.err;
}

// 15. A bad value is quoted short, however long it is.
TEST_F(Hardening, Group15_LongValuesAreClipped) {
  std::ofstream(path("long.txt")) << std::string(100000, 'x');  // below the kernel's 128 KiB per argument
  Result r = sglab(render_args() + " --out out.exr --set \"camera.fov=$(cat long.txt)\"");
  EXPECT_REFUSED(r, "camera.fov");
  r = sglab(render_args() + " --out out.exr --set \"$(cat long.txt)=1\"");
  EXPECT_REFUSED(r, "bytes)");
  r = sglab("eval sg-integral -m exact", "sharpness\n" + std::string(50 << 20, '7') + "x\n");
  EXPECT_REFUSED(r, "bytes)");
}

// 15 and 1, continued: a constant set (`--constants FILE`) is untrusted text too: deep nesting,
// long values, names and keys, and malformed JSON with a long token give short messages.
TEST_F(Hardening, Group15_ConstantSetMessagesAreShort) {
  const std::string eval = "eval clamped-cosine --method sg-cosine --constants record.json";
  const std::string input = "sharpness,cosine\n3,0.25\n";
  const std::string x(100000, 'x');
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{\"fit\": " + std::string(65000, '[') + std::string(65000, ']') + "}", "nested deeper than 64"},
      {R"({"fit": "lambda-d", "parameters": {"lambda_d": ")" + x + R"("}})", "not a number"},
      {R"({"fit": ")" + x + R"(", "parameters": {}})", "unknown fit"},
      {R"({"fit": "lambda-d", "parameters": {")" + x + R"(": 1}})", "unknown parameter"},
      {R"({"fit": "lambda-d", "parameters": {"lambda_d": ")" + x, "not valid JSON"},
      {R"({"fit": "lambda-d", "parameters": {"lambda_d": 3.25}, "objective": ")" + x + R"("}, 1)", "not valid JSON"},
  };
  for (const auto& [record, needle] : cases) {
    std::ofstream(path("record.json")) << record;
    const Result r = sglab(eval, input);
    EXPECT_REFUSED(r, needle);
    EXPECT_NE(r.err.find("record.json"), std::string::npos) << r.err.substr(0, 2000);
  }
}

// 14 and 17, continued (a finding of the scene fuzz target, tests/fuzz/fuzz_scene.cpp): a --set
// value that is not JSON is taken as text; text that is not UTF-8 used to pass validation and
// then make the render or the sweep fail with a raw JSON exception (exit 1) when the scene was
// serialised. It is refused up front.
TEST_F(Hardening, Group17_SetValueNotUtf8IsRefused) {
  const std::string bad = " --set \"$(printf 'description=caf\\351')\"";  // Latin-1 é: byte 0xE9 alone
  Result r = sglab(render_args() + " --out out.exr --stats out.json" + bad);
  EXPECT_REFUSED(r, "not valid UTF-8 text");
  EXPECT_NE(r.err.find("--set description=caf"), std::string::npos) << r.err;
  r = sglab("sweep render --scene " + p("scene.json") + " --rsm 8 --shadow-map 64 --out sw" + bad);
  EXPECT_REFUSED(r, "not valid UTF-8 text");
  EXPECT_FALSE(fs::exists(path("out.exr")));
  EXPECT_FALSE(fs::exists(path("out.json")));
  EXPECT_FALSE(fs::exists(path("sw")));
  // The same text as valid UTF-8 (é = C3 A9) is accepted.
  r = sglab(render_args() + " --out out.exr --set \"$(printf 'description=caf\\303\\251')\"");
  EXPECT_EQ(r.status, 0) << r.err;
  // Paths are recorded in the stats JSON too: an output or scene path that is not UTF-8 is
  // refused before the render, and nothing is written.
  fs::remove(path("out.exr"));
  r = sglab(render_args() + " --out \"$(printf 'caf\\351.exr')\" --stats out.json");
  EXPECT_REFUSED(r, "is not valid UTF-8");
  fs::copy_file(path("scene.json"), path("caf\351.json"));
  r = sglab(render_args("caf\351.json") + " --out out.exr --stats out.json");
  EXPECT_REFUSED(r, "is not valid UTF-8");
  EXPECT_FALSE(fs::exists(path("out.exr")));
  EXPECT_FALSE(fs::exists(path("out.json")));
}

// 16. Sizes are checked before they are allocated, with how much would be needed.
TEST_F(Hardening, Group16_UpFrontSizes) {
  Result r = sglab(render_args() + " --out out.exr --width 16384 --height 16384");
  EXPECT_REFUSED(r, "GB of memory");
  EXPECT_LT(r.seconds, 10);
  EXPECT_REFUSED(sglab("sweep specular --quick --out sw --threads 99999999999"), "99999999999");

  fs::create_directories(path("shards"));
  nlohmann::json m = {
      {"sweep", "toy"}, {"args", {"sweep", "specular"}}, {"grid", "g"}, {"points", 100000000},
      {"shard", "0/2"}, {"columns", {"point", "x"}},     {"rows", 1},   {"points_fnv1a", "8b2ba22e45ea1a52"}};
  std::ofstream(path("shards") / "toy_points.shard-0-of-2.csv") << "point,x\n0,1\n";
  m["points_fnv1a"] = sglab::runner::fnv1a_hex("point,x\n0,1\n");
  std::ofstream(path("shards") / "toy_sweep.shard-0-of-2.json") << m.dump();
  r = sglab("merge --out merged shards");
  EXPECT_REFUSED(r, "the manifests say 100000000 points, the shards hold 1 rows");
  m["points"] = "2";
  std::ofstream(path("shards") / "toy_sweep.shard-0-of-2.json") << m.dump();
  EXPECT_REFUSED(sglab("merge --out merged shards"), "'points' is \"2\", expected a non-negative integer");
}

// 16, continued: `filter` and `filter-sweep` estimate their memory before allocating (the
// documented maximum image, 16384², needs ~100 GB of G-buffers and layers).
TEST_F(Hardening, Group16_FilterMemoryUpFront) {
  Result r = sglab("filter " + p("scene.json") +
                   " --weights normal --out f.exr --stats f.json --quiet --width 16384 --height 16384");
  EXPECT_REFUSED(r, "GB of memory");
  EXPECT_NE(r.err.find("16384×16384 filter run"), std::string::npos) << r.err;
  EXPECT_LT(r.seconds, 10);
  EXPECT_FALSE(fs::exists(path("f.exr")));
  EXPECT_FALSE(fs::exists(path("f.json")));
  r = sglab("filter-sweep --scene " + p("scene.json") +
            " --roughness 0.1,0.2 --scale 1,2 --weights normal --out fs --quiet --width 16384 --height 16384");
  EXPECT_REFUSED(r, "GB of memory");
  EXPECT_NE(r.err.find("4 × a 16384×16384 filter run at 1/1 resolution"), std::string::npos) << r.err;
  EXPECT_LT(r.seconds, 10);
  EXPECT_FALSE(fs::exists(path("fs")));
}

// 17. Minor: NUL bytes, stdin as a directory, a trailing blank line, a subnormal λ.
TEST_F(Hardening, Group17_Minor) {
  Result r = sglab("eval sg-integral -m exact", std::string("sharpness\n1\0x\n", 14));
  EXPECT_REFUSED(r, "value '1\\x00x'");
  {  // standard input redirected from a directory
    const std::string command = fmt::format("'{}' eval sg-integral -m exact < '{}' 2> '{}'", SGLAB_EXE, dir_.string(),
                                            path("err").string());
    const int raw = std::system(command.c_str());
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.err = read_file(path("err"));
  }
  EXPECT_REFUSED(r, "standard input is a directory");
  r = sglab("eval clamped-cosine -m tokuyoshi2024", "sharpness,cosine\n1,0.5\n\n\n");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 2);
  EXPECT_REFUSED(sglab("eval sg-integral -m exact", "sharpness\n1e-310\n"), "subnormal");
  EXPECT_REFUSED(sglab("eval sg-integral -m approx --precision float", "sharpness\n1e-39\n"), "subnormal");
}

}  // namespace
