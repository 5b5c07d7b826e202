// `sglab eval`: evaluates one method of one registered quantity on every row of
// a CSV and appends a `value` column. Everything it knows about quantities, columns and methods
// comes from the registry (sglab::quantities()), so a method added there is evaluable here with
// no change to this file.
//
// Order of work, so that bad input never produces output: read the whole table, parse and
// validate every row, evaluate every row, check every result, and only then write (through an
// AtomicFile for --out, so an existing file is replaced whole or not at all).
#include <sys/stat.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <ranges>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "atomic_file.hpp"
#include "commands.hpp"
#include "constant_sets.hpp"
#include "csv.hpp"
#include "option_checks.hpp"
#include "parse_number_mp50.hpp"
#include "sglab/registry_mp50.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::cli {
namespace {

constexpr std::array kPrecisions{Precision::float32, Precision::float64, Precision::mp50};

// The column eval appends.
const std::string kValueColumn = "value";

struct EvalOptions {
  std::string quantity;
  std::string method;
  std::string precision = "double";
  std::string in;
  std::string out;
  bool list = false;
  bool json = false;
  frontend::Constants constants;  // --constants, read as parsed
};

std::vector<std::string> column_names(const Quantity& q) {
  std::vector<std::string> names;
  for (const auto& c : q.columns) names.push_back(c.name);
  return names;
}

constexpr std::string_view kNegativeMark = "[CAN GO NEGATIVE: published form, kept as published]";

void print_list_text() {
  std::string out = fmt::format(
      "Quantities for `sglab eval QUANTITY --method NAME`. The input CSV needs the listed columns "
      "(found by name; other columns pass through). Precisions: {}.\n",
      fmt::join(kPrecisions | std::views::transform(precision_name), ", "));
  for (const auto& q : quantities()) {
    out += fmt::format("\n{}\n  {}\n  columns:\n", q.name, q.description);
    for (const auto& c : q.columns) out += fmt::format("    {:<12} {}\n", c.name, c.description);
    out += q.reference_method.empty() ? std::string("  methods:\n")
                                      : fmt::format("  methods (reference: {}):\n", q.reference_method);
    for (const auto& m : q.methods) {
      out += fmt::format("    {}{}{}\n", m.name, m.may_be_negative ? "  " : "", m.may_be_negative ? kNegativeMark : "");
      out += fmt::format("      source: {}\n", m.source);
      out += fmt::format("      batch:  {}\n", m.batch_path == BatchPath::vectorized
                                                   ? "vectorized (SIMD lanes, docs/simd.md)"
                                                   : "scalar (the template row by row)");
      if (!m.flaws.empty()) out += fmt::format("      flaws:  {}\n", m.flaws);
      for (const auto& p : m.parameters)
        out += fmt::format("      constant {} = {:.17g} (fit {}; {})\n", p.name, p.published, p.fit, p.source);
    }
  }
  std::cout << out << std::flush;
}

void print_list_json() {
  nlohmann::json j;
  j["precisions"] = nlohmann::json::array();
  for (const Precision p : kPrecisions)
    j["precisions"].push_back({{"name", precision_name(p)}, {"digits", round_trip_digits(p)}});
  j["quantities"] = nlohmann::json::array();
  for (const auto& q : quantities()) {
    nlohmann::json jq{{"name", q.name},
                      {"description", q.description},
                      {"reference_method", q.reference_method},
                      {"columns", nlohmann::json::array()},
                      {"methods", nlohmann::json::array()}};
    for (const auto& c : q.columns)
      jq["columns"].push_back({{"name", c.name}, {"kind", column_kind_name(c.kind)}, {"description", c.description}});
    for (const auto& m : q.methods) {
      nlohmann::json params = nlohmann::json::array();
      for (const auto& p : m.parameters)
        params.push_back({{"name", p.name}, {"fit", p.fit}, {"published", p.published}, {"source", p.source}});
      jq["methods"].push_back({{"name", m.name},
                               {"source", m.source},
                               {"flaws", m.flaws},
                               {"may_be_negative", m.may_be_negative},
                               {"batch", batch_path_name(m.batch_path)},
                               {"parameters", params}});
    }
    j["quantities"].push_back(std::move(jq));
  }
  std::cout << j.dump(2) << '\n' << std::flush;
}

// Significant digits that read back to the same T (sglab::round_trip_digits).
template <class T>
std::string format_value(const T& v, int digits) {
  if constexpr (std::is_same_v<T, mp50>) {
    return v.str(digits);
  } else {
    return fmt::format("{:.{}g}", v, digits);
  }
}

// "<source>: row R (line L)": the 1-based data row, and the input line it starts on.
std::string row_location(const std::string& source, const runner::CsvTable& table, std::size_t row) {
  return fmt::format("{}: row {} (line {})", source, row + 1, table.rows[row].line);
}

// The input column of each of the quantity's arguments, in order; InputError naming a missing
// column, or the input's own 'value' column (which eval appends).
std::vector<std::size_t> argument_columns(const Quantity& q, const runner::CsvTable& table, const std::string& source) {
  std::vector<std::size_t> index;
  for (const auto& c : q.columns) {
    const std::size_t i = table.column(c.name);
    if (i == runner::CsvTable::npos)
      throw runner::InputError(
          fmt::format("{}: line 1 (header): missing column '{}'; quantity '{}' needs the columns {}, the "
                      "header has {}",
                      source, c.name, q.name, fmt::join(column_names(q), ", "), fmt::join(table.header, ", ")));
    index.push_back(i);
  }
  if (table.column(kValueColumn) != runner::CsvTable::npos)
    throw runner::InputError(
        fmt::format("{}: line 1 (header): the input already has a column '{}', which eval appends; rename it", source,
                    kValueColumn));
  return index;
}

// Every row's arguments parsed as T (row-major, q.columns.size() a row) and validated, before any
// is evaluated: bad input is reported as such, in row order, and never after some results were
// computed.
template <class T>
std::vector<T> parse_arguments(const Quantity& q, const Method& method, const runner::CsvTable& table,
                               const std::vector<std::size_t>& index, const std::string& source) {
  const std::size_t rows = table.rows.size();
  const std::size_t k = q.columns.size();
  std::vector<T> args(rows * k);
  std::vector<double> checked(k);  // the values as validated: T's value, in double
  for (std::size_t r = 0; r < rows; ++r) {
    const auto& fields = table.rows[r].fields;
    const auto where = [&](std::size_t j) {
      return fmt::format("{}, column '{}', value '{}'", row_location(source, table, r), q.columns[j].name,
                         clip_text(fields[index[j]]));
    };
    for (std::size_t j = 0; j < k; ++j) {
      try {
        args[r * k + j] = runner::parse_decimal<T>(fields[index[j]]);
      } catch (const runner::NumberError& e) {
        throw runner::InputError(fmt::format("{}: {}", where(j), e.what()));
      }
      checked[j] = runner::validation_double(args[r * k + j]);
      if (method.evaluates_in_double && runner::outside_double(args[r * k + j]))
        throw runner::InputError(
            fmt::format("{}: is outside double's range, and method '{}' of '{}' evaluates in double", where(j),
                        method.name, q.name));
    }
    // The library's checks (registry.hpp: row_error), the same the Python module applies.
    if (const auto error = row_error(q, method, checked)) {
      if (error->column) throw runner::InputError(fmt::format("{}: {}", where(*error->column), error->message));
      std::vector<std::string> values;
      for (std::size_t j = 0; j < k; ++j)
        values.push_back(fmt::format("{} '{}'", q.columns[j].name, clip_text(fields[index[j]])));
      throw runner::InputError(fmt::format("{}, {}: method '{}' of '{}': {}", row_location(source, table, r),
                                           fmt::join(values, ", "), method.name, q.name, error->message));
    }
  }
  return args;
}

// Evaluates `method` on every row; returns the formatted values, one per row.
template <class T>
std::vector<std::string> evaluate(const Quantity& q, const Method& method, Precision precision,
                                  const runner::CsvTable& table, const std::string& source) {
  const MethodFn<T>& fn = method_function<T>(method);
  if (!fn)
    throw std::logic_error(fmt::format("method '{}' of '{}' has no {} evaluator in the registry", method.name, q.name,
                                       precision_name(precision)));
  const std::vector<T> args = parse_arguments<T>(q, method, table, argument_columns(q, table, source), source);

  // Rows are independent and the quadrature references are slow (up to about a second per row in
  // mp50), so spread them over the cores. Failures are recorded per row and reported below in
  // row order, so the message does not depend on scheduling.
  const std::size_t rows = table.rows.size();
  const std::size_t k = q.columns.size();
  std::vector<T> results(rows);
  std::vector<std::optional<std::string>> failures(rows);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rows), [&](const auto& range) {
    for (std::size_t r = range.begin(); r != range.end(); ++r) {
      try {
        results[r] = fn(std::span<const T>(args.data() + r * k, k));
      } catch (const std::exception& e) {
        failures[r] = e.what();
      }
    }
  });

  const int digits = round_trip_digits(precision);
  std::vector<std::string> formatted(rows);
  for (std::size_t r = 0; r < rows; ++r) {
    if (failures[r])
      throw std::runtime_error(fmt::format("{}: method '{}' of '{}' failed: {}", row_location(source, table, r),
                                           method.name, q.name, *failures[r]));
    formatted[r] = format_value(results[r], digits);
    // Never print a NaN or an infinity as if it were a result (docs/math.md §10).
    if (!is_finite_value(results[r]))
      throw std::runtime_error(fmt::format("{}: method '{}' of '{}' in {} returned {}, not a finite number",
                                           row_location(source, table, r), method.name, q.name,
                                           precision_name(precision), formatted[r]));
  }
  return formatted;
}

