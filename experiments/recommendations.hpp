// `sglab recommend` as a library: which method to ship, per quantity, read from the tables a full
// `sglab reproduce` wrote (their CSVs). Per quantity (clamped-cosine, hemispherical, specular, VSGL
// mode, filtering weights, denoising filter, environment mixture fit and basis, exported shaders)
// the Pareto front of error against cost, the choice per cost budget, and the caveats the tables
// measured (negative outputs, where each method is worst, mean against max). Every number it
// prints is read from a table or is a mean, median or maximum of a table's rows, named as such; a table
// that is absent leaves its section out (said so), a malformed one is an InputError.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "run_context.hpp"
#include "table.hpp"

namespace sglab::experiments::recommendations {

// Its output directory in a run's places (runner::Places::dir).
inline constexpr std::string_view kDir = "recommendations";

struct Options {
  std::string from = runner::Places{}.tables_read();  // --from: the tables read (a plain run's default)
  std::string out = runner::Places{}.dir(kDir);       // --out (a plain run's default)
  std::string tables_dir;                             // --tables-dir: where recommendations.md goes (default: --out)
};

// The tables `compute` reads (file names in Options::from), every one of them: `sglab reproduce`
// fingerprints them in the recommend step's marker, so that a changed table reruns it.
const std::vector<std::string>& input_tables();

// One choice: its name, cost and error in the section's units.
struct Candidate {
  std::string name;
  double cost = 0, error = 0;
};

// The Pareto front of `all`: sorted by cost, each member strictly more accurate than every cheaper
// one (ties in cost: the more accurate first).
std::vector<Candidate> pareto_front(std::vector<Candidate> all);

struct Section {
  std::string title;     // "Diffuse: clamped cosine"
  std::string headline;  // one line: the recommendation
  std::string body;      // Markdown: front, budgets, caveats, sources
};

struct Result {
  runner::Provenance provenance;
  std::vector<Section> sections;
  std::vector<std::string> missing;  // tables looked for and not found
};

Result compute(const Options& o);
std::string markdown(const Result& r);
// TABLES/recommendations.md (TABLES: --tables-dir, else --out).
void write(const Options& o, const Result& r);

}  // namespace sglab::experiments::recommendations
