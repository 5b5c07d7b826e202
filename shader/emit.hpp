// `sglab export` as a library: a registry method's formula, traced on sglab::Trace
// (core/include/sglab/trace.hpp) with its constants bound, written as GLSL, HLSL or C source
// (docs/export.md). The code is the recorded formula itself — the same stable forms and the same
// branches (as selects) as sglab's scalar path — in float, with each constant a named literal with
// round-trip digits and its provenance.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sglab/registry.hpp"

namespace sglab::shader {

enum class Language { glsl, hlsl, c };

std::string_view language_name(Language lang);  // "glsl", "hlsl", "c"
std::optional<Language> parse_language(std::string_view name);
const std::vector<std::string>& language_names();

// One constant of an exported method: its value as bound and where it came from.
struct ExportedConstant {
  std::string name;        // the method parameter's name ("A", "lambda_d")
  std::string identifier;  // its name in the code ("c_A")
  double value = 0;        // as bound (double); the code holds float(value)
  std::string provenance;  // "published: SOURCE" or the constant set's provenance
};

// A method's formula as traced: the graph, its output node, and what the code says about it.
struct TracedMethod {
  const Quantity* quantity = nullptr;
  const Method* method = nullptr;
  std::string function;             // the exported function's name, "sglab_clamped_cosine_tokuyoshi2024"
  std::vector<std::string> inputs;  // its arguments: the quantity's columns, in order
  std::vector<ExportedConstant> constants;
  TraceGraph graph;
  int output = -1;

  std::string name() const { return quantity->name + "/" + method->name; }
  // The traced formula evaluated in float by the graph's interpreter (the same operations, in
  // the same order, with the same library functions as sglab's float path).
  float evaluate(std::span<const float> args) const { return graph.evaluate(output, args.data()); }
};

// "QUANTITY/METHOD" → the registry's method; runner::InputError naming the (clipped) value when
// there is no such method, and when the method cannot be exported (saying why).
struct MethodRef {
  const Quantity* quantity;
  const Method* method;
};
MethodRef find_exportable(std::string_view quantity_slash_method);

// Why `m` (which has no traced formula) cannot be exported.
std::string not_exportable_reason(const Quantity& q, const Method& m);

// Every exportable method ("quantity/method"): the registry's, in registry order, then the
// export-only ones.
std::vector<std::string> exportable_methods();

// Formulas `sglab export` emits that are not registry quantities (no `sglab eval`, no reference
// method): the filtering weights `filtering/lobe-weight` (App. E, lobe_aware_weight) and
// `filtering/normal-weight` (App. D, normal_weight) of core/include/sglab/filtering_weights.hpp,
// each a Quantity named "filtering" whose columns are the function's scalar arguments in order.
// Their evaluators (float, double, mp50) are the same template's. (shader/export_only.cpp)
const std::vector<Quantity>& export_only_quantities();
// Whether q is one of export_only_quantities().
bool is_export_only(const Quantity& q);

// Traces `m` with the constants of `set` (published where the set does not override).
// runner::InputError when the method is not exportable.
TracedMethod trace_method(const Quantity& q, const Method& m, const ConstantSet& set);

// Self-contained source defining one function per method (float in, float out), the helpers the
// language lacks first; `command` (the command line that made it) heads the file.
std::string emit(std::span<const TracedMethod> methods, Language lang, std::string_view command);

}  // namespace sglab::shader
