// Shared test helpers: fixed, printed seeds and the grids the core tests sweep; a fresh directory
// per test and a captured run of the built `sglab` binary for the end-to-end tests.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sglab/stiff_cases.hpp"

namespace sglab::test {

// A seeded generator whose seed is printed, so any failure can be replayed
// (SGLAB_TEST_SEED=<n> overrides it).
inline std::mt19937_64 seeded_rng(std::uint64_t default_seed) {
  std::uint64_t seed = default_seed;
  if (const char* env = std::getenv("SGLAB_TEST_SEED")) seed = std::strtoull(env, nullptr, 10);
  std::printf("[ seed     ] %llu (replay with SGLAB_TEST_SEED=%llu)\n", static_cast<unsigned long long>(seed),
              static_cast<unsigned long long>(seed));
  return std::mt19937_64(seed);
}

// The grids live in core/include/sglab/stiff_cases.hpp, shared with the stability atlas
// (`sglab stability`), so the tests and the atlas sweep the same stiff inputs.

// log-spaced values from 10^lo to 10^hi, `per_decade` points per decade, ends included.
inline std::vector<double> log_grid(double lo, double hi, int per_decade) {
  return stiff::log_grid(lo, hi, per_decade);
}

// The stiff sharpnesses of docs/math.md §10: 0 and 1e-8 … 1e8.
inline std::vector<double> stiff_sharpnesses(int per_decade = 2) { return stiff::sharpnesses(per_decade); }

// Cosines including ±1 exactly, the float and double rounding steps inside and past ±1, 1 ± 1e-7,
// 0, ±1e-8, and a uniform interior.
inline std::vector<double> stiff_cosines(int interior = 16) { return stiff::cosines(interior); }

inline double relative_error(double value, double reference) {
  if (reference == 0) return std::fabs(value);
  return std::fabs(value - reference) / std::fabs(reference);
}

// ---- end-to-end tests: a fresh directory per test, a captured command ------------------------

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The small scene of the end-to-end render, filter and hardening tests (JSON text): a glossy floor
// (albedo 0.4, F0 0.5, roughness 0.3), a Lambert wall and, with `crate`, a Lambert box, under a
// spotlight (distance 1.2, falloff 4, power 5) aimed from `light_direction` at `light_target`.
struct SmallScene {
  int width = 12, height = 10;
  std::string light_target = "[0, 0, 0]", light_direction = "[0, -1, -0.5]";
  int cone_angle = 30;
  bool crate = true;

  std::string json() const {
    return "{\n  \"camera\": {\"position\": [0, 1, 2.5], \"look_at\": [0, 0.4, 0], \"fov\": 50, \"width\": " +
           std::to_string(width) + ", \"height\": " + std::to_string(height) +
           "},\n  \"light\": {\"target\": " + light_target + ", \"direction\": " + light_direction +
           ", \"distance\": 1.2, \"cone_angle\": " + std::to_string(cone_angle) +
           ", \"falloff\": 4, \"power\": 5},\n  \"objects\": [\n"
           "    {\"name\": \"floor\", \"type\": \"rectangle\", \"corner\": [-1, 0, -1], \"edge_u\": [0, 0, 2], "
           "\"edge_v\": [2, 0, 0],\n"
           "     \"material\": {\"albedo\": 0.4, \"f0\": 0.5, \"roughness\": 0.3}},\n"
           "    {\"name\": \"wall\", \"type\": \"rectangle\", \"corner\": [-1, 0, -1], \"edge_u\": [2, 0, 0], "
           "\"edge_v\": [0, 2, 0],\n"
           "     \"material\": {\"albedo\": [0.7, 0.6, 0.5]}}" +
           (crate
                ? ",\n    {\"name\": \"crate\", \"type\": \"box\", \"min\": [0.3, 0, -0.6], \"max\": [0.7, 0.4, -0.2], "
                  "\"material\": {\"albedo\": 0.5}}"
                : "") +
           "\n  ]\n}";
  }
};

// For an image read by sglab::render::read_exr: each of `layers` has R, G and B channels, and the
// layer "error" is `value` − `reference` pixel by pixel, up to the float rounding of the stored
// layers. Returns the sum of `reference` over every pixel and channel (its energy).
template <class Image>
double expect_error_layer(const Image& image, const std::vector<std::string>& layers, const std::string& value,
                          const std::string& reference) {
  for (const auto& layer : layers)
    for (const char* c : {"R", "G", "B"}) EXPECT_TRUE(image.channels.count(layer + "." + c)) << layer << c;
  double energy = 0;
  for (const std::string c : {"R", "G", "B"}) {
    const auto& e = image.channels.at("error." + c);
    const auto& v = image.channels.at(value + "." + c);
    const auto& ref = image.channels.at(reference + "." + c);
    for (std::size_t k = 0; k < e.size(); ++k) {
      EXPECT_NEAR(e[k], v[k] - ref[k], 1e-6 * (std::fabs(v[k]) + std::fabs(ref[k])) + 1e-30);
      energy += ref[k];
    }
  }
  return energy;
}

struct CommandResult {
  int status = -1;  // exit status (-1: did not exit normally)
  std::string out, err;
};

// A fixture with a fresh temporary directory dir_, removed after the test.
// The longest message a refused case may print: the bounded messages of quote() and the message cap
// (text_limits.hpp: 80-character quotes, 2,000 bytes at most) leave a one-error message well below it.
inline constexpr std::size_t kShortMessage = 1000;

class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (std::filesystem::temp_directory_path() / "sglab-test-XXXXXX").string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path path(const std::string& name) const { return dir_ / name; }

  // Runs the shell command line `command` in dir_ with standard input from `stdin_file`; returns
  // its exit status and what it wrote to standard output and error (captured through files that
  // are removed again, so dir_ holds only what the command wrote).
  CommandResult run_shell(const std::string& command, const std::filesystem::path& stdin_file = "/dev/null") const {
    const auto out = path(".stdout"), err = path(".stderr");
    const std::string line = "cd '" + dir_.string() + "' && " + command + " < '" + stdin_file.string() + "' > '" +
                             out.string() + "' 2> '" + err.string() + "'";
    const int raw = std::system(line.c_str());
    CommandResult r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = read_file(out);
    r.err = read_file(err);
    std::filesystem::remove(out);
    std::filesystem::remove(err);
    return r;
  }
  // A run refused as bad input: exit status 2, `expected` in standard error and none of `outputs`
  // (names in dir_) written. `what` names the case in the failure messages.
  void expect_bad_input(const CommandResult& r, const std::string& what, const std::string& expected,
                        const std::vector<std::string>& outputs) const {
    EXPECT_EQ(r.status, 2) << what << "\n" << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << what << "\n  stderr: " << r.err;
    for (const auto& o : outputs) EXPECT_FALSE(std::filesystem::exists(path(o))) << what << ": " << o;
  }
  // The hardening form: exit status 2, a message holding `needle` and shorter than kShortMessage,
  // none of `outputs`.
  void refused(const CommandResult& r, const std::string& needle, const std::vector<std::string>& outputs = {}) const {
    expect_bad_input(r, needle, needle, outputs);
    EXPECT_LT(r.err.size(), kShortMessage) << r.err.substr(0, 2000);
  }
#ifdef SGLAB_EXE
  // `sglab ARGS` in dir_ (ARGS as shell words: quote paths).
  CommandResult sglab(const std::string& args, const std::filesystem::path& stdin_file = "/dev/null") const {
    return run_shell(std::string("'") + SGLAB_EXE + "' " + args, stdin_file);
  }
#endif

  std::filesystem::path dir_;
};

}  // namespace sglab::test
