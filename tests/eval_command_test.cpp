// `sglab eval` end to end: runs the built binary (SGLAB_EXE) on CSV files in a temporary directory
// and compares its output with direct calls into core/, its error paths with the documented
// requires (status, a message naming row, column and value, no output file), and --list with the
// registry. Quantities and methods are enumerated from sglab::quantities(), never listed here.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sglab/clamped_cosine.hpp"
#include "sglab/registry.hpp"
#include "test_util.hpp"
#include "sglab/mp50.hpp"

namespace {

namespace fs = std::filesystem;

using Result = sglab::test::CommandResult;
using sglab::test::read_file;

void write_file(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, sep)) parts.push_back(part);
  if (!s.empty() && s.back() == sep) parts.emplace_back();
  return parts;
}

// The `value` column (last field) of each data row of an output without quoted fields.
std::vector<std::string> values_of(const std::string& csv) {
  std::vector<std::string> values;
  const auto lines = split(csv, '\n');
  for (std::size_t i = 1; i < lines.size(); ++i)
    if (!lines[i].empty()) values.push_back(split(lines[i], ',').back());
  return values;
}

// Significant digits printed in a %g-style number ("-1.25e-05" has 3).
int significant_digits(const std::string& number) {
  std::string mantissa = number.substr(0, number.find_first_of("eE"));
  mantissa.erase(
      std::remove_if(mantissa.begin(), mantissa.end(), [](char ch) { return ch == '-' || ch == '+' || ch == '.'; }),
      mantissa.end());
  const auto first = mantissa.find_first_not_of('0');
  return first == std::string::npos ? 1 : static_cast<int>(mantissa.size() - first);
}

std::string join(const std::vector<std::string>& parts, const std::string& separator = ", ") {
  std::string s;
  for (const auto& p : parts) {
    if (!s.empty()) s += separator;
    s += p;
  }
  return s;
}

template <class T>
T parse(const std::string& s) {
  T v{};
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  EXPECT_TRUE(ec == std::errc{} && end == s.data() + s.size()) << s;
  return v;
}

class EvalCommand : public sglab::test::TempDirTest {
 protected:
  // `sglab eval ARGS < stdin_file`, capturing standard output and error.
  Result eval(const std::string& args, const fs::path& stdin_file = "/dev/null") const {
    return sglab("eval " + args, stdin_file);
  }

  // Evaluates `csv` through --in/--out files; expects success.
  std::string eval_csv(const std::string& args, const std::string& csv) const {
    write_file(path("in.csv"), csv);
    fs::remove(path("out.csv"));
    const Result run = eval(
        fmt::format("{} --in '{}' --out '{}'", args, path("in.csv").string(), path("out.csv").string()));
    EXPECT_EQ(run.status, 0) << args << "\n" << run.err;
    EXPECT_EQ(run.out, "");
    return read_file(path("out.csv"));
  }
};

// A (λ, c) grid with the stiff cases of docs/math.md §10 that apply (λ = 0, 1e-8, 1e8; c = ±1).
const std::vector<double> kSharpness{0, 1e-8, 1e-3, 0.5, 1, 2.5, 10, 123.456, 1e4, 1e8};
const std::vector<double> kCosine{-1, -0.7, -0.1, 0, 0.3, 0.99, 1};

template <class T>
std::string grid_csv() {
  std::string csv = "sharpness,cosine\n";
  // fmt's shortest form of a T reads back as exactly that T.
  for (const double l : kSharpness)
    for (const double c : kCosine) csv += fmt::format("{},{}\n", static_cast<T>(l), static_cast<T>(c));
  return csv;
}

template <class T>
void expect_matches_core(const std::string& precision, int digits, const std::string& csv_out) {
  const auto values = values_of(csv_out);
  ASSERT_EQ(values.size(), kSharpness.size() * kCosine.size());
  std::size_t i = 0;
  int max_digits = 0;
  for (const double l : kSharpness) {
    for (const double c : kCosine) {
      const T expected = sglab::clamped_cosine_tokuyoshi2024<T>(static_cast<T>(l), static_cast<T>(c));
      EXPECT_EQ(values[i], fmt::format("{:.{}g}", expected, digits))
          << precision << " at sharpness " << l << ", cosine " << c;
      // Round trip: the printed text reads back as the very value core computed.
      EXPECT_EQ(parse<T>(values[i]), expected) << values[i];
      const int d = significant_digits(values[i]);
      EXPECT_LE(d, digits) << values[i];
      max_digits = std::max(max_digits, d);
      ++i;
    }
  }
  EXPECT_EQ(max_digits, digits) << precision;
}

