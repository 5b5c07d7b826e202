// The registry glue: precision names, column validation, lookups, and the list of modules that
// register quantities.
#include "sglab/registry.hpp"

#include "sglab/brdf.hpp"
#include "sglab/enum_names.hpp"
#include "sglab/filtering_weights.hpp"

#include <cmath>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace sglab {

// Specular reflection off the Gaussian-angle NDF BRDF of Wang et al. 2009 (registry_gaussian_ndf.cpp,
// docs/math.md §5); declared here rather than in registry.hpp, which every command includes.
void register_gaussian_ndf_quantities(std::vector<Quantity>& out);

namespace {
constexpr EnumName<Precision> kPrecisionNames[] = {
    {Precision::float32, "float"}, {Precision::float64, "double"}, {Precision::mp50, "mp50"}};
constexpr EnumName<ColumnKind> kColumnKindNames[] = {
    {ColumnKind::sharpness, "sharpness"},        {ColumnKind::cosine, "cosine"},
    {ColumnKind::mean_length, "mean_length"},    {ColumnKind::positive, "positive"},
    {ColumnKind::nonnegative, "nonnegative"},    {ColumnKind::angle, "angle"},
    {ColumnKind::unit_interval, "unit_interval"}};
constexpr EnumName<BatchPath> kBatchPathNames[] = {{BatchPath::scalar, "scalar"},
                                                   {BatchPath::vectorized, "vectorized"}};
}  // namespace

std::string_view precision_name(Precision p) { return enum_name(kPrecisionNames, p); }

std::string_view batch_path_name(BatchPath path) { return enum_name(kBatchPathNames, path); }

std::optional<Precision> parse_precision(std::string_view name) { return parse_enum(kPrecisionNames, name); }

int round_trip_digits(Precision p) {
  switch (p) {
    case Precision::float32: return 9;   // FLT_DECIMAL_DIG
    case Precision::float64: return 17;  // DBL_DECIMAL_DIG
    case Precision::mp50: return 50;     // cpp_bin_float_50 carries 50 decimal digits
  }
  return 17;
}

const Method* Quantity::find(std::string_view method_name) const {
  for (const auto& m : methods)
    if (m.name == method_name) return &m;
  return nullptr;
}

const std::vector<Quantity>& quantities() {
  static const std::vector<Quantity> all = [] {
    std::vector<Quantity> out;
    register_core_quantities(out);
    register_glossy_quantities(out);
    register_gaussian_ndf_quantities(out);
    register_stiff_quantities(out);
    install_simd_batch_evaluators(out);
    return out;
  }();
  return all;
}

const Quantity* find_quantity(std::string_view name) {
  for (const auto& q : quantities())
    if (q.name == name) return &q;
  return nullptr;
}

double reference_value(const Quantity& q, std::span<const double> args) {
  const Method* ref = q.reference_method.empty() ? nullptr : q.find(q.reference_method);
  if (!ref || !ref->parameters.empty())
    throw std::invalid_argument("reference_value: quantity '" + q.name + "' has no reference method without constants");
  // Key: the quantity's name, then the arguments' bytes (exact doubles: equal keys, equal rows).
  std::string key = q.name;
  key.push_back('\0');
  key.append(reinterpret_cast<const char*>(args.data()), args.size_bytes());
  static std::mutex mutex;
  static std::unordered_map<std::string, double> kept;
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (const auto it = kept.find(key); it != kept.end()) return it->second;
  }
  // Evaluated outside the lock (grids fill in parallel); two threads on one row store one value.
  const double v = ref->eval_double(args);
  std::lock_guard<std::mutex> lock(mutex);
  kept.emplace(std::move(key), v);
  return v;
}

