// Constants as data: every published constant is declared by the registry (Parameter), defined
// once in the sources, re-derived by a named fit, and replaceable at run time (sglab::bind).
//  - the registry's parameters are consistent (distinct names per method; one published value per
//    (fit, name); the fit exists and produces that name), and fit/ says which it produces;
//  - each published value appears as a numeric literal exactly once in core/, fit/, frontend/ and
//    experiments/ (comments and string literals are not definitions);
//  - a bound method changes its output by what the formula predicts (independent closed forms).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "driver.hpp"
#include "sglab/registry.hpp"

namespace {

namespace fs = std::filesystem;
using sglab::ConstantSet;
using sglab::Method;

const Method& method(const std::string& q, const std::string& m) {
  const sglab::Quantity* quantity = sglab::find_quantity(q);
  EXPECT_NE(quantity, nullptr) << q;
  const Method* found = quantity->find(m);
  EXPECT_NE(found, nullptr) << q << "/" << m;
  return *found;
}

double eval(const Method& m, double a, double b) {
  const double args[2] = {a, b};
  return m.eval_double(args);
}

TEST(Constants, RegistryParametersAreConsistentAndProducedByTheirFit) {
  std::map<std::pair<std::string, std::string>, double> published;
  for (const auto& use : sglab::constant_uses()) {
    const auto& p = *use.parameter;
    SCOPED_TRACE(use.user + " " + p.fit + "." + p.name);
    EXPECT_TRUE(std::isfinite(p.published));
    EXPECT_FALSE(p.source.empty());
    EXPECT_FALSE(sglab::column_value_error(sglab::Column{p.name, p.kind, ""}, p.published));
    ASSERT_FALSE(p.fit.empty());
    const auto* f = sglab::fit::find_fitter(p.fit);
    ASSERT_NE(f, nullptr) << "no fit " << p.fit;
    EXPECT_NE(std::find(f->parameters.begin(), f->parameters.end(), p.name), f->parameters.end());
    const auto [it, inserted] = published.insert({{p.fit, p.name}, p.published});
    // lambda-d's λ_d has two published values (the papers' 2 for sg-cosine, the VSGL code's
    // 2.292504 for the renderer); every other constant has one.
    if (!inserted && p.fit != "lambda-d") {
      EXPECT_EQ(it->second, p.published);
    }
  }
  for (const auto& q : sglab::quantities())
    for (const auto& m : q.methods) {
      std::set<std::string> names;
      for (const auto& p : m.parameters)
        EXPECT_TRUE(names.insert(p.fit + "." + p.name).second) << q.name << "/" << m.name;
      // A method with constants can be bound; one without has nothing to bind.
      EXPECT_EQ(bool(m.bind), !m.parameters.empty()) << q.name << "/" << m.name;
    }
  // Every fit feeds something, and every fitted name of a fit is read somewhere.
  for (const auto& f : sglab::fit::fitters()) {
    const auto uses = sglab::fit::registry_parameters(f);
    EXPECT_FALSE(uses.empty()) << f.name;
    for (const auto& name : f.parameters) {
      bool used = false;
      for (const auto& u : uses) used = used || u.parameter->name == name;
      EXPECT_TRUE(used) << f.name << "." << name << " is read by no method";
    }
  }
}

// The source text with comments, string and character literals blanked (so a value quoted in a
// comment or a description is not a definition).
std::string code_only(const std::string& s) {
  std::string out = s;
  std::size_t i = 0;
  while (i < out.size()) {
    if (out.compare(i, 2, "//") == 0) {
      while (i < out.size() && out[i] != '\n') out[i++] = ' ';
    } else if (out.compare(i, 2, "/*") == 0) {
      while (i < out.size() && out.compare(i, 2, "*/") != 0) out[i++] = ' ';
      if (i < out.size()) out[i] = out[i + 1] = ' ', i += 2;
    } else if (out.compare(i, 2, "R\"") == 0) {
      const std::size_t open = out.find('(', i);
      // Built by appends: GCC 12 reports a false -Wrestrict on `")" + std::string&&`.
      std::string close = ")";
      close.append(out, i + 2, open - i - 2).push_back('"');
      const std::size_t end = out.find(close, open);
      for (std::size_t k = i; k < end + close.size(); ++k) out[k] = ' ';
      i = end + close.size();
    } else if (out[i] == '"' || (out[i] == '\'' && !(i > 0 && std::isxdigit(static_cast<unsigned char>(out[i - 1]))))) {
      const char q = out[i];
      out[i++] = ' ';
      while (i < out.size() && out[i] != q) {
        if (out[i] == '\\') out[i++] = ' ';
        if (i < out.size()) out[i++] = ' ';
      }
      if (i < out.size()) out[i++] = ' ';
    } else {
      ++i;
    }
  }
  return out;
}

// Every floating-point literal (with a '.' or an exponent) in `code`, parsed.
std::vector<std::pair<double, std::string>> float_literals(const std::string& code) {
  std::vector<std::pair<double, std::string>> out;
  for (std::size_t i = 0; i < code.size();) {
    const bool starts = (std::isdigit(static_cast<unsigned char>(code[i])) ||
                         (code[i] == '.' && i + 1 < code.size() &&
                          std::isdigit(static_cast<unsigned char>(code[i + 1])))) &&
                        (i == 0 || !(std::isalnum(static_cast<unsigned char>(code[i - 1])) || code[i - 1] == '_' ||
                                     code[i - 1] == '.'));
    if (!starts) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < code.size() && (std::isalnum(static_cast<unsigned char>(code[j])) || code[j] == '.' || code[j] == '\'' ||
                               ((code[j] == '-' || code[j] == '+') && (code[j - 1] == 'e' || code[j - 1] == 'E'))))
      ++j;
    std::string token = code.substr(i, j - i);
    token.erase(std::remove(token.begin(), token.end(), '\''), token.end());
    const bool hex = token.size() > 1 && (token[1] == 'x' || token[1] == 'X');
    if (!hex && token.find_first_of(".eE") != std::string::npos)
      out.push_back({std::strtod(token.c_str(), nullptr), token});
    i = j;
  }
  return out;
}