TEST_F(EvalCommand, DoubleEqualsCoreCallToTheLastDigit) {
  expect_matches_core<double>("double", 17,
                              eval_csv("clamped-cosine --method tokuyoshi2024 --precision double", grid_csv<double>()));
}

TEST_F(EvalCommand, DoubleIsTheDefaultPrecision) {
  const std::string csv = grid_csv<double>();
  EXPECT_EQ(eval_csv("clamped-cosine --method tokuyoshi2024", csv),
            eval_csv("clamped-cosine --method tokuyoshi2024 --precision double", csv));
}

TEST_F(EvalCommand, FloatEqualsCoreCallToTheLastDigit) {
  expect_matches_core<float>("float", 9,
                             eval_csv("clamped-cosine --method tokuyoshi2024 --precision float", grid_csv<float>()));
}

TEST_F(EvalCommand, Mp50EqualsCoreCallToTheLastDigit) {
  // Inputs with more digits than a double holds: they must reach mp50 exactly.
  const std::vector<std::string> sharpness{
      "0", "1e-8", "0.123456789012345678901234567890123", "1.1", "12345.678901234567890123", "1e8"};
  const std::vector<std::string> cosine{"-1", "-0.33333333333333333333333333333333", "0.1", "1"};
  std::string csv = "sharpness,cosine\n";
  for (const auto& l : sharpness)
    for (const auto& c : cosine) csv += l + "," + c + "\n";
  const auto values = values_of(eval_csv("clamped-cosine --method tokuyoshi2024 --precision mp50", csv));
  ASSERT_EQ(values.size(), sharpness.size() * cosine.size());
  std::size_t i = 0;
  int max_digits = 0;
  for (const auto& l : sharpness) {
    for (const auto& c : cosine) {
      const sglab::mp50 expected = sglab::clamped_cosine_tokuyoshi2024(sglab::mp50(l), sglab::mp50(c));
      EXPECT_EQ(values[i], expected.str(50)) << l << "," << c;
      max_digits = std::max(max_digits, significant_digits(values[i]));
      ++i;
    }
  }
  EXPECT_EQ(max_digits, 50);
}

TEST_F(EvalCommand, Mp50ParsesTheDecimalTextNotItsDoubleRounding) {
  const auto value = values_of(
      eval_csv("clamped-cosine --method tokuyoshi2024 --precision mp50", "sharpness,cosine\n1.1,0.1\n"));
  ASSERT_EQ(value.size(), 1u);
  const auto via_double = sglab::clamped_cosine_tokuyoshi2024(sglab::mp50(1.1), sglab::mp50(0.1));
  EXPECT_NE(value[0], via_double.str(50));
  EXPECT_EQ(value[0], sglab::clamped_cosine_tokuyoshi2024(sglab::mp50("1.1"), sglab::mp50("0.1")).str(50));
}

TEST_F(EvalCommand, ExtraColumnsPassThroughInAnyOrder) {
  // Columns in another order than the quantity's, an extra text column with a quoted comma and
  // quote, numbers with spaces and a '+' sign: every field comes back as it was.
  const std::string input =
      "id,cosine,note,sharpness\n"
      "7,0.25,\"hello, world\",2\n"
      "8, -0.5 ,\"say \"\"hi\"\"\",+0.125\n";
  const double v1 = sglab::clamped_cosine_tokuyoshi2024(2.0, 0.25);
  const double v2 = sglab::clamped_cosine_tokuyoshi2024(0.125, -0.5);
  const std::string expected = fmt::format(
      "id,cosine,note,sharpness,value\n"
      "7,0.25,\"hello, world\",2,{:.17g}\n"
      "8, -0.5 ,\"say \"\"hi\"\"\",+0.125,{:.17g}\n",
      v1, v2);
  EXPECT_EQ(eval_csv("clamped-cosine --method tokuyoshi2024", input), expected);

  // The same through standard input and output, with CRLF line ends in the input.
  write_file(path("crlf.csv"),
             "id,cosine,note,sharpness\r\n7,0.25,\"hello, world\",2\r\n"
             "8, -0.5 ,\"say \"\"hi\"\"\",+0.125\r\n");
  const Result run = eval("clamped-cosine --method tokuyoshi2024", path("crlf.csv"));
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.out, expected);
}

