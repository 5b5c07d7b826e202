// Methods are data (ARCHITECTURE.md): every quantity the toolkit evaluates has one registry entry
// listing its input columns and its methods; each method carries its name (the same string on the
// command line, in CSV headers and in tables), its source, its known flaws, its domain, and one
// function per precision. The CLI, the sweeps, the benchmarks and the tables enumerate this
// registry; adding a method is one entry here.
#pragma once

#include <array>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "sglab/scalar.hpp"
#include "sglab/trace.hpp"

namespace sglab {

enum class Precision { float32, float64, mp50 };

// "float", "double", "mp50".
std::string_view precision_name(Precision p);
std::optional<Precision> parse_precision(std::string_view name);
// Significant decimal digits that round-trip the precision (9, 17; 50 for mp50).
int round_trip_digits(Precision p);

// What an input column holds; it decides the column's validation.
enum class ColumnKind {
  sharpness,      // λ ≥ 0, finite
  cosine,         // |c| ≤ 1 + kCosineSlack (rounding past ±1 is accepted and clamped)
  mean_length,    // r ∈ [0, 1]
  positive,       // > 0, finite
  nonnegative,    // ≥ 0, finite
  angle,          // any finite value (radians)
  unit_interval,  // [0, 1]
  finite = angle  // any finite value (a constant of either sign)
};

// How far past ±1 an input cosine may be and still be taken as rounding (1 + 1e-6).
inline constexpr double kCosineSlack = 1e-6;

struct Column {
  std::string name;
  ColumnKind kind;
  std::string description;
  // The values sweeps over stiff inputs (the stability atlas) take for this column; empty: the
  // atlas's values for the column's kind. `stiff_values_quick` for a quick run (empty: the same).
  std::vector<double> stiff_values = {};
  std::vector<double> stiff_values_quick = {};
};

template <class T>
using MethodFn = std::function<T(std::span<const T>)>;

// Evaluates rows × arity interleaved arguments into `out` (one value per row) in one call, so
// that timing loops pay one indirect call per batch instead of one per evaluation.
template <class T>
using BatchFn = std::function<void(std::span<const T> args, std::size_t arity, std::span<T> out)>;

// The same rows as columns (one pointer per column of the quantity, columns[j][i] row i's value of
// column j, out.size() rows), read in place: a caller holding columns (the Python module's arrays)
// neither interleaves them nor has them transposed back by the kernel.
template <class T>
using ColumnsBatchFn = std::function<void(std::span<const T* const> columns, std::span<T> out)>;

// What a method's batch evaluators run: its scalar template row by row (every method registered
// with set_evaluators), or the same template on SIMD lanes (the methods install_simd_batch_evaluators
// lists, docs/simd.md). `sglab eval --list` and the cost column of `sglab error-vs-time` say which.
enum class BatchPath { scalar, vectorized };
// "scalar", "vectorized".
std::string_view batch_path_name(BatchPath path);

// ---- constants as data ----------------------------------------------------------------------
// To give a method constants: define each published value once in its core header (a struct of
// static constexpr doubles, as Tokuyoshi2024T), register the method with
// make_method_with_parameters(…, {Parameter{…}, …}, published_fn, with_fn), and list the names in
// the re-deriving fit's Fitter::parameters (fit/driver.hpp). Commands then accept the fit's
// records through `--constants` (frontend/constant_sets.hpp) with no further change; the test
// tests/constants_test.cpp checks the declarations and that each value is defined once.
// A published constant a method (or the renderer, or the filter) depends on. Its value is defined
// once in core, in the struct the registration cites (SgCosine, Tokuyoshi2024T, …); `sglab fit
// FIT` re-derives it as the record parameter `name`; a ConstantSet (`--constants PATH`) replaces
// it at run time. Printing `published` with 17 significant digits round-trips it.
// What a parameter is to code outside its method, so that callers below the command line find it
// by role, never by its name.
enum class ParameterRole {
  constant,  // a fitted constant of the method alone (bound from a constant set)
  // The sharpness λ_d of the VPLs' diffuse lobes (sg-cosine's): the renderer binds it to the VSGL
  // set's λ_d, and --sg-cosine-a-pi applies to the method that has it.
  vsgl_diffuse_sharpness,
};

struct Parameter {
  std::string name;  // as in the fit record: "lambda_d", "A", "p1", …
  std::string fit;   // the `sglab fit` name that re-derives it ("" if none)
  double published = 0;
  std::string source;                      // paper and equation
  ColumnKind kind = ColumnKind::positive;  // its domain, checked with column_value_error
  ParameterRole role = ParameterRole::constant;
};

// The constants `sglab fit FIT` re-derives, all from one source: each its name, published value and
// domain, as Parameters of that fit.
struct FitConstant {
  std::string name;
  double published = 0;
  ColumnKind kind = ColumnKind::positive;
};
std::vector<Parameter> fit_parameters(const std::string& fit, const std::string& source,
                                      const std::vector<FitConstant>& constants);

// The method's formula on the tracing type (trace.hpp): the inputs in column order, and its
// constants (one per Method::parameters entry) as traced values. What `sglab export` emits code from.
using TraceFn = std::function<Trace(std::span<const Trace> args, std::span<const Trace> params)>;

// A method's 50-digit evaluator, a MethodFn<mp50>, held without naming the 50-digit type: the units
// that copy methods, or evaluate them in float and double, then compile without
// Boost.Multiprecision. The function is defined in sglab/registry_mp50.hpp, which the units that
// set or call it include (without it, the member templates below name an incomplete type).
struct Mp50Function;
namespace detail {
template <class T, class>
struct deferred {  // T, looked up only when a template is instantiated
  using type = T;
};
}  // namespace detail
class Mp50Evaluator {
 public:
  explicit operator bool() const { return held_ != nullptr; }
  // The MethodFn<mp50> (A only defers the lookup to instantiation). std::bad_function_call when
  // none is held, as for an empty MethodFn.
  template <class A = void>
  const auto& function() const {
    if (!held_) throw std::bad_function_call();
    return static_cast<const typename detail::deferred<Mp50Function, A>::type&>(*held_).fn;
  }
  template <class A>
  auto operator()(const A& args) const {
    return function<A>()(args);
  }
  // Holds f, a callable on std::span<const mp50> (set_evaluators' generic formula, or a lambda).
  template <class F>
  Mp50Evaluator& operator=(F f) {
    using Held = typename detail::deferred<Mp50Function, F>::type;
    held_ = std::make_shared<const Held>(Held{std::move(f)});
    return *this;
  }