runner::CsvTable read_input(const std::string& path) {
  if (path.empty()) {
    struct stat st {};
    if (::fstat(0, &st) == 0 && S_ISDIR(st.st_mode))
      throw runner::InputError("standard input is a directory, not a CSV file");
    return runner::read_csv(std::cin, "<stdin>");
  }
  // An ifstream opens a directory without complaint and fails only when reading it.
  if (std::filesystem::is_directory(path))
    throw runner::InputError(fmt::format("the input '{}' is a directory, not a CSV file", path));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw runner::InputError(fmt::format("cannot open the input file '{}'", path));
  return runner::read_csv(in, path);
}

void write_output(const std::string& path, const std::string& text) {
  if (path.empty()) {
    std::cout << text << std::flush;
    if (!std::cout) throw std::runtime_error("cannot write to standard output");
    return;
  }
  runner::AtomicFile file(path);
  file.write(text);
  file.commit();
}

void run_eval(const EvalOptions& o) {
  if (o.list) {
    o.json ? print_list_json() : print_list_text();
    return;
  }
  if (o.quantity.empty())
    throw runner::InputError(fmt::format("eval needs a QUANTITY, one of: {} (see `sglab eval --list`)",
                                         fmt::join(frontend::quantity_names(), ", ")));
  const Quantity* q = find_quantity(o.quantity);
  if (!q) throw runner::InputError(runner::unknown_name_message("quantity", o.quantity, frontend::quantity_names()));
  if (o.method.empty())
    throw runner::InputError(
        fmt::format("eval {} needs --method, one of: {}", q->name, fmt::join(frontend::method_names(*q), ", ")));
  const Method* m = q->find(o.method);
  if (!m)
    throw runner::InputError(runner::unknown_name_message("method", o.method, frontend::method_names(*q)) +
                             " for quantity '" + q->name + "'");
  const auto precision = parse_precision(o.precision);
  if (!precision)
    throw runner::InputError(fmt::format("unknown precision {}; valid precisions: {}", quote(o.precision),
                                         fmt::join(kPrecisions | std::views::transform(precision_name), ", ")));

  runner::check_output_paths({{"--out", o.out}}, {{"--in", o.in}});

  // The constant set first: a bad set is bad input, reported before the table is read.
  const ConstantSet& set = o.constants.set;
  const Method bound = bind(*m, set);
  m = &bound;
  if (!m->parameters.empty())
    std::cerr << fmt::format("sglab eval: {} {} with constants:\n", q->name, m->name)
              << frontend::constants_text(set, frontend::method_constant_uses(q->name + "/" + m->name, *m), "  ")
              << std::flush;

  const runner::CsvTable table = read_input(o.in);
  const std::string source = o.in.empty() ? "<stdin>" : o.in;
  std::vector<std::string> values;
  switch (*precision) {
    case Precision::float32: values = evaluate<float>(*q, *m, *precision, table, source); break;
    case Precision::float64: values = evaluate<double>(*q, *m, *precision, table, source); break;
    case Precision::mp50: values = evaluate<mp50>(*q, *m, *precision, table, source); break;
  }

  std::vector<std::string> header = table.header;
  header.push_back(kValueColumn);
  std::string text;
  runner::append_csv_record(text, header);
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    std::vector<std::string> fields = table.rows[r].fields;
    fields.push_back(std::move(values[r]));
    runner::append_csv_record(text, fields);
  }
  write_output(o.out, text);
}

}  // namespace

