// The parts the sections of `sglab recommend` share (recommendations.cpp and the files of its
// sections: recommendations_quantities.cpp, recommendations_rendering.cpp,
// recommendations_bases.cpp): number formats, the tables read, the section frame, the helpers.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "csv.hpp"
#include "input_error.hpp"
#include "parse_number.hpp"
#include "recommendations.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::experiments::recommendations::detail {

inline std::string g(double x) { return std::isfinite(x) ? fmt::format("{:.3g}", x) : "—"; }
// A count (instructions, ulps, points, floats): every digit.
inline std::string count(double x) { return std::isfinite(x) ? fmt::format("{:.0f}", x) : "—"; }
// A measured cost: three significant digits, every integer digit from 1000 up (2249, not 2.25e+03).
inline std::string magnitude(double x) {
  return std::isfinite(x) && std::abs(x) >= 1000 && std::abs(x) < 1e9 ? count(x) : g(x);
}

// The shader section's "cheapest within": a max error of 1 % of the reference, the generator's own
// choice of a diffuse error small enough to trade for instructions (the most accurate export is
// named beside it).
inline constexpr double kShaderTolerance = 0.01;
// Two environments whose rows in the basis table differ by a median below this (relative) are
// named as ones the table barely tells apart.
inline constexpr double kSameEnvironment = 0.01;

// One committed table: its rows, and the command its header names.
struct Table {
  std::string file, command;
  runner::CsvTable csv;

  bool has(const std::string& column) const { return csv.column(column) != runner::CsvTable::npos; }
  const std::string& text(const runner::CsvRecord& r, const std::string& column) const {
    const std::size_t c = csv.column(column);
    if (c == runner::CsvTable::npos) throw runner::InputError("recommend: " + file + " has no column '" + column + "'");
    return r.fields[c];
  }
  // The field as a number; NaN when empty ("—" in the Markdown tables). runner::parse_table_number:
  // strtod took "nan", "inf" and "1e400" in a table and carried them into the recommendations.
  double number(const runner::CsvRecord& r, const std::string& column) const {
    const std::string& s = text(r, column);
    if (s.empty()) return NAN;
    try {
      return runner::parse_table_number(s);
    } catch (const runner::NumberError& e) {
      throw runner::InputError(
          fmt::format("recommend: {} line {}, column '{}': {} {}", file, r.line, column, quote(s), e.what()));
    }
  }
  std::string source() const {
    return "[" + file + "](" + file + ")" + (command.empty() ? "" : " (`" + command + "`)");
  }
};

// The tables read, by file name; a table that is not there is listed in `missing`.
class Tables {
 public:
  Tables(std::string dir, std::vector<std::string>& missing) : dir_(std::move(dir)), missing_(missing) {}
  const Table* get(const std::string& file);  // recommendations.cpp

 private:
  std::string dir_;
  std::vector<std::string>& missing_;
  std::map<std::string, std::unique_ptr<Table>> cache_;
};

// The choice per budget along a front.
std::string budget_text(const std::vector<Candidate>& front, const std::string& cost_label,
                        std::string (*cost)(double) = g);
// The front as a Markdown table, and the choice per budget.
std::string front_text(const std::vector<Candidate>& front, const std::string& cost_label,
                       const std::string& error_label, std::string (*cost)(double) = g);
const Candidate* named(const std::vector<Candidate>& v, const std::string& name);
double median(std::vector<double> v);
std::string signed_percent(double x);
// Appends `s` to `order` unless it is there: the table's order of first appearance.
void remember(std::vector<std::string>& order, const std::string& s);

// Error-vs-time's rows of `quantity` (double, published constants, the reference left out).
std::vector<Candidate> grid_candidates(const Table& t, const std::string& quantity, const std::string& error_column);
// The methods of `quantity` that return negatives or non-finite values on error-vs-time's grid.
std::string grid_flaws(const Table& t, const std::string& quantity);
// From the stability atlas: each front member's NaN/Inf/negative/>1 % counts and where its error is worst.
std::string stability_caveats(const Table* st, const std::string& quantity, const std::vector<Candidate>& front);
// The headline choice: the most accurate member of the front, and the cheapest one within `good`.
std::string headline(const std::vector<Candidate>& front, const std::string& cost_unit, const std::string& error_name,
                     double good);

// The section titled `title` drawn from the tables `files`: fill(sec, table…) sets its headline
// and body when every one is present, and their sources close the body; without them it stays
// empty (compute leaves it out).
template <std::size_t N, class Fill>
Section section(Tables& tables, std::string title, const char* const (&files)[N], Fill fill) {
  Section sec{std::move(title), "", ""};
  std::array<const Table*, N> t{};
  for (std::size_t k = 0; k < N; ++k) t[k] = tables.get(files[k]);
  if (std::find(t.begin(), t.end(), nullptr) != t.end()) return sec;
  std::apply([&](const auto*... table) { fill(sec, table...); }, t);
  std::string sources;
  for (std::size_t k = 0; k < N; ++k) sources += (k ? ", " : "") + t[k]->source();
  sec.body += "\nSources: " + sources + ".\n";
  return sec;
}

// The sections, in the order of the report: recommendations_quantities.cpp (the approximated
// quantities), recommendations_rendering.cpp (the renderer's choices), recommendations_bases.cpp
// (environment bases, exported shaders).
Section diffuse(Tables& tables);
Section hemispherical(Tables& tables);
Section specular(Tables& tables);
Section vsgl(Tables& tables);
Section filtering(Tables& tables);
Section environment(Tables& tables);
Section denoise(Tables& tables);
Section bases(Tables& tables);
Section shaders(Tables& tables);

}  // namespace sglab::experiments::recommendations::detail