TEST_F(EvalCommand, HeaderOnlyInputGivesHeaderOnlyOutput) {
  EXPECT_EQ(eval_csv("sg-integral --method exact", "sharpness,x\n"), "sharpness,x,value\n");
}

TEST_F(EvalCommand, CosineRoundingPastOneIsAccepted) {
  const auto values = values_of(
      eval_csv("clamped-cosine --method tokuyoshi2024", "sharpness,cosine\n3,1.0000005\n3,-1.0000005\n"));
  EXPECT_EQ(values.size(), 2u);
}

// Every quantity and method of the registry evaluates in every precision on a valid row: each
// `sglab eval` its own process, as above (status 0, nothing on standard output, one finite value
// in its --out file), all of them started by one shell (one line each) instead of a shell per run.
TEST_F(EvalCommand, EveryRegisteredMethodEvaluatesInEveryPrecision) {
  struct Run {
    std::string what, out;
  };
  std::vector<Run> runs;
  std::string script;
  for (const auto& q : sglab::quantities()) {
    std::vector<std::string> header, row;
    for (const auto& c : q.columns) {
      header.push_back(c.name);
      row.push_back("0.5");  // valid for every column kind
    }
    const std::string in = q.name + ".csv";
    write_file(path(in), fmt::format("{}\n{}\n", join(header, ","), join(row, ",")));
    for (const auto& m : q.methods) {
      for (const std::string precision : {"float", "double", "mp50"}) {
        const std::string out = fmt::format("run{}", runs.size());
        runs.push_back({fmt::format("{} {} {}", q.name, m.name, precision), out});
        script += fmt::format(
            "'{}' eval {} --method {} --precision {} --in '{}' --out '{}.csv' > '{}.stdout' 2> '{}.stderr'; "
            "echo $? > '{}.status'\n",
            SGLAB_EXE, q.name, m.name, precision, in, out, out, out, out);
      }
    }
  }
  write_file(path("runs.sh"), script);
  ASSERT_EQ(run_shell("sh runs.sh").status, 0);
  for (const Run& r : runs) {
    EXPECT_EQ(read_file(path(r.out + ".status")), "0\n") << r.what << "\n" << read_file(path(r.out + ".stderr"));
    EXPECT_EQ(read_file(path(r.out + ".stdout")), "") << r.what;
    const auto values = values_of(read_file(path(r.out + ".csv")));
    ASSERT_EQ(values.size(), 1u) << r.what;
    const double v = std::strtod(values[0].c_str(), nullptr);
    EXPECT_TRUE(std::isfinite(v)) << r.what << ": " << values[0];
  }
}

// ---- error paths -------------------------------------------------------------------------------

struct ErrorCase {
  std::string name;
  std::string args;                  // after `sglab eval`, without --in/--out
  std::string input;                 // CSV text: bad input, so exit status 2
  std::vector<std::string> message;  // each must appear in standard error
};