TEST(Constants, EveryPublishedConstantHasExactlyOneDefinition) {
  std::vector<fs::path> files;
  for (const char* dir : {"core", "fit", "frontend", "experiments"})
    for (const auto& e : fs::recursive_directory_iterator(fs::path(SGLAB_SOURCE_DIR) / dir))
      if (e.is_regular_file() && (e.path().extension() == ".hpp" || e.path().extension() == ".cpp"))
        files.push_back(e.path());
  ASSERT_GT(files.size(), 20u);
  std::map<double, std::vector<std::string>> where;  // |value| → "file: literal" per occurrence
  std::set<double> values;  // magnitudes: a literal carries no sign (-3.6 is '-' applied to 3.6)
  for (const auto& use : sglab::constant_uses())
    // Integers (λ_d = 2) cannot be told apart from every other 2 in the code; they are skipped.
    if (use.parameter->published != std::floor(use.parameter->published))
      values.insert(std::abs(use.parameter->published));
  ASSERT_GT(values.size(), 15u);
  for (const auto& file : files) {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    for (const auto& [v, token] : float_literals(code_only(text.str())))
      if (values.count(v)) where[v].push_back(fs::relative(file, SGLAB_SOURCE_DIR).string() + ": " + token);
  }
  for (double v : values) {
    std::string list;
    for (const auto& w : where[v]) list += "\n  " + w;
    EXPECT_EQ(where[v].size(), 1u) << "published constant " << v << " is defined " << where[v].size()
                                   << " times:" << list;
  }
}

// A(λ) = 2π(1 − e^{−2λ})/λ and Iwasaki's product, written out here (independent of core).
double sg_cosine_formula(double lambda, double c, double lambda_d) {
  const double pi = std::acos(-1.0);
  const double a_d = 2 * pi * (1 - std::exp(-2 * lambda_d)) / lambda_d;
  const double s = lambda + lambda_d;
  const double l3 = lambda * lambda_d / s;
  return pi / a_d * 2 * pi * std::exp(l3 * (c - 1)) / s;
}

TEST(Constants, ChangingAConstantChangesTheOutputAsTheFormulaPredicts) {
  ConstantSet set;
  set.set({"lambda-d", "lambda_d", 3.25, "test"});
  set.set({"cosine-lobe-sg", "amplitude", 1.5, "test"});
  const Method& sg = method("clamped-cosine", "sg-cosine");
  const Method bound = sglab::bind(sg, set);
  const Method& lobe = method("clamped-cosine", "cosine-lobe-sg");
  const Method lobe_bound = sglab::bind(lobe, set);
  for (double l : {0.01, 0.5, 2.0, 30.0, 1000.0})
    for (double c : {-1.0, -0.3, 0.0, 0.6, 1.0}) {
      SCOPED_TRACE(testing::Message() << "lambda " << l << " c " << c);
      EXPECT_NEAR(eval(sg, l, c), sg_cosine_formula(l, c, 2.0), 1e-13 * sg_cosine_formula(l, c, 2.0));
      EXPECT_NEAR(eval(bound, l, c), sg_cosine_formula(l, c, 3.25), 1e-13 * sg_cosine_formula(l, c, 3.25));
      // a·∫G G: linear in the amplitude, so the ratio is 1.5/1.17.
      EXPECT_NEAR(eval(lobe_bound, l, c) / eval(lobe, l, c), 1.5 / 1.17, 1e-15);
    }
  // Overriding a constant the method does not read leaves it untouched (the same evaluators).
  EXPECT_FALSE(sglab::bind(method("clamped-cosine", "tokuyoshi2024"), set).bind == nullptr);
  // A later set overrides an earlier value.
  set.set({"lambda-d", "lambda_d", 1.5, "later"});
  EXPECT_EQ(set.find("lambda-d", "lambda_d")->value, 1.5);
  EXPECT_NEAR(eval(sglab::bind(sg, set), 3.0, 0.2), sg_cosine_formula(3.0, 0.2, 1.5), 1e-13);
}

// Binding the published values reproduces the published evaluators (the bound path is the same
// formula), for every method with constants, in double.
TEST(Constants, BindingThePublishedValuesChangesNothing) {
  for (const auto& q : sglab::quantities())
    for (const auto& m : q.methods) {
      if (m.parameters.empty() || q.columns.size() != 2) continue;
      std::vector<double> values;
      for (const auto& p : m.parameters) values.push_back(p.published);
      const Method b = m.bind(values);
      for (double l : {0.01, 1.0, 50.0})
        for (double c : {-0.5, 0.0, 0.9}) {
          const double expected = eval(m, l, c);
          EXPECT_NEAR(eval(b, l, c), expected, 1e-15 * std::max(1.0, std::fabs(expected))) << q.name << "/" << m.name;
        }
    }
}

}  // namespace
