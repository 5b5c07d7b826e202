// A seeded fuzz test of the two parsers that read untrusted text: the CSV reader (every `sglab`
// command that reads a table) and the scene reader (`render`, `filter`, `sweep render`: JSON,
// --set overrides, validation). Valid documents are mutated at random (bytes replaced, inserted,
// deleted, slices duplicated, nesting and numbers at their limits); every result must be either a
// parsed value or the parser's own error (InputError, SceneError) with a short message — never
// another exception, a crash or a message as long as the input. Fixed seeds, printed on failure,
// so a failure reproduces; a few thousand cases a parser, about a second.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "constant_sets.hpp"
#include "input_error.hpp"
#include "csv.hpp"
#include "parse_number.hpp"
#include "sglab/render/scene.hpp"
#include "parse_number_mp50.hpp"

namespace {

constexpr std::size_t kMaxMessage = 1000;

const std::vector<std::string> kTokens = {"[",
                                          "]",
                                          "{",
                                          "}",
                                          "\"",
                                          ",",
                                          "\n",
                                          "\r\n",
                                          std::string(1, '\0'),
                                          "\\",
                                          "1e999",
                                          "-1",
                                          "0",
                                          "1e-320",
                                          "18446744073709551616",
                                          "nan",
                                          "null",
                                          ":",
                                          std::string(200, '['),
                                          std::string(100, 'x'),
                                          "\xEF\xBB\xBF",
                                          "\xff"};

std::string mutate(std::string s, std::mt19937_64& rng) {
  const int edits = 1 + int(rng() % 6);
  for (int e = 0; e < edits; ++e) {
    const std::size_t at = s.empty() ? 0 : rng() % (s.size() + 1);
    switch (rng() % 5) {
      case 0:  // replace a byte
        if (!s.empty()) s[at % s.size()] = char(rng() % 256);
        break;
      case 1:  // insert a token
        s.insert(at, kTokens[rng() % kTokens.size()]);
        break;
      case 2:  // delete a slice
        if (!s.empty()) s.erase(at % s.size(), 1 + rng() % 8);
        break;
      case 3: {  // duplicate a slice
        if (s.empty()) break;
        const std::size_t from = rng() % s.size(), n = 1 + rng() % 40;
        s.insert(at, s.substr(from, n));
        break;
      }
      default:  // cut the text short
        s.resize(at);
    }
  }
  return s;
}

const char* kCsv =
    "sharpness,cosine,note\n"
    "1,0.5,plain\n"
    "1e8,-1,\"quoted, with comma\"\n"
    "0.001,1,\"two\n lines\"\n";

TEST(ParserFuzz, CsvReaderFailsOnlyWithShortUsageErrors) {
  for (std::uint64_t seed = 1; seed <= 4000; ++seed) {
    std::mt19937_64 rng(seed);
    const std::string text = mutate(kCsv, rng);
    std::istringstream in(text);
    try {
      const auto table = sglab::runner::read_csv(in, "<fuzz>");
      for (const auto& row : table.rows) ASSERT_EQ(row.fields.size(), table.header.size()) << "seed " << seed;
    } catch (const sglab::runner::InputError& e) {
      ASSERT_LT(std::string(e.what()).size(), kMaxMessage) << "seed " << seed;
    } catch (const std::exception& e) {
      FAIL() << "seed " << seed << ": unexpected " << typeid(e).name() << ": " << e.what();
    }
  }
}

const char* kSceneText = R"({
  "description": "fuzz",
  "camera": {"position": [0, 1, 2.5], "look_at": [0, 0.4, 0], "up": [0, 1, 0], "fov": 50, "width": 12, "height": 10},
  "light": {"target": [0, 0, 0], "direction": [0, -1, -0.5], "distance": 1.2, "cone_angle": 30, "falloff": 4, "power": [5, 5, 5]},
  "objects": [
    {"name": "floor", "type": "rectangle", "corner": [-1, 0, -1], "edge_u": [0, 0, 2], "edge_v": [2, 0, 0],
     "material": {"albedo": 0.4, "f0": 0.5, "roughness": 0.3}},
    {"name": "crate", "type": "box", "min": [0.3, 0, -0.6], "max": [0.7, 0.4, -0.2], "material": {"albedo": 0.5}},
    {"name": "ball", "type": "sphere", "center": [0, 0.5, 0], "radius": 0.2, "material": {"albedo": [0.1, 0.2, 0.3]}}
  ]
})";

const std::vector<std::string> kOverrides = {"floor.roughness=0.1",
                                             "light.power=1e300",
                                             "camera.width=18446744073709551615",
                                             "objects.0.edge_u=[1e200,0,0]",
                                             "light.direction=[0,-1e-200,0]",
                                             "crate.max=[[[[1]]]]",
                                             "camera.fov=\"x\"",
                                             "objects.9.name=q",
                                             "a..b=1",
                                             "ball.radius=-0",
                                             "light=5"};

