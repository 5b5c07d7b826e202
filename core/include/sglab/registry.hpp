// Methods are data (ARCHITECTURE.md): every quantity the toolkit evaluates has one registry entry
// listing its input columns and its methods; each method carries its name (the same string on the
// command line, in CSV headers and in tables), its source, its known flaws, its domain, and one
// function per precision. The CLI, the sweeps, the benchmarks and the tables enumerate this
// registry; adding a method is one entry here.
#pragma once

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sglab/scalar.hpp"

namespace sglab {

enum class Precision { float32, float64, mp50 };

// "float", "double", "mp50".
std::string_view precision_name(Precision p);
std::optional<Precision> parse_precision(std::string_view name);
// Significant decimal digits that round-trip the precision (9, 17; 50 for mp50).
int round_trip_digits(Precision p);

// What an input column holds; it decides the column's validation.
enum class ColumnKind {
  sharpness,    // λ ≥ 0, finite
  cosine,       // |c| ≤ 1 + kCosineSlack (rounding past ±1 is accepted and clamped)
  mean_length,  // r ∈ [0, 1]
  positive,     // > 0, finite
  nonnegative,  // ≥ 0, finite
  angle,        // any finite value (radians)
  unit_interval // [0, 1]
};

// How far past ±1 an input cosine may be and still be taken as rounding (issue 2: 1 + 1e-6).
inline constexpr double kCosineSlack = 1e-6;

struct Column {
  std::string name;
  ColumnKind kind;
  std::string description;
};

template <class T>
using MethodFn = std::function<T(std::span<const T>)>;

// Evaluates rows × arity interleaved arguments into `out` (one value per row) in one call, so
// that timing loops pay one indirect call per batch instead of one per evaluation.
template <class T>
using BatchFn = std::function<void(std::span<const T> args, std::size_t arity, std::span<T> out)>;

struct Method {
  std::string name;
  std::string source;   // paper and equation
  std::string flaws;    // known flaws, as published; "" if none known
  bool may_be_negative = false;  // the published form itself goes negative (kept, measured)
  // Returns a message when the arguments are outside the method's domain (e.g. λ = 0 for a 2π/λ
  // form), so callers can reject them clearly instead of printing Inf or NaN. Checked after the
  // column validation.
  std::function<std::optional<std::string>(std::span<const double>)> domain_error;
  MethodFn<float> eval_float;
  MethodFn<double> eval_double;
  MethodFn<mp50> eval_mp50;
  BatchFn<float> batch_float;
  BatchFn<double> batch_double;
};

struct Quantity {
  std::string name;
  std::string description;
  std::vector<Column> columns;
  std::string reference_method;  // the method others are measured against ("" if none)
  std::vector<Method> methods;

  const Method* find(std::string_view method_name) const;
};

// Every quantity, in a stable order.
const std::vector<Quantity>& quantities();
const Quantity* find_quantity(std::string_view name);

// Validate one value of a column; returns a message naming what is wrong, or nullopt.
std::optional<std::string> column_value_error(const Column& column, double value);

// "sharpness", "cosine", … (the ColumnKind's name, as `sglab eval --list --json` prints it).
std::string_view column_kind_name(ColumnKind kind);

// What is wrong with one row of arguments (the values as validated: T's value, in double).
struct RowError {
  std::optional<std::size_t> column;  // the offending column; nullopt: the method's domain (whole row)
  std::string message;
};

// The checks every caller applies to a row before evaluating it (`sglab eval`, the Python
// module): each column's value in column order (column_value_error), then the method's domain
// (Method::domain_error). nullopt when the row may be evaluated.
std::optional<RowError> row_error(const Quantity& q, const Method& m, std::span<const double> row);

// Build a Method's three precision functions from one generic callable that takes a
// `std::span<const T>` and returns T. Keeps registrations one line each.
template <class F>
void set_evaluators(Method& m, F f) {
  m.eval_float = [f](std::span<const float> a) { return f(a); };
  m.eval_double = [f](std::span<const double> a) { return f(a); };
  m.eval_mp50 = [f](std::span<const mp50> a) { return f(a); };
  auto batch = [f](auto args, std::size_t arity, auto out) {
    using T = typename decltype(out)::value_type;
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = f(std::span<const T>(args.data() + i * arity, arity));
  };
  m.batch_float = [batch](std::span<const float> a, std::size_t n, std::span<float> o) { batch(a, n, o); };
  m.batch_double = [batch](std::span<const double> a, std::size_t n, std::span<double> o) { batch(a, n, o); };
}

// One registry entry from a generic callable (see set_evaluators).
template <class F>
Method make_method(std::string name, std::string source, std::string flaws, bool may_be_negative,
                   std::function<std::optional<std::string>(std::span<const double>)> domain, F f) {
  Method m;
  m.name = std::move(name);
  m.source = std::move(source);
  m.flaws = std::move(flaws);
  m.may_be_negative = may_be_negative;
  m.domain_error = std::move(domain);
  set_evaluators(m, f);
  return m;
}

// Registration hook for modules that add quantities (the glossy module, …). Each module defines
// one function that appends its quantities; registry.cpp calls them in order.
void register_core_quantities(std::vector<Quantity>& out);
// ASG integrals, ASG × SG product, specular reflection off GGX (SPEC.md §4–5, issue 4).
void register_glossy_quantities(std::vector<Quantity>& out);

}  // namespace sglab