 private:
  std::shared_ptr<const Mp50Function> held_;  // shared: copying a method copies no function
};

struct Method;
// Returns `m` evaluating with `values` (one per m.parameters entry, same order) instead of the
// published values. The published evaluators are not touched, so the published path costs nothing.
using BindFn = std::function<Method(std::span<const double> values)>;

struct Method {
  std::string name;
  std::string source;            // paper and equation
  std::string flaws;             // known flaws, as published; "" if none known
  bool may_be_negative = false;  // the published form itself goes negative (kept, measured)
  // Evaluates in double whatever the precision (a quadrature reference: float rounds and mp50
  // converts the double result). An mp50 argument outside double's range cannot reach it, so
  // callers refuse such a row (runner/parse_number_mp50.hpp validation_double).
  bool evaluates_in_double = false;
  // Returns a message when the arguments are outside the method's domain (e.g. λ = 0 for a 2π/λ
  // form), so callers can reject them clearly instead of printing Inf or NaN. Checked after the
  // column validation.
  std::function<std::optional<std::string>(std::span<const double>)> domain_error;
  // The same domain stated as open lower bounds {column, bound} when it is one (every row with
  // row[column] > bound for each passes domain_error, and no other): a caller may then check a
  // block of rows by its least values instead of calling domain_error row by row (the Python
  // module). Empty: domain_error is the only statement.
  std::vector<std::pair<std::size_t, double>> domain_above;
  MethodFn<float> eval_float;
  MethodFn<double> eval_double;
  Mp50Evaluator eval_mp50;  // (sglab/registry_mp50.hpp)
  BatchFn<float> batch_float;
  BatchFn<double> batch_double;
  BatchPath batch_path = BatchPath::scalar;  // what batch_float and batch_double run
  // The vectorized methods' kernels on columns, bit for bit batch_float's and batch_double's
  // values; empty for the scalar ones (a caller then interleaves rows for batch_*).
  ColumnsBatchFn<float> columns_float;
  ColumnsBatchFn<double> columns_double;
  // The method's constants (empty: none) and how to evaluate with other values (set when
  // `parameters` is not empty). A bound method has no `bind` of its own: bind the base method.
  std::vector<Parameter> parameters;
  BindFn bind;
  // The formula on the tracing type; empty when the method is not exportable (`sglab export`
  // says so by name). Set by the `exportable` registrations below.
  TraceFn trace;
  // Why a method without `trace` is not exportable, when more is known than the generic reason
  // (a branch on its inputs that is not a select, or a quadrature): `sglab export` and the table
  // of `sglab shader-export` print it.
  std::string not_exportable_because;
};

// The largest sharpness (or ASG bandwidth) at which sweeps over stiff inputs run the quadrature
// references (reference.hpp, glossy_reference.hpp); past it they use a closed-form limit or none.
inline constexpr double kQuadratureMaxSharpness = 1e8;

// Where a quantity's reference method may be run by sweeps over stiff inputs (the stability
// atlas). The default: on every row.
struct ReferenceReach {
  // Not past this value in any sharpness or nonnegative column (a quadrature's reach) …
  double max_sharpness = std::numeric_limits<double>::infinity();
  // … where the closed-form large-sharpness limit of the quantity stands in (nullptr: nothing is
  // compared there); `limit_formula` says what it is and how close.
  std::function<double(std::span<const double>)> limit = nullptr;
  std::string limit_formula = {};
  // A reference too slow for the whole grid: at most `rows` rows (`rows_quick` in a quick run; 0:
  // every row), spread over those where `affordable` holds (nullptr: all). `cost` says why, and
  // `affordable_rows` which rows those are.
  std::size_t rows = 0, rows_quick = 0;
  std::function<bool(std::span<const double>)> affordable = nullptr;
  std::string cost = {};
  std::string affordable_rows = {};
};

struct Quantity {
  std::string name;
  std::string description;
  std::vector<Column> columns;
  std::string reference_method;  // the method others are measured against ("" if none)
  std::vector<Method> methods;
  ReferenceReach reference_reach = {};

