// The emitter: walks a traced method's graph and writes it as GLSL, HLSL or C (docs/export.md).
#include "emit.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <set>

#include <fmt/core.h>

#include "input_error.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::shader {
namespace {

const std::vector<std::string> kLanguageNames = {"glsl", "hlsl", "c"};

// Letters, digits and '_' only; a leading digit gets a '_'.
std::string identifier(std::string_view s) {
  std::string out;
  for (char ch : s) out += (std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_');
  if (out.empty() || std::isdigit(static_cast<unsigned char>(out[0]))) out = "_" + out;
  return out;
}

// The shortest decimal that reads back to the float (at most 9 significant digits), with a
// decimal point and the f suffix every one of the three languages accepts.
std::string float_literal(float v, Language lang) {
  if (std::isinf(v)) {
    const char* inf = lang == Language::glsl   ? "uintBitsToFloat(0x7F800000u)"
                      : lang == Language::hlsl ? "asfloat(0x7F800000u)"
                                               : "INFINITY";
    return v > 0 ? inf : fmt::format("(-{})", inf);
  }
  if (std::isnan(v))
    return lang == Language::c      ? "NAN"
           : lang == Language::glsl ? "uintBitsToFloat(0x7FC00000u)"
                                    : "asfloat(0x7FC00000u)";
  char buf[64];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;  // shortest round-trip, fixed or scientific
  std::string s(buf, end);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  else if (s.find('.') == std::string::npos) s.insert(s.find('e'), ".0");
  s += "f";
  return v < 0 || (v == 0 && std::signbit(v)) ? "(" + s + ")" : s;
}

// The helper functions a language lacks, by the operation that needs them.
// Their arithmetic is `precise` (GLSL and HLSL: SPIR-V NoContraction), as the exported functions'
// is (emit_function): without it the driver's compiler may reassociate, fuse and simplify float
// expressions, which undoes the forms that keep them accurate ((1 + x) − 1 is not x in float).
struct Helper {
  TraceOp op;
  std::string name;
  std::string text;  // GLSL and HLSL share it (only float arithmetic, exp, log, abs)
};

const std::vector<Helper>& helpers() {
  static const std::vector<Helper> h = {
      {TraceOp::expm1, "sglab_expm1",
       "// e^x − 1 without the cancellation of exp(x) − 1 near 0: for |x| ≤ 0.5 its Taylor series to x^8\n"
       "// in nested form (the first term left out, x^9/9!, is below 1.1e-8 relative there); exp(x) − 1\n"
       "// elsewhere (|e^x − 1| ≥ 0.39 there: exp's relative error grows by at most 2.6×). Not Kahan's\n"
       "// (u − 1)·x/log(u): GPU log is specified only to an absolute 2^-21 near 1 (Vulkan precision\n"
       "// rules), which that form turns into a relative error.\n"
       "float sglab_expm1(float x) {\n"
       "  precise float e = exp(x) - 1.0f;\n"
       "  precise float s = x * (1.0f + x * (0.5f + x * (0.166666672f + x * (0.0416666679f + x * (0.00833333377f\n"
       "      + x * (0.00138888892f + x * (0.000198412701f + x * 2.48015876e-05f)))))));\n"
       "  return abs(x) > 0.5f ? e : s;\n"
       "}\n"},
      {TraceOp::log1p, "sglab_log1p",
       "// log(1 + x) without the rounding of 1 + x: for |x| ≤ 0.5, 2·atanh(s), s = x/(2 + x), by its\n"
       "// series 2s·Σ s^(2k)/(2k + 1) to k = 6 in nested form (|s| ≤ 1/3: the first term left out is\n"
       "// below 1.2e-8 relative); log(1 + x) elsewhere. Not Goldberg's log(u)·x/(u − 1) (1991, Thm. 4):\n"
       "// GPU log is specified only to an absolute 2^-21 near 1 (Vulkan precision rules), which that\n"
       "// form turns into a relative error (on lavapipe it put the lobe-aware filtering weight 1.4e-6,\n"
       "// 23 ulps, off where its exponent, β/2·log1p(−r²), is −0.0012).\n"
       "float sglab_log1p(float x) {\n"
       "  precise float s = x / (2.0f + x);\n"
       "  precise float q = s * s;\n"
       "  precise float r = 2.0f * s * (1.0f + q * (0.333333343f + q * (0.200000003f + q * (0.142857149f\n"
       "      + q * (0.111111112f + q * (0.0909090936f + q * 0.0769230798f))))));\n"
       "  precise float l = log(1.0f + x);\n"
       "  return abs(x) > 0.5f ? l : r;\n"
       "}\n"},
      {TraceOp::erfc, "sglab_erfc",
       "// erfc(x) = t·exp(−z² + P(t)), t = 1/(1 + z/2), z = |x|; erfc(−z) = 2 − erfc(z) (Press et al.,\n"
       "// Numerical Recipes, 2nd ed., §6.2, erfcc: relative error < 1.2e-7 for every x in exact\n"
       "// arithmetic). In float z² rounds: for large z the value loses about z²·2^-24 relative\n"
       "// (5e-6 at z = 9, where erfc ≈ 4e-37).\n"
       "float sglab_erfc(float x) {\n"
       "  float z = abs(x);\n"
       "  precise float t = 1.0f / (1.0f + 0.5f * z);\n"
       "  precise float p = -1.26551223f + t * (1.00002368f + t * (0.37409196f + t * (0.09678418f + t * (-0.18628806f\n"
       "      + t * (0.27886807f + t * (-1.13520398f + t * (1.48851587f + t * (-0.82215223f + t * "
       "0.17087277f))))))));\n"
       "  precise float r = t * exp(-z * z + p);\n"
       "  precise float l = 2.0f - r;\n"
       "  return x >= 0.0f ? r : l;\n"
       "}\n"},
      {TraceOp::erf, "sglab_erf",
       "// erf(x): for |x| < 0.5 the Maclaurin series 2/√π·Σ (−1)^n x^(2n+1)/(n!(2n+1)) to n = 6\n"
       "// (the first term left out is below 1e-9 relative), else ±(1 − erfc(|x|)) with sglab_erfc\n"
       "// (erf ≥ 0.52 there: the absolute error 1.2e-7 of erfc is at most 2.3e-7 relative).\n"
       "float sglab_erf(float x) {\n"
       "  float z = abs(x);\n"
       "  if (z < 0.5f) {\n"
       "    precise float q = x * x;\n"
       "    precise float s = x * 1.12837917f * (1.0f + q * (-0.333333333f + q * (0.1f + q * (-0.0238095238f\n"
       "        + q * (0.00462962963f + q * (-0.000757575758f + q * 0.000106837607f))))));\n"
       "    return s;\n"
       "  }\n"
       "  precise float r = 1.0f - sglab_erfc(z);\n"
       "  return x >= 0.0f ? r : -r;\n"
       "}\n"},
  };
  return h;
}

// The C spelling of each helper: the C library's own (the same functions sglab's float path calls).
const char* c_function(TraceOp op) {
  switch (op) {
    case TraceOp::exp: return "expf";
    case TraceOp::expm1: return "expm1f";
    case TraceOp::log: return "logf";
    case TraceOp::log1p: return "log1pf";
    case TraceOp::sqrt: return "sqrtf";
    case TraceOp::erf: return "erff";
    case TraceOp::erfc: return "erfcf";
    case TraceOp::abs: return "fabsf";
    case TraceOp::sin: return "sinf";
    case TraceOp::cos: return "cosf";
    default: return nullptr;
  }
}

const char* shader_function(TraceOp op) {
  switch (op) {
    case TraceOp::exp: return "exp";
    case TraceOp::expm1: return "sglab_expm1";
    case TraceOp::log: return "log";
    case TraceOp::log1p: return "sglab_log1p";
    case TraceOp::sqrt: return "sqrt";
    case TraceOp::erf: return "sglab_erf";
    case TraceOp::erfc: return "sglab_erfc";
    case TraceOp::abs: return "abs";
    case TraceOp::sin: return "sin";
    case TraceOp::cos: return "cos";
    default: return nullptr;
  }
}

const char* binary_operator(TraceOp op) {
  switch (op) {
    case TraceOp::add: return "+";
    case TraceOp::sub: return "-";
    case TraceOp::mul: return "*";
    case TraceOp::div: return "/";
    case TraceOp::lt: return "<";
    case TraceOp::le: return "<=";
    case TraceOp::gt: return ">";
    case TraceOp::ge: return ">=";
    case TraceOp::and_: return "&&";
    case TraceOp::or_: return "||";
    default: return nullptr;
  }
}

bool is_boolean(TraceOp op) {
  return op == TraceOp::lt || op == TraceOp::le || op == TraceOp::gt || op == TraceOp::ge || op == TraceOp::not_ ||
         op == TraceOp::and_ || op == TraceOp::or_;
}

// The operations a traced method uses (to pick the helpers).
std::set<TraceOp> used_operations(const TracedMethod& m) {
  std::set<TraceOp> ops;
  for (const auto& n : m.graph.nodes)
    if (n.varying) ops.insert(n.op);
  return ops;
}

// One method's function.
std::string emit_function(const TracedMethod& m, Language lang) {
  const auto& nodes = m.graph.nodes;
  const int out = m.output;
  // Uses of each input-dependent node reachable from the output.
  std::vector<int> uses(nodes.size(), 0);
  std::vector<char> reachable(nodes.size(), 0);
  reachable[out] = 1;
  for (int i = out; i >= 0; --i) {
    if (!reachable[i] || !nodes[i].varying) continue;
    for (int o : {nodes[i].a, nodes[i].b, nodes[i].c})
      if (o >= 0) {
        reachable[o] = 1;
        ++uses[o];
      }
  }
  std::vector<std::string> expr(nodes.size());
  std::vector<char> used_constant(m.constants.size(), 0);
  // GLSL and HLSL: every value is `precise` (SPIR-V NoContraction), so that the driver's compiler
  // evaluates the operations as written — no reassociation, no fused multiply-add, no algebraic
  // simplification. Without it lavapipe gave NaN for clamped-cosine/cosine-lobe-sg at λ = FLT_MAX,
  // c ≥ 1 − 2⁻²⁴, where sglab float is finite: product_integral_exact's L = s·(−2u1u2(1 − c)/d),
  // s = FLT_MAX, u2 = 2.133/s (subnormal), reordered — the threshold in c is where u2·(1 − c)
  // underflows to 0, consistent with an overflowed s·2 = ∞ times that 0. With `precise` the same
  // GLSL gives sglab float's value. C is compiled without contraction (toolchain.cpp:
  // -ffp-contract=off) and needs nothing.
  const std::string precise = lang == Language::c ? "" : "precise ";
  std::string body;
  int locals = 0;
  auto operand = [&](int id) -> std::string {
    const TraceNode& n = nodes[id];
    if (n.varying) return expr[id];
    if (n.op == TraceOp::param) {
      used_constant[n.index] = 1;
      return m.constants[n.index].identifier;
    }
    if (is_boolean(n.op)) return n.value != 0 ? "true" : "false";
    return float_literal(n.value, lang);
  };
  for (int i = 0; i <= out; ++i) {
    const TraceNode& n = nodes[i];
    if (!reachable[i] || !n.varying) continue;
    std::string e;
    if (n.op == TraceOp::input) {
      expr[i] = m.inputs[n.index];
      continue;
    } else if (const char* op = binary_operator(n.op)) {
      e = fmt::format("({} {} {})", operand(n.a), op, operand(n.b));
    } else if (n.op == TraceOp::neg) {
      e = fmt::format("(-{})", operand(n.a));
    } else if (n.op == TraceOp::not_) {
      e = fmt::format("(!{})", operand(n.a));
    } else if (n.op == TraceOp::select) {
      e = fmt::format("({} ? {} : {})", operand(n.a), operand(n.b), operand(n.c));
    } else {
      const char* f = lang == Language::c ? c_function(n.op) : shader_function(n.op);
      e = fmt::format("{}({})", f, operand(n.a));
    }
    // A value used twice, a select, or a long expression gets a local (each computed once).
    if (i == out) {
      expr[i] = e;
    } else if (uses[i] > 1 || n.op == TraceOp::select || e.size() > 72) {
      const std::string name = fmt::format("v{}", ++locals);
      body += fmt::format("  {}{} {} = {};\n", precise, is_boolean(n.op) ? "bool" : "float", name, e);
      expr[i] = name;
    } else {
      expr[i] = e;
    }
  }
  const std::string result = nodes[out].varying ? expr[out] : operand(out);

  const Quantity& q = *m.quantity;
  const Method& meth = *m.method;
  std::string s;
  s += fmt::format("// {}: {}\n", m.name(), meth.source);
  s += fmt::format("// Quantity: {}\n", q.description);
  s += is_export_only(q) ? std::string("// Arguments, in order:")
                         : "// Arguments, in the order of the columns of `sglab eval " + q.name + "`:";
  for (std::size_t i = 0; i < q.columns.size(); ++i)
    s += fmt::format("{} {} ({})", i ? ";" : "", m.inputs[i], q.columns[i].description);
  s += ".\n";
  if (!meth.flaws.empty()) s += fmt::format("// Known flaws, kept as published: {}\n", meth.flaws);
  if (!m.constants.empty()) {
    s += "// Constants (float literals with the digits that round-trip the float; the value as bound, shortest "
         "round-trip double):\n";
    for (const auto& c : m.constants) s += fmt::format("//   {} = {}: {}\n", c.name, c.value, c.provenance);
  }
  std::string params;
  for (std::size_t i = 0; i < m.inputs.size(); ++i) params += fmt::format("{}float {}", i ? ", " : "", m.inputs[i]);
  s += fmt::format("float {}({}) {{\n", m.function, params);
  for (std::size_t i = 0; i < m.constants.size(); ++i)
    if (used_constant[i])
      s += fmt::format("  const float {} = {};\n", m.constants[i].identifier,
                       float_literal(static_cast<float>(m.constants[i].value), lang));
  s += body;
  if (lang == Language::c || !nodes[out].varying) s += fmt::format("  return {};\n}}\n", result);
  else s += fmt::format("  {}float result = {};\n  return result;\n}}\n", precise, result);
  return s;
}

}  // namespace

std::string_view language_name(Language lang) { return kLanguageNames[static_cast<int>(lang)]; }

std::optional<Language> parse_language(std::string_view name) {
  for (std::size_t i = 0; i < kLanguageNames.size(); ++i)
    if (kLanguageNames[i] == name) return static_cast<Language>(i);
  return std::nullopt;
}

const std::vector<std::string>& language_names() { return kLanguageNames; }

std::string not_exportable_reason(const Quantity& q, const Method& m) {
  if (!m.not_exportable_because.empty()) return m.not_exportable_because;
  return fmt::format(
      "its formula is not written for the tracing type (a branch on its inputs that is not a select, or a "
      "quadrature){}",
      m.name == q.reference_method ? " — it is the quantity's reference" : "");
}

bool is_export_only(const Quantity& q) {
  for (const auto& e : export_only_quantities())
    if (&e == &q) return true;
  return false;
}

MethodRef find_exportable(std::string_view name) {
  const auto slash = name.find('/');
  const Quantity* q = slash == std::string_view::npos ? nullptr : find_quantity(name.substr(0, slash));
  const Method* m = q ? q->find(name.substr(slash + 1)) : nullptr;
  if (!m && slash != std::string_view::npos)
    for (const auto& e : export_only_quantities())
      if (e.name == name.substr(0, slash) && e.find(name.substr(slash + 1))) {
        q = &e;
        m = e.find(name.substr(slash + 1));
        break;
      }
  if (!m)
    throw runner::InputError(fmt::format(
        "unknown method '{}' (QUANTITY/METHOD; `sglab export --list` lists the exportable ones)", clip_text(name)));
  if (!m->trace)
    throw runner::InputError(
        fmt::format("{}/{} cannot be exported: {}; `sglab export --list` lists the exportable methods", q->name,
                    m->name, not_exportable_reason(*q, *m)));
  return {q, m};
}

std::vector<std::string> exportable_methods() {
  std::vector<std::string> out;
  for (const auto& q : quantities())
    for (const auto& m : q.methods)
      if (m.trace) out.push_back(q.name + "/" + m.name);
  for (const auto& q : export_only_quantities())
    for (const auto& m : q.methods) out.push_back(q.name + "/" + m.name);
  return out;
}

TracedMethod trace_method(const Quantity& q, const Method& m, const ConstantSet& set) {
  if (!m.trace) find_exportable(q.name + "/" + m.name);  // throws, saying why
  TracedMethod t;
  t.quantity = &q;
  t.method = &m;
  t.function = "sglab_" + identifier(q.name) + "_" + identifier(m.name);
  for (const auto& c : q.columns) t.inputs.push_back(identifier(c.name));
  for (const auto& p : m.parameters) {
    ExportedConstant c;
    c.name = p.name;
    c.identifier = "c_" + identifier(p.name);
    c.value = set.value(p);
    const ConstantValue* v = p.fit.empty() ? nullptr : set.find(p.fit, p.name);
    c.provenance = v ? v->provenance : "published: " + p.source;
    t.constants.push_back(std::move(c));
  }
  TraceRecording recording(t.graph);
  std::vector<Trace> args, params;
  for (std::size_t i = 0; i < q.columns.size(); ++i) args.push_back(Trace::input(int(i)));
  for (std::size_t i = 0; i < t.constants.size(); ++i)
    params.push_back(Trace::parameter(int(i), static_cast<float>(t.constants[i].value)));
  try {
    t.output = m.trace(args, params).id;
  } catch (const TraceBranchError& e) {
    throw runner::InputError(fmt::format("{}/{} cannot be exported: {}", q.name, m.name, e.what()));
  }
  return t;
}

std::string emit(std::span<const TracedMethod> methods, Language lang, std::string_view command) {
  std::string s;
  s += fmt::format("// Generated by `{}`.\n", command);
  s += fmt::format(
      "// {} source, float arithmetic: each function is the method's formula as sglab evaluates it (traced from\n"
      "// core/, not retyped): the same stable forms, its branches as selects (both sides computed, one kept).\n"
      "// Where it was measured against sglab's reference: paper_tables/shader_export.md.\n",
      lang == Language::glsl   ? "GLSL"
      : lang == Language::hlsl ? "HLSL"
                               : "C99");
  std::set<TraceOp> ops;
  for (const auto& m : methods) ops.merge(used_operations(m));
  if (lang == Language::c) {
    s += "#include <math.h>\n#include <stdbool.h>\n";
  } else {
    // sglab_erf calls sglab_erfc, so erfc comes first whenever erf is used.
    if (ops.count(TraceOp::erf)) ops.insert(TraceOp::erfc);
    for (const auto& h : helpers())
      if (ops.count(h.op)) {
        s += '\n';
        s += h.text;
      }
  }
  for (const auto& m : methods) {
    s += '\n';
    s += emit_function(m, lang);
  }
  return s;
}

}  // namespace sglab::shader