std::optional<std::string> column_value_error(const Column& column, double v) {
  auto fmt = [](double x) {
    std::ostringstream s;
    s.precision(17);
    s << x;
    return s.str();
  };
  if (!std::isfinite(v)) return "must be a finite number, got " + fmt(v);
  switch (column.kind) {
    case ColumnKind::sharpness:
      if (v < 0) return "a sharpness must be >= 0, got " + fmt(v);
      break;
    case ColumnKind::cosine:
      if (std::fabs(v) > 1 + kCosineSlack)
        return "a cosine must lie in [-1, 1] (up to 1e-6 of rounding), got " + fmt(v);
      break;
    case ColumnKind::mean_length:
    case ColumnKind::unit_interval:
      if (v < 0 || v > 1) return "must lie in [0, 1], got " + fmt(v);
      break;
    case ColumnKind::positive:
      if (!(v > 0)) return "must be > 0, got " + fmt(v);
      break;
    case ColumnKind::nonnegative:
      if (v < 0) return "must be >= 0, got " + fmt(v);
      break;
    case ColumnKind::angle: break;
  }
  return std::nullopt;
}

std::string_view column_kind_name(ColumnKind kind) { return enum_name(kColumnKindNames, kind); }

std::vector<Parameter> fit_parameters(const std::string& fit, const std::string& source,
                                      const std::vector<FitConstant>& constants) {
  std::vector<Parameter> out;
  for (const FitConstant& c : constants) out.push_back({c.name, fit, c.published, source, c.kind});
  return out;
}

Domain Domain::above(std::vector<std::pair<std::size_t, double>> bounds, std::string message) {
  Domain d;
  d.bounds = bounds;
  d.error = [bounds = std::move(bounds),
             message = std::move(message)](std::span<const double> row) -> std::optional<std::string> {
    for (const auto& [column, bound] : bounds)
      if (!(row[column] > bound)) return message;
    return std::nullopt;
  };
  return d;
}

std::optional<RowError> row_error(const Quantity& q, const Method& m, std::span<const double> row) {
  for (std::size_t j = 0; j < q.columns.size(); ++j)
    if (auto error = column_value_error(q.columns[j], row[j])) return RowError{j, std::move(*error)};
  if (m.domain_error)
    if (auto error = m.domain_error(row)) return RowError{std::nullopt, std::move(*error)};
  return std::nullopt;
}

void ConstantSet::set(ConstantValue v) {
  for (auto& old : values)
    if (old.fit == v.fit && old.name == v.name) {
      old = std::move(v);
      return;
    }
  values.push_back(std::move(v));
}

const ConstantValue* ConstantSet::find(std::string_view fit, std::string_view name) const {
  for (const auto& v : values)
    if (v.fit == fit && v.name == name) return &v;
  return nullptr;
}

double ConstantSet::value(const Parameter& p) const {
  const ConstantValue* v = p.fit.empty() ? nullptr : find(p.fit, p.name);
  return v ? v->value : p.published;
}

Method bind(const Method& m, const ConstantSet& set) {
  if (m.parameters.empty() || !m.bind) return m;
  std::vector<double> values;
  bool changed = false;
  for (const auto& p : m.parameters) {
    values.push_back(set.value(p));
    changed = changed || set.find(p.fit, p.name) != nullptr;
  }
  if (!changed) return m;
  return m.bind(values);
}

namespace {
struct Standalone {
  std::string user;
  Parameter parameter;
};
const std::vector<Standalone>& standalone_constants() {
  static const std::vector<Standalone> all{
      {"render",
       {"lambda_d", "lambda-d", LambertSharpness::papers,
        "Tokuyoshi 2015 (two-VSGL poster) and 2016: λ_d ≈ 2, the diffuse VSGL's vMF sharpness "
        "(the public VSGL code's 2.292504 is the L2 fit, `sglab fit lambda-d`)",
        ColumnKind::positive}},
      {"filter",
       {"lambda_c", "lambda-c", LobeAwareFiltering::lambda_c,
        "Tokuyoshi, lobe-aware filtering, App. D (diffuse lobe similarity)", ColumnKind::positive}},
  };
  return all;
}
}  // namespace

std::vector<ConstantUse> constant_uses() {
  std::vector<ConstantUse> out;
  for (const auto& q : quantities())
    for (const auto& m : q.methods)
      for (const auto& p : m.parameters) out.push_back({q.name + "/" + m.name, &p});
  for (const auto& s : standalone_constants()) out.push_back({s.user, &s.parameter});
  return out;
}

const Parameter* find_standalone_constant(std::string_view user, std::string_view name) {
  for (const auto& s : standalone_constants())
    if (s.user == user && s.parameter.name == name) return &s.parameter;
  return nullptr;
}

}  // namespace sglab