std::vector<ErrorCase> error_cases() {
  const std::string cc = "clamped-cosine --method tokuyoshi2024";
  const std::string cc_float = cc + " --precision float", cc_mp50 = cc + " --precision mp50";
  const std::string h = "sharpness,cosine\n";  // the header of most clamped-cosine inputs below
  std::vector<ErrorCase> cases{
      {"missing column", cc, "sharpness,foo\n1,2\n", {"missing column 'cosine'", "line 1"}},
      {"value column in the input",
       cc,
       "sharpness,cosine,value\n1,0.5,3\n",
       {"line 1 (header)", "already has a column 'value'", "rename it"}},
      {"non-number",
       cc,
       h + "1,0.5\nabc,0.5\n",
       {"row 2 (line 3)", "column 'sharpness'", "value 'abc'", "not a number"}},
      {"empty field", cc, h + "1,0.5\n2,0.5\n3,\n", {"row 3 (line 4)", "column 'cosine'", "value ''", "empty"}},
      {"trailing garbage", cc, h + "1,0.5x\n", {"row 1 (line 2)", "column 'cosine'", "value '0.5x'", "not a number"}},
      {"nan", cc, h + "nan,0.5\n", {"row 1 (line 2)", "column 'sharpness'", "value 'nan'"}},
      {"inf", cc, h + "1,0\ninf,0.5\n", {"row 2 (line 3)", "column 'sharpness'", "value 'inf'"}},
      {"-inf", cc, h + "1,-inf\n", {"row 1 (line 2)", "column 'cosine'", "value '-inf'"}},
      {"hexadecimal", cc, h + "0x1p3,0\n", {"row 1 (line 2)", "column 'sharpness'", "value '0x1p3'"}},
      {"overflow", cc, h + "1e999,0\n", {"row 1 (line 2)", "value '1e999'", "out of the range"}},
      {"float overflow", cc_float, h + "1e39,0\n", {"row 1 (line 2)", "value '1e39'", "out of the range of float"}},
      {"mp50 non-number", cc_mp50, h + "1,0.5\n1e5x,0\n", {"row 2 (line 3)", "column 'sharpness'", "value '1e5x'"}},
      {"negative sharpness", cc, h + "1,0.5\n-1,0.5\n", {"row 2 (line 3)", "column 'sharpness'", "value '-1'", ">= 0"}},
      {"negative sharpness mp50", cc_mp50, h + "-0.5,0.5\n", {"row 1 (line 2)", "column 'sharpness'", "value '-0.5'"}},
      {"cosine above 1", cc, h + "1,1.00001\n", {"row 1 (line 2)", "column 'cosine'", "value '1.00001'", "[-1, 1]"}},
      {"cosine below -1", cc_float, h + "1,-1.000002\n", {"row 1 (line 2)", "column 'cosine'", "value '-1.000002'"}},
      {"domain error",
       "clamped-cosine --method punctual-approx",
       h + "1,0.5\n2,0.5\n0,0.5\n",
       {"row 3 (line 4)", "sharpness '0'", "cosine '0.5'", "punctual-approx", "sharpness 0"}},
      // λ = 1e-39 is a subnormal float (2π/λ would overflow float): refused as input, naming it.
      {"subnormal input",
       "sg-integral --method approx --precision float",
       "sharpness\n1\n1e-39\n",
       {"row 2 (line 3)", "value '1e-39'", "subnormal"}},
      // A quoted field spanning two lines: the row and line numbers differ.
      {"row and line differ",
       cc,
       "note,sharpness,cosine\n\"two\nlines\",1,0.5\nx,-2,0\n",
       {"row 2 (line 4)", "column 'sharpness'", "value '-2'"}},
      {"field count", cc, h + "1,0.5\n1,0.5,3\n", {"row 2 (line 3)", "3 fields", "header has 2"}},
      {"unterminated quote", cc, h + "\"1,0.5\n", {"line 2", "never closed"}},
      {"duplicate column", cc, "sharpness,cosine,sharpness\n1,0.5,2\n", {"line 1", "'sharpness' appears twice"}},
      {"value column exists", cc, "sharpness,cosine,value\n1,0.5,2\n", {"line 1", "'value'"}},
      {"empty input", cc, "", {"empty"}},
      {"unknown precision",
       cc + " --precision quad",
       h + "1,0.5\n",
       {"unknown precision 'quad'", "float", "double", "mp50"}},
  };

  std::vector<std::string> quantity_names;
  for (const auto& q : sglab::quantities()) quantity_names.push_back(q.name);
  ErrorCase unknown_quantity{
      "unknown quantity", "no-such-quantity --method exact", "sharpness\n1\n", {"unknown quantity 'no-such-quantity'"}};
  unknown_quantity.message.push_back(join(quantity_names));
  cases.push_back(unknown_quantity);

  for (const auto& q : sglab::quantities()) {
    std::vector<std::string> methods;
    for (const auto& m : q.methods) methods.push_back(m.name);
    cases.push_back({"unknown method of " + q.name,
                     q.name + " --method no-such-method",
                     "x\n1\n",
                     {"unknown method 'no-such-method'", "'" + q.name + "'", join(methods)}});
  }
  return cases;
}