  const Method* find(std::string_view method_name) const;
};

// The method's function for the scalar type T (float, double or mp50: then with
// sglab/registry_mp50.hpp), for code templated on T.
template <class T>
const MethodFn<T>& method_function(const Method& m) {
  if constexpr (std::is_same_v<T, float>) return m.eval_float;
  else if constexpr (std::is_same_v<T, double>) return m.eval_double;
  else return m.eval_mp50.function<T>();
}
// The method's value at `args` in T.
template <class T>
T eval_as(const Method& m, std::span<const T> args) {
  return method_function<T>(m)(args);
}

// Every quantity, in a stable order.
const std::vector<Quantity>& quantities();
const Quantity* find_quantity(std::string_view name);

// The value of q's reference method (q.reference_method, an exact reference without constants) at
// `args`, computed once per process and then kept: for code that fills grids of references, so
// that the steps of one `sglab reproduce` share the rows they have in common (`fit all`'s
// sglab-specular fit and `sweep specular` integrate the same rows). The value is the method's
// eval_double, bit for bit. Not for timing the reference. std::invalid_argument when q has no
// reference method or it has constants.
double reference_value(const Quantity& q, std::span<const double> args);

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

// A method's domain as a registration states it: nullptr (every row), a function of the row
// (Method::domain_error), or open lower bounds on columns with the message for a row outside them
// (above(): both Method::domain_error and Method::domain_above from the one statement).
struct Domain {
  std::function<std::optional<std::string>(std::span<const double>)> error;
  std::vector<std::pair<std::size_t, double>> bounds;
  Domain(std::nullptr_t = nullptr) {}
  template <class F>
  requires std::is_constructible_v < std::function < std::optional<std::string>(std::span<const double>)
  >, F > Domain(F f) : error(std::move(f)) {}
  static Domain above(std::vector<std::pair<std::size_t, double>> bounds, std::string message);
};

// Build a Method's three precision functions from one generic callable that takes a
// `std::span<const T>` and returns T. Keeps registrations one line each. (The mp50 one needs
// sglab/registry_mp50.hpp, which every unit that registers methods includes.)
template <class F>
void set_evaluators(Method& m, F f) {
  m.eval_float = [f](std::span<const float> a) { return f(a); };
  m.eval_double = [f](std::span<const double> a) { return f(a); };
  m.eval_mp50 = f;
  auto batch = [f](auto args, std::size_t arity, auto out) {
    using T = typename decltype(out)::value_type;
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = f(std::span<const T>(args.data() + i * arity, arity));
  };
  m.batch_float = [batch](std::span<const float> a, std::size_t n, std::span<float> o) { batch(a, n, o); };
  m.batch_double = [batch](std::span<const double> a, std::size_t n, std::span<double> o) { batch(a, n, o); };
  m.batch_path = BatchPath::scalar;
  m.columns_float = nullptr;
  m.columns_double = nullptr;
}

// One registry entry from a generic callable (see set_evaluators).
template <class F>
Method make_method(std::string name, std::string source, std::string flaws, bool may_be_negative, Domain domain, F f) {
  Method m;
  m.name = std::move(name);
  m.source = std::move(source);
  m.flaws = std::move(flaws);
  m.may_be_negative = may_be_negative;
  m.domain_error = std::move(domain.error);
  m.domain_above = std::move(domain.bounds);
  set_evaluators(m, f);
  return m;
}

// A method with constants: `published` is the ordinary generic callable (the published path, as
// in make_method); `with(args, p)` evaluates with the parameter values p (a std::span<const T>,
// one per `parameters` entry, already converted to T).
template <class F, class G>
Method make_method_with_parameters(std::string name, std::string source, std::string flaws, bool may_be_negative,
                                   Domain domain, std::vector<Parameter> parameters, F published, G with) {
  Method m = make_method(std::move(name), std::move(source), std::move(flaws), may_be_negative, std::move(domain),
                         published);
  m.parameters = std::move(parameters);
  Method base = m;
  m.bind = [base, with](std::span<const double> values) {
    Method b = base;
    const std::vector<double> v(values.begin(), values.end());
    set_evaluators(b, [with, v](auto a) {
      using T = typename decltype(a)::value_type;
      // At most 8 constants per method: a fixed array keeps the bound path allocation-free.
      std::array<T, 8> p{};
      for (std::size_t i = 0; i < v.size() && i < p.size(); ++i) p[i] = T(v[i]);
      return with(a, std::span<const T>(p.data(), v.size()));
    });
    return b;
  };
  return m;
}

// The same registrations for a method whose formula also instantiates on the tracing type
// (every branch on an input a select): the first argument `exportable` makes `sglab export` emit
// it. The traced formula is `f` itself (without constants) or `with` (with its constants).
struct Exportable {};
inline constexpr Exportable exportable{};

template <class F>
Method make_method(Exportable, std::string name, std::string source, std::string flaws, bool may_be_negative,
                   Domain domain, F f) {
  Method m = make_method(std::move(name), std::move(source), std::move(flaws), may_be_negative, std::move(domain), f);
  m.trace = [f](std::span<const Trace> a, std::span<const Trace>) { return f(a); };
  return m;
}

template <class F, class G>
Method make_method_with_parameters(Exportable, std::string name, std::string source, std::string flaws,
                                   bool may_be_negative, Domain domain, std::vector<Parameter> parameters, F published,
                                   G with) {
  Method m = make_method_with_parameters(std::move(name), std::move(source), std::move(flaws), may_be_negative,
                                         std::move(domain), std::move(parameters), published, with);
  m.trace = [with](std::span<const Trace> a, std::span<const Trace> p) { return with(a, p); };
  return m;
}

// A set of constants that replace published ones: (fit, parameter) → value, with where each value
// came from. Later `set` calls override earlier ones. Lookups not in the set give the published
// value. Reading sets from files is the CLI's business (frontend/constant_sets.hpp).
struct ConstantValue {
  std::string fit;
  std::string name;
  double value = 0;
  std::string provenance;  // "file F: fit lambda-d, objective …, precision …"
};
struct ConstantSet {
  std::vector<ConstantValue> values;
  void set(ConstantValue v);
  const ConstantValue* find(std::string_view fit, std::string_view name) const;
  // The parameter's value in this set (its published value when the set does not override it).
  double value(const Parameter& p) const;
  bool empty() const { return values.empty(); }
};

// `m` with every parameter the set overrides replaced (a copy of `m` when it overrides none).
Method bind(const Method& m, const ConstantSet& set);

// Every published constant the toolkit uses: each registry method's parameters, then the
// constants of code that is not a registry method (the renderer's λ_d, the filter's λ_c), with
// who uses it ("clamped-cosine/sg-cosine", "render", "filter").
struct ConstantUse {
  std::string user;
  const Parameter* parameter;
};
std::vector<ConstantUse> constant_uses();
// The standalone constants (render λ_d, filter λ_c) by user, nullptr if none.
const Parameter* find_standalone_constant(std::string_view user, std::string_view name);

// Registration hook for modules that add quantities (the glossy module, …). Each module defines
// one function that appends its quantities; registry.cpp calls them in order.
void register_core_quantities(std::vector<Quantity>& out);
// ASG integrals, ASG × SG product, specular reflection off GGX (docs/math.md §4–5).
void register_glossy_quantities(std::vector<Quantity>& out);
// The stiff cases of docs/math.md §10 that are not formulas of their own: (nearly) opposite SG
// lobes, degenerate VPL sets, the shading point on top of a VSGL. Registered last: the last one
// wraps the clamped-cosine methods registered before it.
void register_stiff_quantities(std::vector<Quantity>& out);
// Replaces the batch evaluators of the vectorized methods (and of their bound versions) with the
// SIMD kernels of core/src/simd (docs/simd.md); run after every module registered. The scalar
// evaluators stay the definition.
void install_simd_batch_evaluators(std::vector<Quantity>& quantities);

}  // namespace sglab
