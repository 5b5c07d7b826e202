// Hostile and careless inputs to the environment-map commands, merges and constant sets, one test
// per group of failures they used to cause: inputs overwritten and outputs not one set (A),
// unbounded messages (B), memory or time unbounded by tiny inputs (C), bad values accepted (D),
// unchecked mixture records (E), Inf/NaN written with exit status 0 (F), stale or mixed results
// (H), exit status and determinism of constant sets (I). Each case runs the built `sglab`, and
// asserts the exit status, that the message is short and names the value, and that no output was
// written and no input changed. Expected values come from closed forms or from the same command on
// an equivalent input, never from the code under test.
#include <sys/stat.h>
#include <unistd.h>

#include <cfloat>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sglab/envmap.hpp"
#include "sglab/render/environment.hpp"
#include "sglab/render/exr.hpp"
#include "sglab/render/mixture_record.hpp"
#include "sweep.hpp"
#include "test_util.hpp"

namespace {

namespace fs = std::filesystem;
using sglab::test::CommandResult;
using sglab::test::read_file;

using sglab::test::kShortMessage;

class HardeningEnvmap : public sglab::test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    // A 16 × 8 map of one RGB lobe (texel means), and the lobe as a mixture record.
    std::ofstream(path("m.exr"), std::ios::binary)
        << sglab::render::encode_environment(sglab::rasterize_mixture({lobe()}, 16, 8, 2));
    write_mixture("fit.json", {{"lobe0.axis_x", 0.0},
                               {"lobe0.axis_y", 0.6},
                               {"lobe0.axis_z", 0.8},
                               {"lobe0.sharpness", 4.0},
                               {"lobe0.r", 1.0},
                               {"lobe0.g", 2.0},
                               {"lobe0.b", 0.5}});
    std::ofstream(path("in.csv")) << "sharpness,cosine\n1,0.5\n";
  }
  static sglab::SgLight lobe() {
    sglab::SgLight l;
    l.axis = sglab::Vec3<double>(0, 0.6, 0.8);
    l.sharpness = 4;
    l.amplitude = {1, 2, 0.5};
    return l;
  }
  void write_mixture(const std::string& name, const nlohmann::json& parameters,
                     const std::string& fit = "envmap") const {
    std::ofstream(path(name)) << nlohmann::json{{"fit", fit}, {"parameters", parameters}}.dump();
  }
};

// A. An output that is an input, two outputs on one file, an output set with one bad member:
// refused before anything is written; a merge whose summary is refused leaves no merged output.
TEST_F(HardeningEnvmap, GroupA_OutputsAreOneSetAndNeverInputs) {
  const std::string map = read_file(path("m.exr")), fit = read_file(path("fit.json"));
  refused(sglab("fit envmap m.exr --lobes 1 --json m.exr"), "refusing to overwrite an input");
  refused(sglab("envmap render m.exr --mixture fit.json --res 4 --out m.exr"), "refusing to overwrite an input");
  refused(sglab("envmap render m.exr --mixture fit.json --res 4 --out fit.json"), "refusing to overwrite an input");
  refused(sglab("envmap make mixture --mixture fit.json --width 8 --out fit.json"), "refusing to overwrite an input");
  EXPECT_EQ(read_file(path("m.exr")), map);
  EXPECT_EQ(read_file(path("fit.json")), fit);
  refused(sglab("fit envmap m.exr --lobes 1 --json o.out --exr o.out"), "each output needs its own file", {"o.out"});
  fs::create_directories(path("dir"));
  refused(sglab("fit envmap m.exr --lobes 1 --json f.json --exr dir"), "is a directory", {"f.json"});
  refused(sglab("envmap render m.exr --mixture fit.json --res 4 --out r.exr --stats dir"), "is a directory", {"r.exr"});

  // A merge whose shards check but whose summary is refused (the scene was edited after the
  // shards ran, so the merged output is not the sweep the scene now defines): the merged
  // per-point CSV and manifest are removed again.
  std::ofstream(path("scene.json")) << sglab::test::SmallScene{.crate = false}.json();
  const std::string sweep =
      "sweep render --scene scene.json --rsm 8 --shadow-map 16 --width 8 --height 8 --vary light.power=1,2 --table t "
      "--out shards";
  for (const char* shard : {"0/2", "1/2"}) ASSERT_EQ(sglab(sweep + " --shard " + shard).status, 0);
  nlohmann::json edited = nlohmann::json::parse(read_file(path("scene.json")));
  edited["description"] = "edited after the shards ran";
  std::ofstream(path("scene.json")) << edited.dump();
  const CommandResult r = sglab("merge --out merged shards");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_FALSE(fs::exists(path("merged/t_points.csv"))) << r.err;
  EXPECT_FALSE(fs::exists(path("merged/t_sweep.json")));
}

