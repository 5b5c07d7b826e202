// `sglab vsgl-fis-bias` as a library: the bias of the FIS VSGLs' sums against the exact sums over
// every RSM texel, over seeds (compute), and its table (tables). The quantities and their
// definitions are in vsgl_fis_bias.cpp's opening comment.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "run_context.hpp"
#include "table.hpp"

namespace sglab::experiments::vsgl_fis_bias {

// Its directory in a run's places (runner::Places::dir): its tables go there unless the run has
// a tables directory (paper_tables/ in `sglab reproduce`).
inline constexpr std::string_view kDir = "vsgl_fis_bias";

struct Options {
  int seeds = 64;
  int rsm = 64;                                                   // RSM resolution of the shipped scenes
  std::string tables_dir = runner::Places{}.tables_or_dir(kDir);  // --tables-dir: a plain run's
};

// One sum of one RSM at one N: exact value, mean over the seeds, relative bias (the first moment's
// as ‖mean − exact‖/(Wσ)) and its standard error.
struct Row {
  std::string rsm;
  int n = 0;
  std::string quantity;  // importance, total_power, first_moment, second_moment
  double exact = 0, mean = 0, bias = 0, standard_error = 0;
};

struct Result {
  runner::Provenance provenance;
  Options options;
  std::vector<Row> rows;  // per RSM, per N, the four quantities in the order above
};

// InputError for seeds outside [2, 100000] or rsm outside [1, 1024].
Result compute(const Options& o);

struct Tables {
  std::string markdown, csv;  // bodies; write_table adds the provenance headers
};
Tables tables(const Result& r);

// TABLES/vsgl_fis_bias.{md,csv}; the Markdown also on stdout.
void write(const Result& r);

}  // namespace sglab::experiments::vsgl_fis_bias
