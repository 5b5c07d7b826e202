#include "fit_record.hpp"

#include "record.hpp"
#include "sglab/registry.hpp"

namespace sglab::frontend {

Judgement judge(const fit::Fitter& f, const fit::FitResult& r) {
  Judgement j;
  for (const auto& u : fit::registry_parameters(f)) {
    const auto slash = u.user.find('/');
    if (slash == std::string::npos) continue;
    const Quantity* q = find_quantity(u.user.substr(0, slash));
    const Method* m = q ? q->find(u.user.substr(slash + 1)) : nullptr;
    if (!m || q->reference_method.empty() || q->columns.size() != 2) continue;
    ConstantSet set;
    for (const auto& p : r.parameters) set.set({r.fit, p.name, p.value, "this fit"});
    j.method = u.user;
    j.published = fit::standard_grid_error(*q, *m);
    j.fitted = fit::standard_grid_error(*q, bind(*m, set));
    break;
  }
  return j;
}

nlohmann::ordered_json fit_record_json(const fit::FitResult& r, const Judgement& jd, const std::string& precision) {
  nlohmann::ordered_json j = fit::record_json(r);
  j["precision"] = precision;
  if (!jd.method.empty()) {
    j["fit::standard_grid_error"] = {
        {"method", jd.method},
        {"grid",
         "sglab error-vs-time grid (full), double, |method - reference| / reference at c = 1; published = the "
         "method's own published constants (sglab eval --list)"},
        {"published", {{"max", jd.published.max_error}, {"rms", jd.published.rms_error}}},
        {"fit", {{"max", jd.fitted.max_error}, {"rms", jd.fitted.rms_error}}}};
  }
  return j;
}

}  // namespace sglab::frontend
