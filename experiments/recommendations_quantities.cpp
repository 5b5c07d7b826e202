// `sglab recommend`'s sections on the approximated quantities: the clamped cosine, the
// hemispherical integral, the specular lobe (recommendations_detail.hpp).
#include "recommendations_detail.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "csv.hpp"
#include "sglab/registry.hpp"

namespace sglab::experiments::recommendations::detail {

Section diffuse(Tables& tables) {
  return section(
      tables, "Diffuse: the clamped cosine (an SG light on a Lambertian surface)", {"error_vs_time.csv"},
      [&](Section& sec, const Table* evt) {
        const auto all = grid_candidates(*evt, "clamped-cosine", "max_error");
        const auto front = pareto_front(all);
        sec.headline = headline(front, "ns/eval", "max error", 1e-3);
        std::string& b = sec.body;
        b += "Pareto front of max error / D(λ, 1) on error-vs-time's grid against ns per evaluation (double, the "
             "vectorized "
             "batch), published constants:\n\n";
        b += front_text(front, "ns/eval", "max error");
        b += "\nCaveats measured:\n\n" + grid_flaws(*evt, "clamped-cosine");
        // RMSE against max: an ordering the max hides.
        std::map<std::string, double> rmse;
        for (const auto& c : grid_candidates(*evt, "clamped-cosine", "rmse")) rmse[c.name] = c.error;
        for (std::size_t i = 0; i + 1 < front.size(); ++i)
          if (rmse[front[i].name] < rmse[front[i + 1].name])
            b += fmt::format(
                "- RMSE against max: {} has the lower RMSE ({} against {}'s {}) though the larger max error.\n",
                front[i].name, g(rmse[front[i].name]), front[i + 1].name, g(rmse[front[i + 1].name]));
        b += stability_caveats(tables.get("stability.csv"), "clamped-cosine", front);
        if (const Table* nw = tables.get("near_wall_smape.csv")) {
          std::string by_mean, by_max;
          double best_mean = INFINITY, best_max = INFINITY;
          for (const auto& r : nw->csv.rows) {
            const double mean = nw->number(r, "mean_smape"), max = nw->number(r, "max_smape");
            if (mean < best_mean) best_mean = mean, by_mean = nw->text(r, "method");
            if (max < best_max) best_max = max, by_max = nw->text(r, "method");
          }
          b += fmt::format(
              "- Near-wall render (the 2022 poster's figure): lowest mean SMAPE {} ({}), lowest max SMAPE {} ({}){}. "
              "{}\n",
              by_mean, g(best_mean), by_max, g(best_max), by_mean == by_max ? "" : ": mean and max disagree",
              nw->source());
        }
        std::vector<Candidate> by_error = all;
        std::sort(by_error.begin(), by_error.end(),
                  [](const Candidate& x, const Candidate& y) { return x.error < y.error; });
        if (const Table* sw = tables.get("near_wall_smape_sweep.csv"); sw && by_error.size() >= 2 && !front.empty()) {
          // Where the runner-up in max error beats the most accurate method in mean SMAPE over the sweep's cells.
          const std::string a = front.back().name, bname = by_error[by_error[0].name == a ? 1 : 0].name;
          std::map<std::pair<std::string, std::string>, std::map<std::string, double>> cells;
          for (const auto& r : sw->csv.rows)
            cells[{sw->text(r, "sharpness"), sw->text(r, "distance")}][sw->text(r, "method")] = sw->number(
                r, "mean_smape");
          std::set<std::string> sharp;
          int worse = 0, total = 0;
          for (const auto& [cell, m] : cells)
            if (m.count(a) && m.count(bname)) {
              ++total;
              if (m.at(bname) < m.at(a)) ++worse, sharp.insert(cell.first);
            }
          if (total)
            b += fmt::format(
                "- Near-wall sweep (sharpness × distance): {}'s mean SMAPE is above {}'s in {} of {} cells{}. {}\n", a,
                bname, worse, total, sharp.empty() ? "" : fmt::format(" (at sharpness {})", fmt::join(sharp, ", ")),
                sw->source());
        }
      });
}

// ---- hemispherical ---------------------------------------------------------------------------

Section hemispherical(Tables& tables) {
  return section(
      tables, "Hemispherical integral of an SG (the poster's RMSE plot)",
      {"hemispherical_rmse.csv", "error_vs_time.csv"}, [&](Section& sec, const Table* h, const Table* evt) {
        std::map<std::string, std::pair<double, std::string>> worst;  // method → (max RMSE, λ)
        for (const auto& r : h->csv.rows) {
          auto& w = worst.try_emplace(h->text(r, "method"), -1.0, "").first->second;
          if (const double v = h->number(r, "rmse_normalized"); v > w.first) w = {v, h->text(r, "lambda")};
        }
        std::vector<Candidate> all;
        for (const auto& c : grid_candidates(*evt, "clamped-cosine", "max_error"))
          if (worst.count(c.name)) all.push_back({c.name, c.cost, worst[c.name].first});
        const auto front = pareto_front(all);
        sec.headline = headline(front, "ns/eval", "max normalized RMSE", 1e-3);
        sec.body =
            "Pareto front of the largest normalized RMSE over λ against the method's ns per evaluation (error-vs-time, "
            "double):\n\n" +
            front_text(front, "ns/eval", "max normalized RMSE") + "\nWhere each method is worst:\n\n";
        for (const auto& [m, w] : worst)
          sec.body += fmt::format("- {}: {} at λ = {:.3g}.\n", m, g(w.first), std::strtod(w.second.c_str(), nullptr));
      });
}

// ---- specular ----------------------------------------------------------------------------------

Section specular(Tables& tables) {
  return section(
      tables, "Specular: an SG light on GGX", {"specular_vs_roughness.csv", "error_vs_time.csv"},
      [&](Section& sec, const Table* sv, const Table* evt) {
        std::map<std::string, const runner::CsvRecord*> overall;
        for (const auto& r : sv->csv.rows)
          if (sv->text(r, "by") == "all") overall[sv->text(r, "method")] = &r;
        std::vector<Candidate> all;
        for (const auto& c : grid_candidates(*evt, "specular", "max_error"))
          if (overall.count(c.name)) all.push_back({c.name, c.cost, sv->number(*overall[c.name], "weighted_error")});
        const auto front = pareto_front(all);
        sec.headline = headline(front, "ns/eval", "brightness-weighted error", 0.1);
        std::string& b = sec.body;
        b += "Pareto front of the brightness-weighted relative error over the whole roughness sweep against ns per "
             "evaluation "
             "(error-vs-time, double):\n\n" +
             front_text(front, "ns/eval", "brightness-weighted error") + "\nCaveats measured:\n\n";
        for (const auto& c : front) {
          const auto& r = *overall[c.name];
          b += fmt::format(
              "- {}: max relative error {} and SMAPE {} over the sweep; worst at roughness {}, light sharpness {}, "
              "view cos "
              "{}, "
              "light {}; on error-vs-time's grid max error {}.\n",
              c.name, g(sv->number(r, "max_relative")), g(sv->number(r, "smape")), g(sv->number(r, "worst_roughness")),
              sv->text(r, "worst_light_sharpness"), sv->text(r, "worst_view_cos"), sv->text(r, "worst_position"),
              g(named(grid_candidates(*evt, "specular", "max_error"), c.name)->error));
        }
        // Roughnesses where the recommended method is not the best one.
        if (!front.empty()) {
          const std::string best = front.back().name;
          std::map<std::string, std::pair<double, std::string>> leader;  // roughness → (lowest weighted error, method)
          std::map<std::string, double> best_error;
          for (const auto& r : sv->csv.rows) {
            if (sv->text(r, "by") != "roughness") continue;
            const double e = sv->number(r, "weighted_error");
            auto& l = leader.try_emplace(sv->text(r, "group"), INFINITY, "").first->second;
            if (e < l.first) l = {e, sv->text(r, "method")};
            if (sv->text(r, "method") == best) best_error[sv->text(r, "group")] = e;
          }
          for (const auto& [roughness, l] : leader)
            if (l.second != best && best_error.count(roughness))
              b += fmt::format("- At roughness {}: {} is ahead ({} against {}'s {}).\n",
                               g(std::strtod(roughness.c_str(), nullptr)), l.second, g(l.first), best,
                               g(best_error[roughness]));
        }
        b += grid_flaws(*evt, "specular");
      });
}

}  // namespace sglab::experiments::recommendations::detail
