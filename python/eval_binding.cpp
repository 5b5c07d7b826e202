// The evaluation of the native module (module_parts.hpp: eval_numeric, eval_mp50). It reads the
// caller's numpy arrays in place through their strides (broadcast views included: a stride of 0
// costs nothing), a chunk of rows at a time into a small interleaved buffer for the registry's batch
// evaluators, with the GIL released and the chunks spread over the cores by TBB. Bad input, a method
// that throws and a non-finite result are reported for the first offending element in C order,
// whatever the scheduling.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "input_error.hpp"
#include "constant_sets.hpp"
#include "parse_number_mp50.hpp"
#include "sglab/registry_mp50.hpp"
#include "sglab/simd.hpp"
#include "chunk_checks.hpp"
#include "module_parts.hpp"

namespace sglab::python {
namespace {

// ---- evaluation ----------------------------------------------------------------------------

// `m` with the constant sets of `sglab eval --constants` (paths in order, later ones override
// earlier ones, "published" resets); `m` itself (a copy) with none. A bad set is the loader's
// InputError (naming the file and the key), a ValueError in Python.
Method bound_method(const Method& m, const std::vector<std::string>& constants) {
  return bind(m, sglab::frontend::load_constant_sets(constants));
}

// Where an element sits in the broadcast shape: "3" in 1-D, "(2, 5)" otherwise, "()" for 0-d.
std::string index_text(std::size_t flat, const std::vector<py::ssize_t>& shape) {
  if (shape.size() == 1) return std::to_string(flat);
  std::vector<py::ssize_t> idx(shape.size());
  for (std::size_t d = shape.size(); d-- > 0;) {
    idx[d] = py::ssize_t(flat % std::size_t(shape[d]));
    flat /= std::size_t(shape[d]);
  }
  return shape.size() == 1 ? std::to_string(idx[0]) : fmt::format("({})", fmt::join(idx, ", "));
}

// The first thing wrong with a chunk (or with the whole call): which element, and the exception
// Python gets.
struct Failure {
  enum Kind { input, method_threw, not_finite } kind;
  std::size_t index;
  std::string message;  // without the location
  std::optional<std::size_t> column;
};

[[noreturn]] void raise(const Failure& f, const Quantity& q, const Method& m, const std::vector<py::ssize_t>& shape,
                        const std::vector<std::string>& values, std::string_view precision) {
  const std::string where = fmt::format("sglab.eval('{}', '{}')", q.name, m.name);
  std::string text;
  if (f.kind == Failure::input && f.column) {
    text = fmt::format("{}: column '{}', index {}, value {}: {}", where, q.columns[*f.column].name,
                       index_text(f.index, shape), values[*f.column], f.message);
    throw py::value_error(text);
  }
  std::vector<std::string> row;
  for (std::size_t j = 0; j < q.columns.size(); ++j) row.push_back(fmt::format("{} {}", q.columns[j].name, values[j]));
  const std::string at = fmt::format("{}: index {} ({})", where, index_text(f.index, shape), fmt::join(row, ", "));
  switch (f.kind) {
    case Failure::input: throw py::value_error(fmt::format("{}: outside the method's domain: {}", at, f.message));
    case Failure::method_threw:
      throw std::runtime_error(fmt::format("{}: the method failed in {}: {}", at, precision, f.message));
    case Failure::not_finite:
      PyErr_SetString(
          PyExc_FloatingPointError,
          fmt::format("{}: the method returned {} in {}, not a finite number", at, f.message, precision).c_str());
      throw py::error_already_set();
  }
  throw std::logic_error("unreachable");
}

// Rows per chunk: large enough that one batch call and one TBB task per chunk are negligible,
// small enough that the interleaved buffer stays in L1/L2 and both cores get work.
constexpr std::size_t kChunk = 2048;

// Visits the elements [begin, end) of a C-order iteration over `shape`, calling f(flat, offsets)
// with each column's byte offset. Strides are per column (0 on broadcast axes).
template <class F>
void for_each_element(std::size_t begin, std::size_t end, const std::vector<py::ssize_t>& shape,
                      const std::vector<std::vector<py::ssize_t>>& strides, F f) {
  const std::size_t k = strides.size(), nd = shape.size();
  std::vector<py::ssize_t> offset(k, 0);
  if (nd == 0) {
    if (begin < end) f(std::size_t(0), offset);
    return;
  }
  std::vector<py::ssize_t> idx(nd);
  std::size_t rest = begin;
  for (std::size_t d = nd; d-- > 0;) {
    idx[d] = py::ssize_t(rest % std::size_t(shape[d]));
    rest /= std::size_t(shape[d]);
  }
  for (std::size_t j = 0; j < k; ++j)
    for (std::size_t d = 0; d < nd; ++d) offset[j] += idx[d] * strides[j][d];
  for (std::size_t i = begin; i < end; ++i) {
    f(i, offset);
    for (std::size_t d = nd; d-- > 0;) {  // next index, carrying into outer axes
      for (std::size_t j = 0; j < k; ++j) offset[j] += strides[j][d];
      if (++idx[d] < shape[d]) break;
      for (std::size_t j = 0; j < k; ++j) offset[j] -= shape[d] * strides[j][d];
      idx[d] = 0;
    }
  }
}

template <class T>
const BatchFn<T>& batch_of(const Method& m) {
  if constexpr (std::is_same_v<T, float>) return m.batch_float;
  else return m.batch_double;
}

template <class T>
std::string value_text(const T& v) {
  if constexpr (std::is_same_v<T, mp50>) return v.str(round_trip_digits(Precision::mp50));
  else return fmt::format("{}", v);  // shortest text that reads back to the same T
}

// A subnormal input is refused as `sglab eval` refuses its text (parse_number.hpp): it has lost
// precision already, and the methods' 1/λ-like terms overflow on it.
template <class T>
std::optional<std::string> subnormal_error(T v) {
  if (std::fpclassify(v) != FP_SUBNORMAL) return std::nullopt;
  return std::string("is out of the range of ") + (std::is_same_v<T, float> ? "float" : "double") +
         " (too close to zero: subnormal)";
}

// How each column is read: `step` bytes from one element to the next in C order when the column
// is flat (C-contiguous: step = the item size; a broadcast scalar: step = 0), or through its
// strides (step < 0: for_each_element).
struct Layout {
  std::vector<const char*> data;
  std::vector<py::ssize_t> shape;
  std::vector<std::vector<py::ssize_t>> strides;
  std::vector<py::ssize_t> step;
  bool flat = true;  // every column flat: the fast path of run_chunk
};

// The column's step in C order if it is flat, else −1.
py::ssize_t flat_step(const std::vector<py::ssize_t>& shape, const std::vector<py::ssize_t>& strides,
                      py::ssize_t itemsize) {
  if (std::all_of(strides.begin(), strides.end(), [](py::ssize_t s) { return s == 0; })) return 0;
  py::ssize_t expected = itemsize;
  for (std::size_t d = shape.size(); d-- > 0;) {
    if (shape[d] != 1 && strides[d] != expected) return -1;
    expected *= shape[d];
  }
  return itemsize;
}

// Per thread, reused chunk after chunk: no allocation per chunk.
template <class T>
struct ChunkScratch {
  std::vector<T> args;
};

// The per-row checks of a chunk as `sglab eval` applies them (subnormal, then row_error): the
// first failure, or nullopt. `columns_ok`: the column checks are known to pass (column_chunk_ok),
// only the method's domain is left.
template <class T>
std::optional<Failure> check_rows(const Quantity& q, const Method& m, std::size_t begin, std::size_t end,
                                  std::span<const T> args, bool columns_ok) {
  const std::size_t k = q.columns.size();
  thread_local std::vector<double> checked;
  checked.resize(k);
  for (std::size_t i = begin; i < end; ++i) {
    const T* row = args.data() + (i - begin) * k;
    std::optional<Failure> failure;
    for (std::size_t j = 0; j < k; ++j) {
      checked[j] = static_cast<double>(row[j]);
      if (columns_ok) continue;
      if (auto e = subnormal_error(row[j])) failure = Failure{Failure::input, i, std::move(*e), j};
    }
    if (failure) return failure;
    if (columns_ok) {
      if (m.domain_error)
        if (auto e = m.domain_error(checked)) return Failure{Failure::input, i, std::move(*e), std::nullopt};
    } else if (auto e = row_error(q, m, checked)) {
      return Failure{Failure::input, i, std::move(e->message), e->column};
    }
  }
  return std::nullopt;
}

// Rows [begin, begin + len) of K flat columns interleaved into `a` (K values per row), the layout
// the batch evaluators take; K known at compile time, so that the copy vectorizes (a column of
// step 0, a broadcast scalar, repeats its one value).
template <std::size_t K, class T>
void interleave_rows(const Layout& l, std::size_t begin, std::size_t len, T* a) {
  const T* c[K];
  for (std::size_t j = 0; j < K; ++j) c[j] = reinterpret_cast<const T*>(l.data[j]) + (l.step[j] ? begin : 0);
  std::size_t inc[K];
  for (std::size_t j = 0; j < K; ++j) inc[j] = l.step[j] ? 1 : 0;
  bool all_flat = true;
  for (std::size_t j = 0; j < K; ++j) all_flat = all_flat && inc[j] == 1;
  if (all_flat) {
    for (std::size_t r = 0; r < len; ++r)
      for (std::size_t j = 0; j < K; ++j) a[r * K + j] = c[j][r];
  } else {
    for (std::size_t r = 0; r < len; ++r)
      for (std::size_t j = 0; j < K; ++j) a[r * K + j] = c[j][r * inc[j]];
  }
}
template <class T>
void interleave_rows(const Layout& l, std::size_t begin, std::size_t len, T* a) {
  const std::size_t k = l.data.size();
  switch (k) {
    case 2: return interleave_rows<2>(l, begin, len, a);
    case 3: return interleave_rows<3>(l, begin, len, a);
    case 4: return interleave_rows<4>(l, begin, len, a);
    case 5: return interleave_rows<5>(l, begin, len, a);
    case 6: return interleave_rows<6>(l, begin, len, a);
    default:
      for (std::size_t j = 0; j < k; ++j) {
        const T* c = reinterpret_cast<const T*>(l.data[j]);
        for (std::size_t r = 0; r < len; ++r) a[r * k + j] = l.step[j] ? c[begin + r] : c[0];
      }
  }
}

template <class T>
const ColumnsBatchFn<T>& columns_batch_of(const Method& m) {
  if constexpr (std::is_same_v<T, float>) return m.columns_float;
  else return m.columns_double;
}

// Per thread, reused chunk after chunk: a broadcast column (step 0) repeated over a chunk, for the
// column evaluators.
// The most columns a quantity passed to a column evaluator may have (specular: six).
inline constexpr std::size_t kMaxColumns = 8;
template <class T>
struct ColumnScratch {
  std::vector<T> repeated[kMaxColumns];
};

// The chunk's columns for Method::columns_*: flat columns in place, a broadcast one repeated into
// the thread's scratch; false when the quantity has more columns than the scratch holds.
template <class T>
bool chunk_columns(const Layout& l, std::size_t begin, std::size_t len, const T** columns) {
  thread_local ColumnScratch<T> s;
  const std::size_t k = l.data.size();
  if (k > kMaxColumns) return false;
  for (std::size_t j = 0; j < k; ++j) {
    const T* c = reinterpret_cast<const T*>(l.data[j]);
    if (l.step[j]) {
      columns[j] = c + begin;
    } else {
      s.repeated[j].assign(len, c[0]);
      columns[j] = s.repeated[j].data();
    }
  }
  return true;
}

// One chunk: read the rows, check them, evaluate, check every result. Returns the chunk's first
// failure. `batch`: through the method's batch evaluator (one call per chunk: on the columns in
// place when the method has a column evaluator, else on rows interleaved from them); otherwise row
// by row through the scalar definition (Method::eval_*), which `sglab eval` calls.
template <class T>
std::optional<Failure> run_chunk(const Quantity& q, const Method& m, std::size_t begin, std::size_t end,
                                 const Layout& l, bool batch, T* out) {
  const std::size_t k = l.data.size(), len = end - begin;
  thread_local ChunkScratch<T> s;
  std::span<const T> args;
  bool evaluated = false, threw = false;
  // Rows interleaved into the scratch, the layout the batch and scalar evaluators take (one column
  // read in place).
  const auto interleaved = [&] {
    if (l.flat && k == 1 && l.step[0] != 0)
      return std::span<const T>(reinterpret_cast<const T*>(l.data[0]) + begin, len);
    s.args.resize(len * k);
    if (l.flat) interleave_rows(l, begin, len, s.args.data());
    else
      for_each_element(begin, end, l.shape, l.strides, [&](std::size_t i, const std::vector<py::ssize_t>& offset) {
        for (std::size_t j = 0; j < k; ++j)
          s.args[(i - begin) * k + j] = *reinterpret_cast<const T*>(l.data[j] + offset[j]);
      });
    return std::span<const T>(s.args);
  };
  if (l.flat) {
    // Each column checked once per chunk, in one pass over its values.
    bool ok = true;
    thread_local std::vector<double> least;
    least.assign(k, 0.0);
    for (std::size_t j = 0; j < k && ok; ++j) {
      const T* c = reinterpret_cast<const T*>(l.data[j]) + (l.step[j] ? begin : 0);
      ok = column_chunk_ok(q.columns[j], c, l.step[j] ? len : 1, least[j]);
    }
    // A failing chunk, or one of a method with a domain check that its bounds (domain_above) do not
    // settle for the whole chunk, is checked row by row, in order.
    if (!ok || (m.domain_error && !chunk_in_domain_above(m, least))) {
      args = interleaved();
      if (auto f = check_rows<T>(q, m, begin, end, args, ok)) return f;
    }
    const T* columns[kMaxColumns];
    if (batch && columns_batch_of<T>(m) && chunk_columns(l, begin, len, columns)) {
      try {
        columns_batch_of<T>(m)(std::span<const T* const>(columns, k), std::span<T>(out + begin, len));
        evaluated = true;
      } catch (const std::exception&) {
        threw = true;  // row by row below, to name the row that throws
      }
    }
  } else {
    args = interleaved();
    if (auto f = check_rows<T>(q, m, begin, end, args, false)) return f;
  }
  if (!evaluated && args.empty()) args = interleaved();
  if (batch && !evaluated && !threw) {
    try {
      batch_of<T>(m)(args, k, std::span<T>(out + begin, len));
      evaluated = true;
    } catch (const std::exception&) {
      // Row by row below, to name the row that throws.
    }
  }
  if (!evaluated)
    for (std::size_t r = 0; r < len; ++r) {
      try {
        out[begin + r] = method_function<T>(m)(args.subspan(r * k, k));
      } catch (const std::exception& e) {
        return Failure{Failure::method_threw, begin + r, e.what(), std::nullopt};
      }
    }
  if (!all_finite(out + begin, len))
    for (std::size_t r = 0; r < len; ++r)
      if (!is_finite_value(out[begin + r]))
        return Failure{Failure::not_finite, begin + r, value_text(out[begin + r]), std::nullopt};
  return std::nullopt;
}

// The element's inputs as text, for a message (read again with the GIL held).
template <class T>
std::vector<std::string> element_values(std::size_t flat, const std::vector<const char*>& data,
                                        const std::vector<py::ssize_t>& shape,
                                        const std::vector<std::vector<py::ssize_t>>& strides) {
  std::vector<std::string> values(data.size());
  for_each_element(flat, flat + 1, shape, strides, [&](std::size_t, const std::vector<py::ssize_t>& offset) {
    for (std::size_t j = 0; j < data.size(); ++j)
      values[j] = value_text(*reinterpret_cast<const T*>(data[j] + offset[j]));
  });
  return values;
}

}  // namespace

// float32 or float64 arrays of one broadcast shape (the Python side broadcasts and casts) →
// a new C-contiguous array of that shape and dtype. `vectorized`: every method through its batch
// evaluator (the registry's vectorized kernels for simd::vectorized_methods(), which may differ
// from `sglab eval` in the last bits); otherwise those methods row by row through the scalar
// definition, as `sglab eval` (the others' batch evaluator is that definition in a loop: the same
// values, one call per chunk).
template <class T>
py::array_t<T> eval_numeric(const std::string& quantity, const std::string& method,
                            const std::vector<py::array>& columns, const std::vector<std::string>& constants,
                            bool vectorized) {
  const Quantity& q = quantity_named(quantity);
  const Method bound = bound_method(method_named(q, method), constants);
  const Method& m = bound;
  const std::string_view precision = precision_name(std::is_same_v<T, float> ? Precision::float32 : Precision::float64);
  if (!batch_of<T>(m) || !method_function<T>(m))
    throw std::logic_error(
        fmt::format("method '{}' of '{}' has no {} evaluator in the registry", m.name, q.name, precision));
  if (columns.size() != q.columns.size())
    throw py::value_error(
        fmt::format("quantity '{}' takes {} columns, got {}", q.name, q.columns.size(), columns.size()));
  Layout l;
  for (std::size_t j = 0; j < columns.size(); ++j) {
    const py::array& a = columns[j];
    if (!py::isinstance<py::array_t<T>>(a))
      throw py::value_error(fmt::format("column '{}': expected {} values", q.columns[j].name, precision));
    const std::vector<py::ssize_t> s(a.shape(), a.shape() + a.ndim());
    if (j == 0) l.shape = s;
    else if (s != l.shape) throw py::value_error("columns must be broadcast to one shape first");
    l.data.push_back(static_cast<const char*>(a.data()));
    l.strides.emplace_back(a.strides(), a.strides() + a.ndim());
    l.step.push_back(flat_step(l.shape, l.strides.back(), py::ssize_t(sizeof(T))));
    l.flat = l.flat && l.step.back() >= 0;
  }
  const std::string key = q.name + "/" + m.name;
  const auto& simd_methods = simd::vectorized_methods();
  const bool batch = vectorized || std::find(simd_methods.begin(), simd_methods.end(), key) == simd_methods.end();
  py::array_t<T> result(l.shape);
  T* out = result.mutable_data();
  const std::size_t n = std::size_t(result.size());
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<std::optional<Failure>> failures(chunks);
  {
    py::gil_scoped_release release;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const auto& range) {
      for (std::size_t c = range.begin(); c != range.end(); ++c)
        failures[c] = run_chunk<T>(q, m, c * kChunk, std::min(n, (c + 1) * kChunk), l, batch, out);
    });
  }
  for (const auto& f : failures)
    if (f) raise(*f, q, m, l.shape, element_values<T>(f->index, l.data, l.shape, l.strides), precision);
  return result;
}

