// A scalar type that records the operations of a formula instead of computing them (as a
// ceres::Jet carries derivatives along): instantiating a method's template on `Trace` yields an
// expression graph of the formula itself — the same stable forms, the same branches — from which
// `sglab export` writes GLSL, HLSL and C (docs/export.md). One formula, many evaluators.
//
// The graph is recorded for float: the target precision of the exported code. Literals are kept
// as the float T(x) gives, epsilon<Trace>() is float's, and every node that depends on no input
// (a literal, a constant of the method, or arithmetic on them) carries its value computed in
// float exactly as sglab's float evaluation computes it.
//
// Value-dependent branches: a comparison of traced values gives a TraceBool. Branching on it with
// `if` works only when it depends on no input (a branch on a constant is decided while tracing);
// otherwise it throws TraceBranchError, and the method is not exportable until that branch is
// written as a select (scalar.hpp: select(cond, if_true, if_false)), which records both sides.
// Series summed until the term falls below ε (series_converged) sum a fixed kTraceSeriesTerms
// terms when traced.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "sglab/eigen_scalar.hpp"
#include "sglab/scalar.hpp"

namespace sglab {

enum class TraceOp : std::uint8_t {
  input,
  param,
  literal,  // leaves
  neg,
  exp,
  expm1,
  log,
  log1p,
  sqrt,
  erf,
  erfc,
  abs,  // unary
  sin,
  cos,  // unary (the specular light axis's azimuth)
  add,
  sub,
  mul,
  div,  // binary arithmetic
  lt,
  le,
  gt,
  ge,  // comparisons (give booleans)
  not_,
  and_,
  or_,    // boolean logic
  select  // a ? b : c (a boolean)
};

struct TraceNode {
  TraceOp op = TraceOp::literal;
  int a = -1, b = -1, c = -1;  // operands (node ids, all smaller than this node's)
  int index = -1;              // the input's or parameter's position
  bool varying = false;        // depends on an input
  float value = 0;             // when !varying: the value in float (booleans: 0 or 1)
};

// One operation applied to float values (booleans as 0/1): the trace's constant folding and its
// interpreter use this one definition, with the same library functions as sglab's float path.
inline float trace_apply(TraceOp op, float a, float b, float c) {
  switch (op) {
    case TraceOp::neg: return -a;
    case TraceOp::exp: return std::exp(a);
    case TraceOp::expm1: return std::expm1(a);
    case TraceOp::log: return std::log(a);
    case TraceOp::log1p: return std::log1p(a);
    case TraceOp::sqrt: return std::sqrt(a);
    case TraceOp::erf: return std::erf(a);
    case TraceOp::erfc: return std::erfc(a);
    case TraceOp::abs: return std::abs(a);
    case TraceOp::sin: return std::sin(a);
    case TraceOp::cos: return std::cos(a);
    case TraceOp::add: return a + b;
    case TraceOp::sub: return a - b;
    case TraceOp::mul: return a * b;
    case TraceOp::div: return a / b;
    case TraceOp::lt: return a < b ? 1.f : 0.f;
    case TraceOp::le: return a <= b ? 1.f : 0.f;
    case TraceOp::gt: return a > b ? 1.f : 0.f;
    case TraceOp::ge: return a >= b ? 1.f : 0.f;
    case TraceOp::not_: return a != 0 ? 0.f : 1.f;
    case TraceOp::and_: return (a != 0 && b != 0) ? 1.f : 0.f;
    case TraceOp::or_: return (a != 0 || b != 0) ? 1.f : 0.f;
    case TraceOp::select: return a != 0 ? b : c;
    default: return a;  // leaves carry their value
  }
}

// The recorded graph. Identical nodes are recorded once (hash-consing), so a value the formula
// computes twice (e^{−λ} in two helpers) is one node: common subexpressions come for free.
class TraceGraph {
 public:
  std::vector<TraceNode> nodes;

  int add(TraceNode n) {
    if (n.op != TraceOp::input && n.op != TraceOp::param && n.op != TraceOp::literal) {
      n.varying = false;
      for (int o : {n.a, n.b, n.c})
        if (o >= 0) n.varying = n.varying || nodes[o].varying;
      if (!n.varying) n.value = trace_apply(n.op, value(n.a), value(n.b), value(n.c));
    }
    const Key k = key(n);
    if (auto it = index_.find(k); it != index_.end()) return it->second;
    nodes.push_back(n);
    index_.emplace(k, int(nodes.size()) - 1);
    return int(nodes.size()) - 1;
  }

  // The formula's value for one row of inputs (parameters as recorded), in float.
  float evaluate(int output, const float* inputs) const {
    std::vector<float> v(std::size_t(output) + 1);
    for (int i = 0; i <= output; ++i) {
      const TraceNode& n = nodes[i];
      if (!n.varying) v[i] = n.value;
      else if (n.op == TraceOp::input) v[i] = inputs[n.index];
      else v[i] = trace_apply(n.op, v[n.a], n.b >= 0 ? v[n.b] : 0.f, n.c >= 0 ? v[n.c] : 0.f);
    }
    return v[output];
  }