TEST_F(EvalCommand, BadInputFailsNamingRowColumnAndValueAndWritesNothing) {
  for (const ErrorCase& c : error_cases()) {
    SCOPED_TRACE(c.name);
    write_file(path("in.csv"), c.input);
    const std::string out = path("out.csv").string();
    const std::string files = fmt::format(" --in '{}' --out '{}'", path("in.csv").string(), out);

    // No output file before: none after, and no temporary left beside it.
    fs::remove(out);
    Result run = eval(c.args + files);
    EXPECT_EQ(run.status, 2) << run.err;
    for (const auto& part : c.message)
      EXPECT_NE(run.err.find(part), std::string::npos) << part << "\n  in: " << run.err;
    EXPECT_EQ(run.out, "");
    EXPECT_FALSE(fs::exists(out));
    std::size_t entries = 0;
    for (const auto& e : fs::directory_iterator(dir_)) entries += e.path().filename() != "in.csv";
    EXPECT_EQ(entries, 0u) << "files left in the output directory";

    // An existing output file is left untouched.
    write_file(out, "precious\n");
    run = eval(c.args + files);
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_EQ(read_file(out), "precious\n");

    // Through standard input and output: nothing on standard output.
    run = eval(c.args, path("in.csv"));
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_EQ(run.out, "");
  }
}

TEST_F(EvalCommand, MissingInputFileIsBadInput) {
  const Result run = eval(fmt::format("clamped-cosine --method reference --in '{}'", path("absent.csv").string()));
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("absent.csv"), std::string::npos) << run.err;
}

TEST_F(EvalCommand, SuccessReplacesAnExistingOutputFile) {
  write_file(path("out.csv"), "old contents\n");
  EXPECT_EQ(eval_csv("sg-integral --method exact", "sharpness\n0\n"),
            fmt::format("sharpness,value\n0,{:.17g}\n", 4 * std::acos(-1.0)));
}

// ---- --list -----------------------------------------------------------------------------------

TEST_F(EvalCommand, ListNamesEveryQuantityColumnAndMethodAndMarksNegativeOnes) {
  const Result run = eval("--list");
  ASSERT_EQ(run.status, 0) << run.err;
  const auto lines = split(run.out, '\n');
  std::size_t negative_methods = 0;
  for (const auto& q : sglab::quantities()) {
    SCOPED_TRACE(q.name);
    // The quantity's block: from its name line to the next blank line.
    const auto begin = std::find(lines.begin(), lines.end(), q.name);
    ASSERT_NE(begin, lines.end());
    const auto end = std::find(begin, lines.end(), "");
    const std::vector<std::string> block(begin, end);
    const auto has = [&](const std::string& text) {
      return std::any_of(block.begin(), block.end(),
                         [&](const std::string& line) { return line.find(text) != std::string::npos; });
    };
    EXPECT_TRUE(has(q.description));
    for (const auto& c : q.columns) EXPECT_TRUE(has(c.name + " ")) << c.name;
    for (const auto& m : q.methods) {
      const auto line = std::find_if(block.begin(), block.end(), [&](const std::string& l) {
        return l == "    " + m.name || l.starts_with("    " + m.name + "  ");
      });
      ASSERT_NE(line, block.end()) << m.name;
      EXPECT_EQ(line->find("NEGATIVE") != std::string::npos, m.may_be_negative) << *line;
      EXPECT_TRUE(has(m.source)) << m.name;
      // Its batch path, on the line after its source: what the cost columns time.
      ASSERT_GT(std::distance(line, block.end()), 2) << m.name;
      EXPECT_TRUE((line + 2)->starts_with("      batch:  " + std::string(sglab::batch_path_name(m.batch_path))))
          << m.name << ": " << *(line + 2);
      if (!m.flaws.empty()) {
        EXPECT_TRUE(has(m.flaws)) << m.name;
      }
      negative_methods += m.may_be_negative;
    }
  }
  // hill-fitted and meder at least: the marking above is not vacuous.
  EXPECT_GE(negative_methods, 2u);
}

