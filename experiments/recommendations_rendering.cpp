// `sglab recommend`'s sections on the renderer's choices: the VSGL mode, the filtering weights, the
// environment's SG mixture fit, the denoising filter (recommendations_detail.hpp).
#include "recommendations_detail.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "csv.hpp"

namespace sglab::experiments::recommendations::detail {

// ---- VSGL mode -----------------------------------------------------------------------------------

Section vsgl(Tables& tables) {
  return section(
      tables, "Indirect light: the VSGL mode", {"vsgl_error_vs_count.csv"}, [&](Section& sec, const Table* t) {
        std::vector<Candidate> all;
        for (const auto& r : t->csv.rows)
          all.push_back({t->text(r, "vsgl"), t->number(r, "seconds_vsgl") + t->number(r, "seconds_shading"),
                         t->number(r, "relative_l2")});
        const auto front = pareto_front(all);
        sec.headline = headline(front, "s (build + shading)", "relative L2", 0.5);
        std::string& b = sec.body;
        b +=
            "Pareto front of the indirect light's relative L2 against the exact VPL sum on cornell-glossy, against the "
            "seconds "
            "to build and shade the VSGLs (the sum of the table's two columns):\n\n" +
            front_text(front, "s (build + shading)", "relative L2") + "\nCaveats measured:\n\n";
        if (const Table* rd = tables.get("vsgl_error_vs_roughness_distance.csv")) {
          std::map<std::string, std::tuple<double, std::string, std::string>> worst;
          for (const auto& r : rd->csv.rows) {
            auto& w = worst.try_emplace(rd->text(r, "vsgl"), -1.0, "", "").first->second;
            if (const double e = rd->number(r, "relative_l2"); e > std::get<0>(w))
              w = {e, rd->text(r, "floor.roughness"), rd->text(r, "light.distance")};
          }
          for (const auto& [m, w] : worst)
            b += fmt::format("- {}: worst relative L2 {} at floor roughness {}, light distance {} ({}).\n", m,
                             g(std::get<0>(w)), std::get<1>(w), std::get<2>(w), rd->file);
        }
        const Table* off = tables.get("vsgl_visibility_off.csv");
        const Table* on = tables.get("vsgl_visibility_on.csv");
        if (off && on)
          for (const auto& r : off->csv.rows)
            for (const auto& q : on->csv.rows)
              if (off->text(r, "vsgl") == on->text(q, "vsgl"))
                b += fmt::format("- {} with the 2016 visibility: relative L2 {} → {} (SMAPE {} → {}).\n",
                                 off->text(r, "vsgl"), g(off->number(r, "relative_l2")),
                                 g(on->number(q, "relative_l2")), g(off->number(r, "smape")),
                                 g(on->number(q, "smape")));
      });
}

// ---- filtering weights ---------------------------------------------------------------------------

Section filtering(Tables& tables) {
  return section(tables, "Upsampling: the filtering weights", {"filtering.csv"}, [&](Section& sec, const Table* t) {
    struct Acc {
      double sum = 0, glossy = 0, worst = -1;
      int n = 0;
      std::string at;
    };
    std::map<std::string, Acc> acc;
    for (const auto& r : t->csv.rows) {
      Acc& a = acc[t->text(r, "weights")];
      const double e = t->number(r, "relative_l2");
      a.sum += e;
      a.glossy += t->number(r, "glossy_relative_l2");
      ++a.n;
      if (e > a.worst)
        a.worst = e, a.at = "scale " + t->text(r, "scale") + ", floor roughness " + t->text(r, "floor_roughness");
    }
    std::vector<std::pair<double, std::string>> ranked;
    for (const auto& [w, a] : acc) ranked.push_back({a.sum / a.n, w});
    std::sort(ranked.begin(), ranked.end());
    if (!ranked.empty())
      sec.headline = fmt::format("**{}** (lowest mean relative L2 over the sweep, {}; the table measures no cost)",
                                 ranked.front().second, g(ranked.front().first));
    std::string& b = sec.body;
    b += "The table times no weighting, so there is no cost axis: the weightings ranked by their mean relative L2 over "
         "every "
         "scale × floor roughness of the sweep, with the glossy pixels' mean and the worst row:\n\n"
         "| weights | mean relative L2 | mean glossy relative L2 | worst relative L2 | at |\n|---|---|---|---|---|\n";
    for (const auto& [mean, w] : ranked) {
      const Acc& a = acc[w];
      b += fmt::format("| {} | {} | {} | {} | {} |\n", w, g(mean), g(a.glossy / a.n), g(a.worst), a.at);
    }
  });
}

// ---- environment: SG mixture fit ----------------------------------------------------------------

Section environment(Tables& tables) {
  return section(
      tables, "Environment lighting: the SG mixture fit", {"envmap_lobes.csv"}, [&](Section& sec, const Table* t) {
        // One fit per (environment, lobe count): the table repeats it on every shading row.
        std::map<std::pair<std::string, std::string>, const runner::CsvRecord*> fits;
        for (const auto& r : t->csv.rows) fits.emplace(std::pair{t->text(r, "environment"), t->text(r, "lobes")}, &r);
        std::map<std::string, std::pair<Candidate, int>> acc;  // "ceres N" → sums over environments
        for (const auto& [key, r] : fits)
          for (const auto& [method, prefix] : {std::pair{"ceres", "ceres"}, std::pair{"vmf-em", "vmf_em"}}) {
            auto& [c, n] = acc[fmt::format("{}, N = {}", method, key.second)];
            c.cost += t->number(*r, std::string(prefix) + "_seconds");
            c.error += t->number(*r, std::string(prefix) + "_relative_error");
            ++n;
          }
        std::vector<Candidate> all;
        for (auto [name, cn] : acc) all.push_back({name, cn.first.cost / cn.second, cn.first.error / cn.second});
        const auto front = pareto_front(all);
        sec.headline = headline(front, "s (fit)", "mean fit error", 0.1);
        sec.body =
            fmt::format(
                "Pareto front of the mixture's relative fit error against the fit's seconds, each the mean over the "
                "table's {} environments:\n\n",
                std::set<std::string>([&] {
                  std::set<std::string> e;
                  for (const auto& [k, r] : fits) e.insert(k.first);
                  return e;
                }())
                    .size()) +
            front_text(front, "s (fit)", "mean fit error");
      });
}

// ---- denoising ---------------------------------------------------------------------------------

// The receiver classes of the denoising table: the column of their relative L2 and their name.
struct ReceiverClass {
  const char* column;
  const char* name;
};
constexpr ReceiverClass kReceiverClasses[] = {{"glossy_relative_l2", "glossy"}, {"diffuse_relative_l2", "diffuse"}};

namespace {

// The denoising table by noisy input and weighting (one row per floor roughness), and the parts of
// the section written from it.
struct DenoiseSection {
  using Rows = std::vector<const runner::CsvRecord*>;
  const Table* t;
  std::string& b;  // the section's body
  bool timed;      // the table has the filter's cost column
  std::vector<std::string> inputs, weights;
  std::map<std::string, std::map<std::string, Rows>> rows;  // noisy input → weights → one row per floor roughness

