#include "record.hpp"

#include <cmath>

namespace sglab::fit {

FitOptions checked_options(const Fitter& f, const std::string& objective, const std::string& precision) {
  FitOptions o;
  o.objective = choose_objective(f, objective);
  o.precision = precision;
  unit_roundoff(o.precision);  // validates the name
  return o;
}

nlohmann::ordered_json record_json(const FitResult& r) {
  nlohmann::ordered_json j;
  auto obj = [](const std::vector<NamedValue>& v) {
    nlohmann::ordered_json o = nlohmann::ordered_json::object();
    for (const auto& nv : v) {
      if (std::isfinite(nv.value)) o[nv.name] = nv.value;
      else o[nv.name] = nullptr;
    }
    return o;
  };
  j["fit"] = r.fit;
  j["objective"] = r.objective;
  j["domain"] = r.domain;
  j["parameters"] = obj(r.parameters);
  j["published"] = obj(r.published);
  j["relative_difference"] = obj(r.relative_difference);
  j["final_cost"] = r.final_cost;
  j["iterations"] = r.iterations;
  j["converged"] = r.converged;
  j["seconds"] = r.seconds;
  auto number_or_null = [](double v) {
    return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
  };
  j["objective_at_published"] = number_or_null(r.published_cost);
  j["objective_at_fit"] = r.final_cost;
  j["singular_values"] = r.singular_values;
  nlohmann::ordered_json range = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < r.cost_range.size(); ++i)
    range[r.parameters[i].name] = {r.cost_range[i].first, r.cost_range[i].second};
  j["cost_range_1pct"] = range;
  return j;
}

}  // namespace sglab::fit