TEST_F(EvalCommand, ListJsonMatchesTheRegistry) {
  const Result run = eval("--list --json");
  ASSERT_EQ(run.status, 0) << run.err;
  const auto j = nlohmann::json::parse(run.out);
  const auto& all = sglab::quantities();
  ASSERT_EQ(j.at("quantities").size(), all.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    const auto& jq = j["quantities"][i];
    EXPECT_EQ(jq.at("name"), all[i].name);
    EXPECT_EQ(jq.at("description"), all[i].description);
    EXPECT_EQ(jq.at("reference_method"), all[i].reference_method);
    ASSERT_EQ(jq.at("columns").size(), all[i].columns.size());
    for (std::size_t k = 0; k < all[i].columns.size(); ++k)
      EXPECT_EQ(jq["columns"][k].at("name"), all[i].columns[k].name);
    ASSERT_EQ(jq.at("methods").size(), all[i].methods.size());
    for (std::size_t k = 0; k < all[i].methods.size(); ++k) {
      const auto& m = all[i].methods[k];
      EXPECT_EQ(jq["methods"][k].at("name"), m.name);
      EXPECT_EQ(jq["methods"][k].at("source"), m.source);
      EXPECT_EQ(jq["methods"][k].at("flaws"), m.flaws);
      EXPECT_EQ(jq["methods"][k].at("may_be_negative"), m.may_be_negative);
      EXPECT_EQ(jq["methods"][k].at("batch"), sglab::batch_path_name(m.batch_path));
    }
  }
  for (const auto& p : j.at("precisions"))
    EXPECT_EQ(p.at("digits"), sglab::round_trip_digits(*sglab::parse_precision(p.at("name").get<std::string>())));
}

TEST_F(EvalCommand, ListExcludesEvaluationOptions) {
  EXPECT_NE(eval("--list --method reference").status, 0);
  EXPECT_NE(eval("--json").status, 0);
}

// ---- accuracy end to end --------------------------------------------------------------------

// tokuyoshi2024 agrees with the reference within 0.2 % of the value at c = 1, for λ on a log grid
// from 1e-3 to 1e4 and c in [-1, 1], both evaluated by the binary on one CSV.
TEST_F(EvalCommand, Tokuyoshi2024WithinPointTwoPercentOfReference) {
  constexpr int kLambdas = 57;  // 8 per decade
  constexpr int kCosines = 41;  // step 0.05, c = ±1 included exactly
  std::string csv = "sharpness,cosine\n";
  for (int i = 0; i < kLambdas; ++i)
    for (int j = 0; j < kCosines; ++j)
      csv += fmt::format("{},{}\n", std::pow(10.0, -3.0 + 7.0 * i / (kLambdas - 1)), -1.0 + 2.0 * j / (kCosines - 1));
  const auto reference = values_of(eval_csv("clamped-cosine --method reference", csv));
  const auto tokuyoshi = values_of(eval_csv("clamped-cosine --method tokuyoshi2024", csv));
  ASSERT_EQ(reference.size(), std::size_t(kLambdas * kCosines));
  ASSERT_EQ(tokuyoshi.size(), reference.size());
  double worst = 0;
  for (int i = 0; i < kLambdas; ++i) {
    const double at_c1 = parse<double>(reference[i * kCosines + kCosines - 1]);
    for (int j = 0; j < kCosines; ++j) {
      const double r = parse<double>(reference[i * kCosines + j]);
      const double t = parse<double>(tokuyoshi[i * kCosines + j]);
      const double error = std::fabs(t - r) / at_c1;
      worst = std::max(worst, error);
      EXPECT_LE(error, 0.002) << "row " << i * kCosines + j + 1;
    }
  }
  RecordProperty("max_error_relative_to_c1", fmt::format("{:.3g}", worst));
  std::printf("tokuyoshi2024 vs reference: max error %.4g %% of the value at c = 1\n", 100 * worst);
}

}  // namespace