TEST(ParserFuzz, SceneReaderFailsOnlyWithShortSceneErrors) {
  for (std::uint64_t seed = 1; seed <= 3000; ++seed) {
    std::mt19937_64 rng(seed);
    const std::string text = mutate(kSceneText, rng);
    try {
      nlohmann::json document = sglab::render::parse_scene_text(text, "<fuzz>");
      if (rng() % 2) {
        std::string o = kOverrides[rng() % kOverrides.size()];
        if (rng() % 2) o = mutate(o, rng);
        sglab::render::apply_override(document, o);
      }
      const sglab::render::Scene scene = sglab::render::parse_scene(document);
      ASSERT_GE(scene.camera.width, 1) << "seed " << seed;
      ASSERT_FALSE(scene.objects.empty()) << "seed " << seed;
    } catch (const sglab::render::SceneError& e) {
      ASSERT_LT(std::string(e.what()).size(), kMaxMessage)
          << "seed " << seed << ": " << std::string(e.what()).substr(0, 300);
    } catch (const std::exception& e) {
      FAIL() << "seed " << seed << ": unexpected " << typeid(e).name() << ": " << std::string(e.what()).substr(0, 300);
    }
  }
}

// The constant-set reader (`--constants FILE`): a fit record as `sglab fit NAME --json` writes it,
// mutated; each result is either a set or the reader's InputError with a short message.
const char* kFitRecord = R"({
  "fit": "lambda-c",
  "parameters": {"lambda_c": 0.63, "sigma_n2": 0.054},
  "objective": "least squares of the filter's normal weight",
  "precision": "double"
})";