void add_eval_command(CLI::App& app) {
  auto o = std::make_shared<EvalOptions>();
  CLI::App* cmd = app.add_subcommand("eval",
                                     "Evaluate a method of a quantity on every row of a CSV; appends a 'value' column");
  auto* quantity = cmd->add_option("quantity", o->quantity, "Quantity to evaluate (see --list)")
                       ->check(frontend::one_of(frontend::quantity_names(), "quantity"));
  auto* method = cmd->add_option("--method,-m", o->method,
                                 "Method of the quantity (see --list):" + frontend::methods_per_quantity());
  auto* precision = cmd->add_option("--precision,-p", o->precision,
                                    "float, double or mp50 (50 decimal digits); values are printed "
                                    "with 9, 17 or 50 significant digits")
                        ->capture_default_str();
  auto* in = cmd->add_option("--in,-i", o->in, "Input CSV with a header (default: standard input)");
  auto* out = cmd->add_option("--out,-o", o->out,
                              "Output CSV (default: standard output); written only if every row "
                              "succeeds, and replaced atomically");
  auto* list = cmd->add_flag("--list", o->list, "List every quantity with its columns and methods (source, flaws)");
  cmd->add_flag("--json", o->json, "With --list: print the list as JSON")->needs(list);
  frontend::add_constants_option(*cmd, o->constants);
  list->excludes(quantity)->excludes(method)->excludes(precision)->excludes(in)->excludes(out);
  cmd->footer(
      "Exit status: 0 on success; 2 for bad input (unknown quantity, method or precision, a "
      "missing column, a field that is not a finite number, a value outside its column's or the "
      "method's domain), naming the row, column and value; 1 if a method fails or returns NaN or "
      "infinity, or on an I/O error. On any error no output file is written.");
  cmd->callback([o] { run_eval(*o); });
}

}  // namespace sglab::cli