// B. A 100 KB name in any name option gives a message of at most a clipped quote.
TEST_F(HardeningEnvmap, GroupB_LongNamesAreClipped) {
  const std::string x(100000, 'x');
  std::ofstream(path("long.txt")) << x;
  for (const std::string args :
       {"eval clamped-cosine --method \"$(cat long.txt)\" --in /dev/null", "eval \"$(cat long.txt)\" --method x",
        "envmap make \"$(cat long.txt)\" --out o.exr", "fit envmap m.exr --lobes 1 --method \"$(cat long.txt)\"",
        "envmap render m.exr --mixture fit.json --geometry \"$(cat long.txt)\" --out o.exr",
        "envmap render m.exr --mixture fit.json --diffuse \"$(cat long.txt)\" --res 4 --out o.exr",
        "envmap make sky --width \"$(cat long.txt)\" --out o.exr", "reproduce --only \"$(cat long.txt)\"",
        "envmap lobes --env \"$(cat long.txt)\""}) {
    const CommandResult r = sglab(args);
    EXPECT_EQ(r.status, 2) << args << "\n" << r.err.substr(0, 300);
    EXPECT_LT(r.err.size(), kShortMessage) << args << "\n" << r.err.substr(0, 300);
    EXPECT_NE(r.err.find("xxxxxxxx"), std::string::npos) << args << ": the message names the value\n"
                                                         << r.err.substr(0, 300);
  }
  EXPECT_FALSE(fs::exists(path("o.exr")));
}

// C. Sizes refused before anything is allocated or read: an EXR whose header claims 65536 × 32768
// (the file holds only its offset table), one within the limits whose file is far too small for
// its pixels, a constant set that is a device or a FIFO (which never ends or blocks), a sphere
// image of 100000².
TEST_F(HardeningEnvmap, GroupC_SizesRefusedBeforeAllocation) {
  const auto header_only = [&](const std::string& name, int w, int h) {
    Imf::Header header(w, h);
    for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(path(name).c_str(), header);  // no pixels written: the file is the header and offset table
  };
  header_only("huge.exr", 65536, 32768);
  header_only("big.exr", 8192, 4096);
  const auto t0 = std::chrono::steady_clock::now();
  refused(sglab("fit envmap huge.exr --lobes 1 --json f.json"), "not a readable EXR", {"f.json"});
  refused(sglab("fit envmap big.exr --lobes 1 --json f.json"), "more than a file of", {"f.json"});
  EXPECT_THROW(sglab::render::read_exr(path("big.exr").string()), std::runtime_error);
  ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0600), 0);
  refused(sglab("eval clamped-cosine --method sg-cosine --in in.csv --constants /dev/zero"), "not a regular file");
  refused(sglab("eval clamped-cosine --method sg-cosine --in in.csv --constants fifo"), "not a regular file");
  refused(sglab("envmap render m.exr --mixture fifo --res 4 --out o.exr"), "not a regular file", {"o.exr"});
  refused(sglab("envmap render fifo --mixture fit.json --res 4 --out o.exr"), "not a regular file", {"o.exr"});
  refused(sglab("envmap lobes --env a=m.exr --res 100000"), "[2, 2048]");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 60);
}