TEST(ParserFuzz, ConstantSetReaderFailsOnlyWithShortUsageErrors) {
  const auto dir = std::filesystem::temp_directory_path() / ("sglab-parser-fuzz-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto file = dir / "record.json";
  const std::vector<std::string> records = {kFitRecord, R"({"fit": "lambda-d", "parameters": {"lambda_d": 3.25}})"};
  for (std::uint64_t seed = 1; seed <= 3000; ++seed) {
    std::mt19937_64 rng(seed);
    std::ofstream(file, std::ios::binary) << mutate(records[seed % records.size()], rng);
    try {
      const auto set = sglab::frontend::load_constant_sets({file.string()});
      for (const auto& v : set.values) ASSERT_TRUE(std::isfinite(v.value)) << "seed " << seed;
    } catch (const sglab::runner::InputError& e) {
      ASSERT_LT(std::string(e.what()).size(), kMaxMessage)
          << "seed " << seed << ": " << std::string(e.what()).substr(0, 300);
    } catch (const std::exception& e) {
      FAIL() << "seed " << seed << ": unexpected " << typeid(e).name() << ": " << std::string(e.what()).substr(0, 300);
    }
  }
  std::filesystem::remove_all(dir);
}

// The number grammar of every table-reading command (runner/parse_number.hpp): optional spaces or
// tabs around, optional sign, digits with an optional fraction, an optional exponent; finite,
// normal values of the type only. Each accepted text with its value (the compiler's reading of
// the same literal), each refused one with the reason the message gives.
TEST(NumberGrammar, AcceptedTextsAndTheirValues) {
  using sglab::runner::parse_decimal;
  const std::pair<const char*, double> accepted[] = {
      {"0.5", 0.5},
      {"-0.5", -0.5},
      {"+2", 2.0},
      {"1.", 1.0},
      {".5", 0.5},
      {"-.5", -0.5},
      {"1e3", 1e3},
      {"1E-3", 1e-3},
      {"-1.5e+2", -150.0},
      {"2.5E2", 250.0},
      {"0", 0.0},
      {"-0", -0.0},
      {"000123", 123.0},
      {" 0.25", 0.25},
      {"0.25 ", 0.25},
      {"\t7", 7.0},
      {" \t-3e-1\t ", -0.3},
      {"1e308", 1e308},
      {"2.2250738585072014e-308", 2.2250738585072014e-308},
      {"0.1", 0.1},
      {"123456789012345678901234567890", 123456789012345678901234567890.0},
  };
  for (const auto& [text, value] : accepted) {
    double got = 0;
    ASSERT_NO_THROW(got = parse_decimal<double>(text)) << "'" << text << "'";
    EXPECT_EQ(got, value) << "'" << text << "'";
    EXPECT_EQ(std::signbit(got), std::signbit(value)) << "'" << text << "'";
  }
  EXPECT_EQ(parse_decimal<float>("0.1"), 0.1f);
  EXPECT_EQ(parse_decimal<float>("3.4e38"), 3.4e38f);
  EXPECT_EQ(parse_decimal<float>(" 1.17549435e-38"), 1.17549435e-38f);
  // mp50 reads the decimal text itself, not its double rounding.
  EXPECT_EQ(parse_decimal<sglab::mp50>("0.1"), sglab::mp50("0.1"));
  EXPECT_EQ(parse_decimal<sglab::mp50>("-1.25e-3 "), sglab::mp50("-0.00125"));
}

TEST(NumberGrammar, RefusedTextsNameTheReason) {
  using sglab::runner::NumberError;
  using sglab::runner::parse_decimal;
  const char* not_numbers[] = {
      " ",
      "\t",
      "0.5x",
      "x0.5",
      "1e",
      "1e+",
      "1e-",
      "e5",
      ".",
      "-",
      "+",
      "+-1",
      "--1",
      "1..2",
      "1.2.3",
      "1e5.5",
      "1e5e5",
      "0x10",
      "0x1p3",
      "nan",
      "NaN",
      "-nan",
      "inf",
      "-inf",
      "+inf",
      "infinity",
      "1,5",
      "1 2",
      "1_000",
      "0.5\n",
      "\n0.5",
      "0.5\r",
      "１",
      "1e+-5",
      ".e5",
      "- 1",
      "1.5f",
      "1d0",
      "0b1",
      "\xEF\xBB\xBF"
      "1",
  };
  for (const char* text : not_numbers) {
    try {
      (void)parse_decimal<double>(text);
      ADD_FAILURE() << "accepted '" << text << "'";
    } catch (const NumberError& e) {
      EXPECT_NE(std::string(e.what()).find("not a number"), std::string::npos) << "'" << text << "': " << e.what();
    }
  }
  EXPECT_THROW((void)parse_decimal<double>(""), NumberError);
  // Out of double's range, subnormals included: refused in double, and mp50 numbers (mp50 reads
  // them into its own, far wider range; its callers validate them through validation_double).
  const std::pair<const char*, const char*> out_of_range[] = {
      {"1e309", "too large"},          {"-1e400", "too large"},           {"1e-400", "too close to zero"},
      {"4e-320", "too close to zero"}, {"2.2e-308", "too close to zero"},
  };
  for (const auto& [text, why] : out_of_range) {
    try {
      (void)parse_decimal<double>(text);
      ADD_FAILURE() << "accepted '" << text << "'";
    } catch (const NumberError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << "'" << text << "': " << e.what();
    }
    sglab::mp50 got;
    ASSERT_NO_THROW(got = parse_decimal<sglab::mp50>(text)) << "'" << text << "'";
    EXPECT_EQ(got, sglab::mp50(text)) << "'" << text << "'";
    EXPECT_TRUE(sglab::runner::outside_double(got)) << "'" << text << "'";
  }
  // mp50's own range ends: the decimal exponent is judged on the text (a 10^(10^12) is never
  // converted), then the value.
  const std::pair<const char*, const char*> out_of_mp50[] = {
      {"1e999999999999", "too large"},
      {"-1e999999999999", "too large"},
      {"1e-999999999999", "too close to zero"},
      {"0.000001e-999999999999", "too close to zero"},
      {"1e99999999999999999999999999", "too large"},
      {"123456e-99999999999999999999999999", "too close to zero"},
  };
  for (const auto& [text, why] : out_of_mp50) {
    try {
      (void)parse_decimal<sglab::mp50>(text);
      ADD_FAILURE() << "accepted '" << text << "'";
    } catch (const NumberError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << "'" << text << "': " << e.what();
      EXPECT_NE(std::string(e.what()).find("mp50"), std::string::npos) << "'" << text << "': " << e.what();
    }
  }
  // A zero mantissa is 0 whatever its exponent; the largest and smallest decimal exponents mp50 holds.
  EXPECT_EQ(parse_decimal<sglab::mp50>("0e-999999999999"), 0);
  EXPECT_EQ(parse_decimal<sglab::mp50>("-0.000e999999999999"), 0);
  EXPECT_EQ(parse_decimal<sglab::mp50>("1e100000"), sglab::mp50("1e100000"));
  EXPECT_EQ(parse_decimal<sglab::mp50>("1e-100000"), sglab::mp50("1e-100000"));
  // The stand-ins rows are validated with: ±DBL_MAX past double, ±DBL_MIN below its smallest normal.
  constexpr double kMax = std::numeric_limits<double>::max(), kMin = std::numeric_limits<double>::min();
  EXPECT_EQ(sglab::runner::validation_double(sglab::mp50("1e400")), kMax);
  EXPECT_EQ(sglab::runner::validation_double(sglab::mp50("-1e400")), -kMax);
  EXPECT_EQ(sglab::runner::validation_double(sglab::mp50("1e-400")), kMin);
  EXPECT_EQ(sglab::runner::validation_double(sglab::mp50("-1e-400")), -kMin);
  EXPECT_EQ(sglab::runner::validation_double(sglab::mp50("0.5")), 0.5);
  EXPECT_FALSE(sglab::runner::outside_double(sglab::mp50(kMax)));
  EXPECT_FALSE(sglab::runner::outside_double(sglab::mp50(kMin)));
  EXPECT_FALSE(sglab::runner::outside_double(sglab::mp50(0)));
  for (const char* text : {"3.5e38", "1e39", "1e-40", "1e-46", "1.1e-38"})
    EXPECT_THROW((void)parse_decimal<float>(text), NumberError) << text;
}

}  // namespace