  DenoiseSection(const Table* table, std::string& body) : t(table), b(body), timed(table->has("ns_per_pixel")) {
    for (const auto& r : t->csv.rows) {
      remember(inputs, t->text(r, "noisy"));
      remember(weights, t->text(r, "weights"));
      rows[t->text(r, "noisy")][t->text(r, "weights")].push_back(&r);
    }
  }

  double mean(const Rows& rs, const std::string& column) const {
    double s = 0;
    for (const auto* r : rs) s += t->number(*r, column);
    return rs.empty() ? NAN : s / double(rs.size());
  }
  // The weighting of `input` with the lowest mean of `column`.
  std::pair<double, std::string> lowest(const std::string& input, const std::string& column) {
    std::pair<double, std::string> best{INFINITY, ""};
    for (const auto& w : weights)
      if (rows[input].count(w)) best = std::min(best, {mean(rows[input][w], column), w});
    return best;
  }
  std::string cost(const std::string& input, const std::string& w) {
    return timed ? fmt::format(", {} ns/pixel", magnitude(mean(rows[input][w], "ns_per_pixel"))) : std::string();
  }

  // The headline: per noisy input, the weighting with the lowest mean for each receiver class.
  std::string headline() {
    std::vector<std::string> verdicts;
    for (const auto& in : inputs) {
      const auto gl = lowest(in, kReceiverClasses[0].column), di = lowest(in, kReceiverClasses[1].column);
      if (gl.second == di.second)
        verdicts.push_back(fmt::format("{}: **{}** on both (glossy {}, diffuse {}{})", in, gl.second, g(gl.first),
                                       g(di.first), cost(in, gl.second)));
      else
        verdicts.push_back(fmt::format("{}: glossy **{}** ({}{}), diffuse **{}** ({}{})", in, gl.second, g(gl.first),
                                       cost(in, gl.second), di.second, g(di.first), cost(in, di.second)));
    }
    return fmt::format("lowest mean relative L2 over the floor roughnesses, per noisy input — {}{}",
                       fmt::join(verdicts, "; "), timed ? "" : "; the table measures no cost");
  }