 private:
  float value(int id) const { return id >= 0 ? nodes[id].value : 0.f; }
  struct Key {
    TraceOp op;
    int a, b, c, index;
    std::uint32_t bits;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::size_t h = std::size_t(k.op);
      for (std::size_t v :
           {std::size_t(k.a), std::size_t(k.b), std::size_t(k.c), std::size_t(k.index), std::size_t(k.bits)})
        h = h * 1000003u ^ v;
      return h;
    }
  };
  static Key key(const TraceNode& n) {
    std::uint32_t bits = 0;
    if (n.op == TraceOp::literal) std::memcpy(&bits, &n.value, sizeof bits);
    // A parameter is identified by its position alone; a literal by its bits (0 and −0 differ).
    return {n.op, n.a, n.b, n.c, n.index, bits};
  }
  std::unordered_map<Key, int, KeyHash> index_;
};

// The graph the Trace values of this thread record into (set by TraceRecording).
inline thread_local TraceGraph* active_trace_graph = nullptr;

// Records every Trace operation of this thread into `g` while alive.
class TraceRecording {
 public:
  explicit TraceRecording(TraceGraph& g) : previous_(active_trace_graph) { active_trace_graph = &g; }
  ~TraceRecording() { active_trace_graph = previous_; }
  TraceRecording(const TraceRecording&) = delete;
  TraceRecording& operator=(const TraceRecording&) = delete;

 private:
  TraceGraph* previous_;
};

// A branch on a value that depends on an input: the formula has to say it as a select.
struct TraceBranchError : std::logic_error {
  using std::logic_error::logic_error;
};

inline TraceGraph& trace_graph() {
  if (!active_trace_graph) throw std::logic_error("Trace used outside a TraceRecording");
  return *active_trace_graph;
}

struct Trace {
  int id;

  Trace() : Trace(0.f) {}
  template <class A, std::enable_if_t<std::is_arithmetic_v<A> && !std::is_same_v<A, bool>, int> = 0>
  Trace(A v) {  // NOLINT: implicit, as a float literal converts to float
    TraceNode n;
    n.op = TraceOp::literal;
    n.value = static_cast<float>(v);
    id = trace_graph().add(n);
  }
  static Trace node(TraceOp op, int a, int b = -1, int c = -1) {
    TraceNode n;
    n.op = op;
    n.a = a;
    n.b = b;
    n.c = c;
    Trace t(0.f);
    t.id = trace_graph().add(n);
    return t;
  }
  static Trace input(int index) { return leaf(TraceOp::input, index, 0.f); }
  static Trace parameter(int index, float value) { return leaf(TraceOp::param, index, value); }

  Trace& operator+=(const Trace& o) { return *this = node(TraceOp::add, id, o.id); }
  Trace& operator-=(const Trace& o) { return *this = node(TraceOp::sub, id, o.id); }
  Trace& operator*=(const Trace& o) { return *this = node(TraceOp::mul, id, o.id); }
  Trace& operator/=(const Trace& o) { return *this = node(TraceOp::div, id, o.id); }

 private:
  static Trace leaf(TraceOp op, int index, float value) {
    TraceNode n;
    n.op = op;
    n.index = index;
    n.value = value;
    n.varying = op == TraceOp::input;
    Trace t(0.f);
    t.id = trace_graph().add(n);
    return t;
  }
};

// A traced comparison. Converting it to bool (an `if` on it) is allowed only when it depends on
// no input; see the header comment.
struct TraceBool {
  int id;
  bool varying() const { return trace_graph().nodes[id].varying; }
  explicit operator bool() const {
    const TraceNode& n = trace_graph().nodes[id];
    if (n.varying) throw TraceBranchError("a branch on a value that depends on an input (it needs a select)");
    return n.value != 0;
  }
};