// D. Values outside an option's domain: exit 2 naming the value, nothing written.
TEST_F(HardeningEnvmap, GroupD_BadOptionValues) {
  refused(sglab("fit envmap m.exr --lobes 1 --threads 0 --json f.json"), "'0' is not an integer in [1,", {"f.json"});
  refused(sglab("fit envmap m.exr --lobes 1 --max-iterations -1 --json f.json"), "'-1' is not an integer in [1,",
          {"f.json"});
  for (const char* v : {"nan", "inf", "-inf", "1e999"})
    refused(sglab(fmt::format("envmap make sky --width 8 --sun-azimuth {} --out o.exr", v)), "is not a finite number",
            {"o.exr"});
  for (const char* v : {"nan", "0", "-1", "2", "1e-300"})
    refused(sglab(fmt::format("envmap lobes --env a=m.exr --roughness {} --quick --out o --tables-dir o", v)),
            "is not a finite number", {"o"});
  for (const char* v : {"0", "-3"})
    refused(sglab(fmt::format("envmap lobes --env a=m.exr --res {} --quick --out o", v)), "[2, 2048]", {"o"});
  refused(sglab("envmap lobes --env \"$(printf 'a\\nb')=m.exr\" --quick --out o --tables-dir o"), "a\\x0ab=m.exr",
          {"o"});
  refused(sglab("sweep specular --quick --shard '' --out o"), "an empty shard", {"o"});
}

// E. Mixture records: every key a lobe field, every lobe whole, axes normalised without overflow,
// the record of this fit only.
TEST_F(HardeningEnvmap, GroupE_MixtureRecords) {
  const nlohmann::json one = {{"lobe0.axis_x", 0.0},    {"lobe0.axis_y", 0.0}, {"lobe0.axis_z", 1.0},
                              {"lobe0.sharpness", 3.0}, {"lobe0.r", 1.0},      {"lobe0.g", 1.0},
                              {"lobe0.b", 1.0}};
  nlohmann::json gap = one;
  for (const char* f : {"axis_x", "axis_y", "axis_z", "sharpness", "r", "g", "b"}) gap[std::string("lobe2.") + f] = 1.0;
  write_mixture("gap.json", gap);
  refused(sglab("envmap make mixture --mixture gap.json --width 8 --out o.exr"), "\"lobe1.axis_x\" is missing",
          {"o.exr"});
  nlohmann::json unknown = one;
  unknown["lobe0.sharpnes"] = 1.0;
  write_mixture("unknown.json", unknown);
  refused(sglab("envmap make mixture --mixture unknown.json --width 8 --out o.exr"),
          "'lobe0.sharpnes' is not a lobe field", {"o.exr"});
  write_mixture("other.json", one, "lambda-d");
  refused(sglab("envmap make mixture --mixture other.json --width 8 --out o.exr"), "\"fit\" is '\"lambda-d\"'",
          {"o.exr"});
  nlohmann::json zero = one;
  zero["lobe0.axis_z"] = 0.0;
  write_mixture("zero.json", zero);
  refused(sglab("envmap make mixture --mixture zero.json --width 8 --out o.exr"), "lobe0 has the zero axis", {"o.exr"});
  // (0, 0, 1e200) is the axis +z: the same map as (0, 0, 1), byte for byte.
  nlohmann::json far = one;
  far["lobe0.axis_z"] = 1e200;
  write_mixture("one.json", one);
  write_mixture("far.json", far);
  ASSERT_EQ(sglab("envmap make mixture --mixture one.json --width 16 --out one.exr").status, 0);
  ASSERT_EQ(sglab("envmap make mixture --mixture far.json --width 16 --out far.exr").status, 0);
  const auto a = sglab::render::load_environment(path("one.exr").string()),
             b = sglab::render::load_environment(path("far.exr").string());
  EXPECT_EQ(a.texels, b.texels);
  const sglab::SgMixture m = sglab::render::load_mixture(path("far.json").string());
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].axis, sglab::Vec3<double>(0, 0, 1));
}