// mp50: each column a flat list (already broadcast) of decimal strings, parsed at 50 digits by
// `sglab eval`'s parser, or Python floats, taken exactly. Returns the values as 50-digit strings,
// the text `sglab eval --precision mp50` prints.
std::vector<std::string> eval_mp50(const std::string& quantity, const std::string& method,
                                   const std::vector<std::vector<py::object>>& columns,
                                   const std::vector<py::ssize_t>& shape, const std::vector<std::string>& constants) {
  const Quantity& q = quantity_named(quantity);
  const Method bound = bound_method(method_named(q, method), constants);
  const Method& m = bound;
  if (!m.eval_mp50) throw std::logic_error(fmt::format("method '{}' of '{}' has no mp50 evaluator", m.name, q.name));
  if (columns.size() != q.columns.size())
    throw py::value_error(
        fmt::format("quantity '{}' takes {} columns, got {}", q.name, q.columns.size(), columns.size()));
  const std::size_t k = columns.size(), n = k ? columns[0].size() : 0;
  std::vector<mp50> args(n * k);
  std::vector<std::string> text(n * k);
  for (std::size_t j = 0; j < k; ++j) {
    if (columns[j].size() != n) throw py::value_error("columns must be broadcast to one shape first");
    for (std::size_t i = 0; i < n; ++i) {
      const py::object& v = columns[j][i];
      if (py::isinstance<py::str>(v)) {
        text[i * k + j] = "'" + v.cast<std::string>() + "'";
        try {
          args[i * k + j] = runner::parse_decimal<mp50>(v.cast<std::string>());
        } catch (const runner::NumberError& e) {
          throw py::value_error(fmt::format("sglab.eval('{}', '{}'): column '{}', index {}, value {}: {}", q.name,
                                            m.name, q.columns[j].name, index_text(i, shape), text[i * k + j],
                                            e.what()));
        }
      } else {
        const double d = v.cast<double>();
        args[i * k + j] = mp50(d);
        text[i * k + j] = fmt::format("{}", d);
        if (auto e = subnormal_error(d))
          throw py::value_error(fmt::format("sglab.eval('{}', '{}'): column '{}', index {}, value {}: {}", q.name,
                                            m.name, q.columns[j].name, index_text(i, shape), text[i * k + j], *e));
      }
    }
  }
  const auto values_at = [&](std::size_t i) {
    return std::vector<std::string>(text.begin() + std::ptrdiff_t(i * k), text.begin() + std::ptrdiff_t((i + 1) * k));
  };
  std::vector<double> checked(k);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < k; ++j) {
      checked[j] = runner::validation_double(args[i * k + j]);
      if (m.evaluates_in_double && runner::outside_double(args[i * k + j]))
        raise(Failure{Failure::input, i,
                      fmt::format("is outside double's range, and method '{}' evaluates in double", m.name), j},
              q, m, shape, values_at(i), "mp50");
    }
    if (auto e = row_error(q, m, checked))
      raise(Failure{Failure::input, i, e->message, e->column}, q, m, shape, values_at(i), "mp50");
  }
  std::vector<mp50> results(n);
  std::vector<std::optional<std::string>> threw(n);
  {
    py::gil_scoped_release release;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        try {
          results[i] = m.eval_mp50(std::span<const mp50>(args.data() + i * k, k));
        } catch (const std::exception& e) {
          threw[i] = e.what();
        }
      }
    });
  }
  std::vector<std::string> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (threw[i]) raise(Failure{Failure::method_threw, i, *threw[i], std::nullopt}, q, m, shape, values_at(i), "mp50");
    out[i] = value_text(results[i]);
    if (!is_finite_value(results[i]))
      raise(Failure{Failure::not_finite, i, out[i], std::nullopt}, q, m, shape, values_at(i), "mp50");
  }
  return out;
}

template py::array_t<float> eval_numeric<float>(const std::string&, const std::string&, const std::vector<py::array>&,
                                                const std::vector<std::string>&, bool);
template py::array_t<double> eval_numeric<double>(const std::string&, const std::string&, const std::vector<py::array>&,
                                                  const std::vector<std::string>&, bool);

}  // namespace sglab::python