inline Trace operator-(const Trace& a) { return Trace::node(TraceOp::neg, a.id); }
inline Trace operator+(const Trace& a) { return a; }
inline Trace operator+(const Trace& a, const Trace& b) { return Trace::node(TraceOp::add, a.id, b.id); }
inline Trace operator-(const Trace& a, const Trace& b) { return Trace::node(TraceOp::sub, a.id, b.id); }
inline Trace operator*(const Trace& a, const Trace& b) { return Trace::node(TraceOp::mul, a.id, b.id); }
inline Trace operator/(const Trace& a, const Trace& b) { return Trace::node(TraceOp::div, a.id, b.id); }
inline TraceBool operator<(const Trace& a, const Trace& b) { return {Trace::node(TraceOp::lt, a.id, b.id).id}; }
inline TraceBool operator<=(const Trace& a, const Trace& b) { return {Trace::node(TraceOp::le, a.id, b.id).id}; }
inline TraceBool operator>(const Trace& a, const Trace& b) { return {Trace::node(TraceOp::gt, a.id, b.id).id}; }
inline TraceBool operator>=(const Trace& a, const Trace& b) { return {Trace::node(TraceOp::ge, a.id, b.id).id}; }
inline TraceBool operator!(const TraceBool& a) { return {Trace::node(TraceOp::not_, a.id).id}; }
inline TraceBool operator&&(const TraceBool& a, const TraceBool& b) {
  return {Trace::node(TraceOp::and_, a.id, b.id).id};
}
inline TraceBool operator||(const TraceBool& a, const TraceBool& b) {
  return {Trace::node(TraceOp::or_, a.id, b.id).id};
}

inline Trace exp(const Trace& x) { return Trace::node(TraceOp::exp, x.id); }
inline Trace expm1(const Trace& x) { return Trace::node(TraceOp::expm1, x.id); }
inline Trace log(const Trace& x) { return Trace::node(TraceOp::log, x.id); }
inline Trace log1p(const Trace& x) { return Trace::node(TraceOp::log1p, x.id); }
inline Trace sqrt(const Trace& x) { return Trace::node(TraceOp::sqrt, x.id); }
inline Trace erf(const Trace& x) { return Trace::node(TraceOp::erf, x.id); }
inline Trace erfc(const Trace& x) { return Trace::node(TraceOp::erfc, x.id); }
inline Trace abs(const Trace& x) { return Trace::node(TraceOp::abs, x.id); }
inline Trace sin(const Trace& x) { return Trace::node(TraceOp::sin, x.id); }
inline Trace cos(const Trace& x) { return Trace::node(TraceOp::cos, x.id); }

// value_of(x) of a Trace is the Trace itself (comparisons then record); its number type is float,
// the precision the trace is recorded for.
template <>
struct scalar_traits<Trace> {
  using value_type = float;
  static const Trace& value(const Trace& x) { return x; }
};

// select on a traced condition: both sides are recorded and a select node joins them (a side
// that is a std::array joins element by element). A condition that depends on no input is
// decided now, and only its side is recorded.
template <class F, class G>
auto select(const TraceBool& cond, F&& if_true, G&& if_false) -> decltype(if_true()) {
  using R = decltype(if_true());
  if (!cond.varying()) return static_cast<bool>(cond) ? R(if_true()) : R(if_false());
  const R a = if_true();
  const R b = if_false();
  if constexpr (std::is_same_v<R, Trace>) {
    return Trace::node(TraceOp::select, cond.id, a.id, b.id);
  } else {
    R out;
    for (std::size_t i = 0; i < static_cast<std::size_t>(out.size()); ++i)
      out[i] = Trace::node(TraceOp::select, cond.id, a[i].id, b[i].id);
    return out;
  }
}

// std::max and std::min for traced values, as selects with std::max's and std::min's comparisons
// ((a < b) ? b : a and (b < a) ? b : a): a formula's `using std::max; max(x, y)` finds these by
// argument-dependent lookup (non-templates, preferred to std::max<Trace>, whose `<` would be a
// branch on the inputs) and records the same choice sglab's float path makes.
inline Trace max(const Trace& a, const Trace& b) {
  return select(
      a < b, [&] { return b; }, [&] { return a; });
}
inline Trace min(const Trace& a, const Trace& b) {
  return select(
      b < a, [&] { return b; }, [&] { return a; });
}

// Terms a traced series sums (series_converged). Every series in core is in powers of |x| ≤ 1
// with factorial denominators, at most n·|x|^(n−1)/(n+1)!: the first term left out, 13/14! =
// 1.5e-10, is below float's ε times the smallest of their sums (0.26, the c = −1 series at λ = 1).
inline constexpr int kTraceSeriesTerms = 12;

// A traced series stops after kTraceSeriesTerms terms (a series of constants at the float
// rule, term ≤ ε·sum, as sglab's float path).
inline bool series_converged(const Trace& term, const Trace& sum, int n) {
  const auto& nodes = trace_graph().nodes;
  if (!nodes[term.id].varying && !nodes[sum.id].varying)
    return std::abs(nodes[term.id].value) <= std::numeric_limits<float>::epsilon() * std::abs(nodes[sum.id].value);
  return n >= kTraceSeriesTerms;
}

}  // namespace sglab

// Eigen vectors of traced values (Vec3<Trace>: the specular methods' axes and directions), at
// float's costs (eigen_scalar.hpp), in the same order for Trace as for float.
namespace Eigen {
template <>
struct NumTraits<sglab::Trace> : sglab::ScalarNumTraits<sglab::Trace, float> {};
}  // namespace Eigen