// F. Values that would overflow to Inf or NaN downstream are refused up front: a sun whose texels
// overflow float, amplitudes of 1e308, a roughness of 1e-300, a lobe of sharpness 1e8.
TEST_F(HardeningEnvmap, GroupF_NoInfOrNullWritten) {
  refused(sglab("envmap make sky --width 8 --sun-luminance 1e308 --out o.exr"),
          "'1e308' is not a finite number in [0, 1e+30]", {"o.exr"});
  nlohmann::json big = {{"lobe0.axis_x", 0.0}, {"lobe0.axis_y", 0.0}, {"lobe0.axis_z", 1.0}, {"lobe0.sharpness", 3.0},
                        {"lobe0.r", 1e308},    {"lobe0.g", 1.0},      {"lobe0.b", 1.0}};
  write_mixture("big.json", big);
  refused(sglab("envmap make mixture --mixture big.json --width 8 --out o.exr"), "lobe0.r 1e+308 is outside [0, 1e+30]",
          {"o.exr"});
  refused(sglab("envmap render m.exr --mixture fit.json --res 4 --roughness 1e-300 --out o.exr"),
          "is not a finite number in [0.001, 1]", {"o.exr"});
  big["lobe0.r"] = 1.0;
  big["lobe0.sharpness"] = 1e8;
  write_mixture("sharp.json", big);
  refused(sglab("envmap render m.exr --mixture sharp.json --res 4 --out o.exr"),
          "lobe0.sharpness 100000000 is outside [0, 1e+06]", {"o.exr"});
  // The largest accepted amplitude renders to finite layers and statistics.
  big["lobe0.sharpness"] = sglab::render::kMaxMixtureSharpness;
  big["lobe0.r"] = sglab::render::kMaxMixtureAmplitude;
  write_mixture("edge.json", big);
  const CommandResult r = sglab(
      "envmap render m.exr --mixture edge.json --res 4 --roughness 0.001 --out o.exr --stats s.json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(read_file(path("s.json")).find("null"), std::string::npos) << read_file(path("s.json"));
}

// H. Fingerprints cover contents: a sweep rerun after its constant set was edited recomputes; a
// shard manifest of another version, or without one, is not merged.
TEST_F(HardeningEnvmap, GroupH_FingerprintsCoverContents) {
  std::ofstream(path("scene.json")) << sglab::test::SmallScene{.crate = false}.json();
  std::ofstream(path("ld.json")) << R"({"fit": "lambda-d", "parameters": {"lambda_d": 3.25}})";
  const std::string sweep =
      "sweep render --scene scene.json --rsm 8 --shadow-map 16 --width 8 --height 8 --constants ld.json --out sw";
  ASSERT_EQ(sglab(sweep).status, 0);
  CommandResult r = sglab(sweep);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("finished earlier"), std::string::npos) << r.err;
  std::ofstream(path("ld.json")) << R"({"fit": "lambda-d", "parameters": {"lambda_d": 4.5}})";
  r = sglab(sweep);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("finished earlier"), std::string::npos) << r.err;

  const std::string shards =
      "sweep render --scene scene.json --rsm 8 --shadow-map 16 --width 8 --height 8 --vary light.power=1,2 --table t "
      "--out shards";
  for (const char* shard : {"0/2", "1/2"}) ASSERT_EQ(sglab(shards + " --shard " + shard).status, 0);
  const fs::path manifest = path("shards/t_sweep.shard-1-of-2.json");
  nlohmann::json m = nlohmann::json::parse(read_file(manifest));
  m["version"] = "sglab 0.0.1";
  std::ofstream(manifest) << m.dump();
  refused(sglab("merge --out merged shards"), "written by 'sglab 0.0.1'", {"merged/t_points.csv"});
  m.erase("version");
  std::ofstream(manifest) << m.dump();
  refused(sglab("merge --out merged shards"), "the manifest has no 'version'", {"merged/t_points.csv"});
}

// I. Constant sets: a symbolic link loop, a 4000-character path and two records setting one
// constant are bad input (exit 2, a short message), never a filesystem error or a silent winner.
TEST_F(HardeningEnvmap, GroupI_ConstantSetDirectories) {
  const std::string eval = "eval clamped-cosine --method sg-cosine --in in.csv --constants ";
  fs::create_directories(path("loop"));
  fs::create_symlink("x.json", path("loop/x.json"));  // a link to itself
  std::ofstream(path("loop/a.json")) << R"({"fit": "lambda-d", "parameters": {"lambda_d": 3.25}})";
  refused(sglab(eval + "loop"), "'x.json' cannot be examined");
  refused(sglab(eval + std::string(4000, 'p')), "cannot be examined");
  fs::create_directories(path("two"));
  std::ofstream(path("two/a.json")) << R"({"fit": "lambda-d", "parameters": {"lambda_d": 3.25}})";
  std::ofstream(path("two/b.json")) << R"({"fit": "lambda-d", "parameters": {"lambda_d": 4.5}})";
  refused(sglab(eval + "two"), "lambda-d.lambda_d is set by two records");
}

}  // namespace