  // Each weighting's means and worst row, per noisy input.
  void table() {
    b += "Per noisy input, each weighting's mean relative L2 over the table's floor roughnesses (all pixels, glossy "
         "receivers, diffuse "
         "receivers) and its worst row (all pixels)";
    b += timed ? ", with the filter's mean ns per pixel (the table's cost column):\n\n"
               : "; the table measures no cost:\n\n";
    b += "| noisy input | weights | ns/pixel | relative L2 | glossy | diffuse | worst relative L2 | at floor roughness "
         "|\n"
         "|---|---|---|---|---|---|---|---|\n";
    for (const auto& in : inputs)
      for (const auto& w : weights) {
        if (!rows[in].count(w)) continue;
        const Rows& rs = rows[in][w];
        const runner::CsvRecord* worst = rs.front();
        for (const auto* r : rs)
          if (t->number(*r, "relative_l2") > t->number(*worst, "relative_l2")) worst = r;
        b += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", in, w,
                         timed ? magnitude(mean(rs, "ns_per_pixel")) : "—", g(mean(rs, "relative_l2")),
                         g(mean(rs, kReceiverClasses[0].column)), g(mean(rs, kReceiverClasses[1].column)),
                         g(t->number(*worst, "relative_l2")), t->text(*worst, "floor_roughness"));
      }
  }

  // With a cost column: the Pareto front per noisy input.
  void fronts() {
    if (timed)
      for (const auto& in : inputs) {
        std::vector<Candidate> all;
        for (const auto& w : weights)
          if (rows[in].count(w))
            all.push_back({w, mean(rows[in][w], "ns_per_pixel"), mean(rows[in][w], "relative_l2")});
        b += "\nPareto front of " + in + " (mean relative L2, all pixels, against mean ns per pixel):\n\n" +
             front_text(pareto_front(all), "ns/pixel", "relative L2", magnitude);
      }
  }

  // Caveats of one noisy input: where the lowest mean is not the lowest row by row, and mean against
  // worst row.
  void caveats(const std::string& in) {
    // Where the weighting with the lowest mean is not the lowest row by row.
    for (const auto& rc : kReceiverClasses) {
      const std::string best = lowest(in, rc.column).second;
      for (const auto& other : weights) {
        if (other == best || !rows[in].count(other)) continue;
        int above = 0, n = 0;
        double most = -INFINITY;
        std::string at, values;
        std::vector<std::string> where;
        for (const auto* r : rows[in][best])
          for (const auto* q : rows[in][other]) {
            if (t->text(*r, "floor_roughness") != t->text(*q, "floor_roughness")) continue;
            ++n;
            const double e = t->number(*r, rc.column), o = t->number(*q, rc.column);
            if (!(e > o)) continue;
            ++above;
            where.push_back(t->text(*r, "floor_roughness"));
            if (e / o - 1 > most)
              most = e / o - 1, at = t->text(*r, "floor_roughness"), values = fmt::format("{} against {}", g(e), g(o));
          }
        if (above)
          b += fmt::format(
              "- {}, {} receivers: {} (the lowest mean) is above {} at {} of {} floor roughnesses ({}); most at {}, "
              "{} "
              "({}).\n",
              in, rc.name, best, other, above, n, fmt::join(where, ", "), at, signed_percent(most), values);
      }
    }
    // Mean against worst row (all pixels).
    std::pair<double, std::string> best_worst{INFINITY, ""};
    for (const auto& w : weights) {
      if (!rows[in].count(w)) continue;
      double worst = -INFINITY;
      for (const auto* r : rows[in][w]) worst = std::max(worst, t->number(*r, "relative_l2"));
      best_worst = std::min(best_worst, {worst, w});
    }
    const auto best_mean = lowest(in, "relative_l2");
    if (best_worst.second != best_mean.second)
      b += fmt::format("- {}, all pixels: {} has the lowest mean relative L2 ({}), {} the lowest worst row ({}).\n", in,
                       best_mean.second, g(best_mean.first), best_worst.second, g(best_worst.first));
  }

  // Caveat: filtering that makes it worse than the noisy input it starts from.
  void worse_than_noisy() {
    // Filtering that makes it worse than the noisy input it starts from.
    if (t->has("noisy_relative_l2"))
      for (const auto& w : weights) {
        int worse = 0, n = 0;
        double most = -INFINITY;
        std::string at;
        for (const auto& in : inputs)
          for (const auto* r : rows[in][w]) {
            ++n;
            const double e = t->number(*r, "relative_l2"), noisy = t->number(*r, "noisy_relative_l2");
            if (!(e > noisy)) continue;
            ++worse;
            if (e / noisy - 1 > most)
              most = e / noisy - 1, at = fmt::format("{}, floor roughness {}: {} against {}", in,
                                                     t->text(*r, "floor_roughness"), g(e), g(noisy));
          }
        if (worse)
          b += fmt::format(
              "- {}: the filtered image is further from the reference than its noisy input on {} of {} rows (most {} "
              "at "
              "{}).\n",
              w, worse, n, signed_percent(most), at);
      }
  }
};

}  // namespace

Section denoise(Tables& tables) {
  return section(tables, "Denoising: the filter", {"filtering_denoise.csv"}, [&](Section& sec, const Table* t) {
    DenoiseSection s(t, sec.body);
    sec.headline = s.headline();
    s.table();
    s.fronts();
    sec.body += "\nCaveats measured:\n\n";
    for (const auto& in : s.inputs) s.caveats(in);
    s.worse_than_noisy();
  });
}

}  // namespace sglab::experiments::recommendations::detail
