// `sglab sweep specular`'s summary of the per-point CSV (sweep_specular.hpp): per method and
// roughness the brightness-weighted error and the error near the lobe, as CSV and Markdown; the sweep
// itself is sweep_specular.cpp.
#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "csv_fields.hpp"
#include "parse_number.hpp"
#include "sglab/text_limits.hpp"
#include "sweep_specular.hpp"
#include "table.hpp"

namespace sglab::experiments {

// ---- summary ----------------------------------------------------------------------------------

namespace {

// Per (group, value, method): per point the brightness-weighted error Σ|v − r|/Σ|r| over rows
// with a value; the bright rows' SMAPE.
struct Brightness {
  std::map<std::string, metrics::BrightnessWeighted> points;  // point key → its sums
  double smape_sum = 0;
  std::size_t bright = 0;
};

// The brightness-weighted error (the mean over points) and the bright rows' SMAPE of one summary row.
void add_brightness(const Brightness& b, SpecularSummaryRow& row) {
  double sum = 0;
  for (const auto& [point, e] : b.points)
    if (e.has_reference()) {
      sum += e.value();
      ++row.weighted_points;
    }
  if (row.weighted_points) row.weighted_error = sum / double(row.weighted_points);
  row.bright_rows = b.bright;
  if (row.bright_rows) row.bright_smape = b.smape_sum / double(row.bright_rows);
}

}  // namespace

std::vector<SpecularSummaryRow> summarize_specular_points(const runner::CsvTable& t, const std::string& source) {
  auto column = [&](const std::string& name) {
    const std::size_t c = t.column(name);
    if (c == runner::CsvTable::npos)
      throw runner::InputError(fmt::format("{}: no column '{}' (not a specular sweep's per-point CSV?)", source, name));
    return c;
  };
  const std::size_t c_reference = column("reference"), c_scale = column("scale"), c_value = column("value"),
                    c_method = column("method"), c_position = column("position"), c_roughness = column("roughness"),
                    c_sharpness = column("light_sharpness"), c_view = column("view_cos");
  auto number = [&](const runner::CsvRecord& r, std::size_t c) {
    try {
      return runner::parse_decimal<double>(r.fields[c]);
    } catch (const runner::NumberError& e) {
      throw runner::InputError(
          fmt::format("{}: line {}, column '{}': '{}' {}", source, r.line, t.header[c], r.fields[c], e.what()));
    }
  };

  struct Group {
    std::string by;
    std::size_t column;   // npos: one group "all"
    bool near_lobe_only;  // only the rows of the near-lobe positions
    std::vector<std::string> order;
  };
  std::vector<Group> groups = {
      {"roughness", c_roughness, false, {}},       {"roughness_near_lobe", c_roughness, true, {}},
      {"light_sharpness", c_sharpness, false, {}}, {"view_cos", c_view, false, {}},
      {"position", c_position, false, {}},         {"all", runner::CsvTable::npos, false, {}}};
  std::vector<std::string> methods;
  std::map<std::tuple<std::size_t, std::string, std::string>, metrics::ErrorAccumulator> acc;  // (group, value, method)
  std::map<std::tuple<std::size_t, std::string, std::string>, Brightness> brightness;
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    const runner::CsvRecord& r = t.rows[i];
    const std::string& method = r.fields[c_method];
    if (std::find(methods.begin(), methods.end(), method) == methods.end()) methods.push_back(method);
    const double reference = number(r, c_reference), scale = number(r, c_scale);
    const bool has_value = !r.fields[c_value].empty();
    const double value = has_value ? number(r, c_value) : 0.0;
    const bool near_lobe = specular_position_near_lobe(r.fields[c_position]);
    for (std::size_t g = 0; g < groups.size(); ++g) {
      if (groups[g].near_lobe_only && !near_lobe) continue;
      const std::string key = groups[g].column == runner::CsvTable::npos ? "all" : r.fields[groups[g].column];
      auto& order = groups[g].order;
      if (std::find(order.begin(), order.end(), key) == order.end()) order.push_back(key);
      acc.try_emplace({g, key, method}, kSpecularNearZero).first->second.add(has_value, value, reference, scale, i);
      if (!has_value) continue;
      Brightness& b = brightness[{g, key, method}];
      auto& point = b.points[r.fields[c_roughness] + "," + r.fields[c_sharpness] + "," + r.fields[c_view]];
      point.add(value, reference);
      if (reference >= kSpecularBrightCutoff * scale && reference > 0) {
        b.smape_sum += metrics::smape(value, reference);
        ++b.bright;
      }
    }
  }
  std::vector<SpecularSummaryRow> out;
  for (std::size_t g = 0; g < groups.size(); ++g)
    for (const auto& key : groups[g].order)
      for (const auto& method : methods) {
        const auto it = acc.find({g, key, method});
        if (it == acc.end()) continue;
        SpecularSummaryRow row{.by = groups[g].by, .group = key, .method = method, .stats = it->second.stats()};
        if (const auto b = brightness.find({g, key, method}); b != brightness.end()) add_brightness(b->second, row);
        if (row.stats.worst < t.rows.size()) {
          const auto& w = t.rows[row.stats.worst].fields;
          row.worst_roughness = w[c_roughness];
          row.worst_light_sharpness = w[c_sharpness];
          row.worst_view_cos = w[c_view];
          row.worst_position = w[c_position];
        }
        out.push_back(std::move(row));
      }
  return out;
}

std::string specular_summary_csv(const std::vector<SpecularSummaryRow>& rows) {
  std::string csv;
  runner::append_csv_fields(csv, "by", "group", "method", "points", "relative_points", "near_zero", "missing",
                            "rmse_relative", "max_relative", "smape", "max_scaled", "rmse_scaled", "worst_roughness",
                            "worst_light_sharpness", "worst_view_cos", "worst_position", "weighted_error",
                            "weighted_points", "bright_smape", "bright_rows");
  for (const auto& r : rows) {
    const metrics::ErrorStats& s = r.stats;
    runner::append_csv_fields(csv, r.by, r.group, r.method, s.points, s.relative, s.near_zero, s.missing,
                              runner::csv_number(s.rmse_relative), runner::csv_number(s.max_relative),
                              runner::csv_number(s.smape), runner::csv_number(s.max_scaled),
                              runner::csv_number(s.rmse_scaled), r.worst_roughness, r.worst_light_sharpness,
                              r.worst_view_cos, r.worst_position, runner::csv_number(r.weighted_error),
                              r.weighted_points, runner::csv_number(r.bright_smape), r.bright_rows);
  }
  return csv;
}

namespace {

std::string percent(double x) { return std::isnan(x) ? "—" : fmt::format("{:.3g}", 100 * x); }

// A group value as a reader wants it: numbers to 3 digits ("0.0178"), names as they are.
std::string short_group(const std::string& g) {
  try {
    return fmt::format("{:.3g}", runner::parse_decimal<double>(g));
  } catch (const runner::NumberError&) {
    return g;
  }
}

// The summary rows indexed for the tables: the methods and each `by`'s group values in order.
struct SummaryIndex {
  std::vector<std::string> methods;
  std::map<std::string, std::vector<std::string>> groups;  // by → values in order
  std::map<std::tuple<std::string, std::string, std::string>, const SpecularSummaryRow*> cell;

  explicit SummaryIndex(const std::vector<SpecularSummaryRow>& rows) {
    for (const auto& r : rows) {
      if (std::find(methods.begin(), methods.end(), r.method) == methods.end()) methods.push_back(r.method);
      auto& g = groups[r.by];
      if (std::find(g.begin(), g.end(), r.group) == g.end()) g.push_back(r.group);
      cell[{r.by, r.group, r.method}] = &r;
    }
  }
  std::string values(const std::string& by) {
    std::string s;
    for (const auto& g : groups[by]) s += (s.empty() ? "" : ", ") + short_group(g);
    return s;
  }
  // One table: a row per group value of `by`, a column per method, `show` of the summary row.
  template <class Show>
  std::string rtable(const std::string& by, const std::string& first, Show show) {
    std::string s = "| " + first + " |", rule = "|---|";
    for (const auto& m : methods) {
      s += fmt::format(" {} |", m);
      rule += "---|";
    }
    s += "\n" + rule + "\n";
    for (const auto& g : groups[by]) {
      s += "| " + short_group(g) + " |";
      for (const auto& m : methods) {
        const auto it = cell.find({by, g, m});
        s += fmt::format(" {} |", it == cell.end() ? std::string("—") : show(*it->second));
      }
      s += "\n";
    }
    return s + "\n";
  }
  // As `rtable`, with `show` of the row's ErrorStats.
  template <class Show>
  std::string table(const std::string& by, const std::string& first, Show show) {
    return rtable(by, first, [&](const SpecularSummaryRow& r) { return show(r.stats); });
  }
};

// What is compared with what: the BRDF, the quantity, the grid, the measures.
std::string summary_intro(const std::vector<SpecularSummaryRow>& rows, SummaryIndex& x,
                          const runner::Provenance& provenance, SpecularBrdf brdf) {
  std::size_t near_zero = 0, points = 0;
  for (const auto& r : rows)
    if (r.by == "all") near_zero = std::max(near_zero, r.stats.near_zero), points = std::max(points, r.stats.points);
  const auto values = [&](const std::string& by) { return x.values(by); };

  const bool gaussian = brdf == SpecularBrdf::gaussian;
  const std::string title = gaussian
                                ? "Specular reflection of an SG light off the Gaussian-angle NDF BRDF: error against m"
                                : "Specular reflection of an SG light off GGX: error against roughness";
  const std::string model =
      gaussian
          ? "Every method of the `specular-gaussian-ndf` quantity (`sglab eval --list`): the SG approximations of the "
            "Cook–Torrance-style BRDF of Wang et al. 2009 (NDF e^{−(θ_h/m)²} ≈ G(h; n, 2/m²) warped about the mirror "
            "direction, M_o = F·S/(π(n·ω)(n·ωo)) at the lobe axis; `sg-warp-meder` is the form of the blog post "
            "\"Rendering using Spherical Gaussians\", the cosine as Meder & Brüderlin 2018's SG as in PhySG) against "
            "`reference`, THE SAME BRDF integrated exactly (adaptive 2D quadrature, ≤ 1e-6 relative), not against GGX: "
            "unit-amplitude SG light, D = e^{−(θ_h/m)²} with D(n) = 1, V-cavity S (Cook & Torrance 1982), Schlick "
            "f0 = 0.04 (docs/math.md §5). In the tables below **α is the NDF width m** (radians; ≈ the Beckmann/GGX α "
            "at small angles), over m"
          : "Every method of the `specular` quantity (`sglab eval --list`) against `reference` (adaptive 2D "
            "quadrature, ≤ 1e-6 relative), unit-amplitude SG light, GGX with height-correlated Smith and Schlick "
            "f0 = 0.04, over roughness α";
  return runner::markdown_header(provenance) +
         fmt::format(
             "# {9}\n\n"
             "Command: `{0}` (per-point data: `{11}_points.csv` in its `--out` directory; sharded runs joined by "
             "`sglab merge` give the same file). {10} ∈ {{{1}}} × light sharpness λ ∈ {{{2}}} × view_cos ∈ {{{3}}} "
             "× light positions {{{4}}} in the lobe's own frame: the mirror direction; one in-plane width toward the "
             "normal and "
             "toward the horizon; one and three widths across the plane of incidence (the lobe is cos θo narrower "
             "across it: "
             "in-plane width min(√(1/λ + 2α²), π/6), across min(√(1/λ + 2α²cos²θo), π/6)); the normal. Only lights "
             "above the "
             "horizon, and no duplicate rows (at view_cos = 1 the mirror is the normal and the one-width positions are "
             "one).\n\n"
             "**Brightness-weighted error** = per point Σ|v − r|/Σr over its light positions, averaged over the "
             "points: the "
             "error in proportion to how much each light contributes. **Bright SMAPE** = SMAPE over the rows whose "
             "reference "
             "is at least {8} % of their point's peak (the largest reference over its positions). Plain SMAPE = mean "
             "of "
             "2|v − r|/(|v| + |r|) (0–200 %) over all significant rows, dominated by dim rows where a method returning "
             "~0 scores "
             "~200 %; RMSE = root mean square of the relative error. **Near-zero references**: a reference below {5} "
             "of its "
             "point's peak has no meaningful relative error; such rows ({6} of {7} per method over the grid) are left "
             "out of "
             "SMAPE, RMSE and the maximum and counted. The scaled error |v − r| / (the peak), over all rows, covers "
             "them "
             "(\"RMSE scaled\", \"max scaled\"). All numbers in %.\n\n",
             provenance.command, values("roughness"), values("light_sharpness"), values("view_cos"), values("position"),
             runner::csv_number(kSpecularNearZero), near_zero, points, fmt::format("{:g}", 100 * kSpecularBrightCutoff),
             title, model, gaussian ? "specular-gaussian" : "specular");
}

// The whole grid: every statistic per method.
std::string whole_grid_table(const std::vector<SpecularSummaryRow>& rows) {
  std::string md;
  md +=
      "## Over the whole grid\n\n| method | brightness-weighted | bright SMAPE | SMAPE | max relative | RMSE | RMSE "
      "scaled | max scaled | near 0 | missing | worst point (α, λ, view_cos, position) "
      "|\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    if (r.by != "all") continue;
    const metrics::ErrorStats& s = r.stats;
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", r.method, percent(r.weighted_error),
                      percent(r.bright_smape), percent(s.smape), percent(s.max_relative), percent(s.rmse_relative),
                      percent(s.rmse_scaled), percent(s.max_scaled), s.near_zero, s.missing,
                      r.worst_roughness.empty() ? "—"
                                                : fmt::format("{}, {}, {}, {}", short_group(r.worst_roughness),
                                                              short_group(r.worst_light_sharpness),
                                                              short_group(r.worst_view_cos), r.worst_position));
  }
  return md;
}

}  // namespace

std::string specular_summary_markdown(const std::vector<SpecularSummaryRow>& rows, const runner::Provenance& provenance,
                                      SpecularBrdf brdf) {
  SummaryIndex x(rows);
  auto weighted = [](const SpecularSummaryRow& r) { return percent(r.weighted_error); };
  auto bright = [](const SpecularSummaryRow& r) { return percent(r.bright_smape); };
  auto smape = [](const metrics::ErrorStats& s) { return percent(s.smape); };
  auto max_rel = [](const metrics::ErrorStats& s) { return percent(s.max_relative); };
  auto rmse = [](const metrics::ErrorStats& s) { return percent(s.rmse_relative); };
  auto rmse_scaled = [](const metrics::ErrorStats& s) { return percent(s.rmse_scaled); };
  auto both = [](const metrics::ErrorStats& s) { return percent(s.smape) + " / " + percent(s.max_relative); };
  const auto rtable = [&](const std::string& by, const std::string& first, auto show) {
    return x.rtable(by, first, show);
  };
  const auto table = [&](const std::string& by, const std::string& first, auto show) {
    return x.table(by, first, show);
  };
  std::string md = summary_intro(rows, x, provenance, brdf);
  md += "## Brightness-weighted error Σ|v − r|/Σr (%) by roughness α\n\n" + rtable("roughness", "α", weighted);
  md += fmt::format("## SMAPE (%) over rows ≥ {:g} % of the point's peak, by roughness α\n\n",
                    100 * kSpecularBrightCutoff) +
        rtable("roughness", "α", bright);
  md += "## SMAPE (%) by roughness α\n\n" + table("roughness", "α", smape);
  md += "## Maximum relative error (%) by roughness α\n\n" + table("roughness", "α", max_rel);
  md += "## RMSE of the relative error (%) by roughness α\n\n" + table("roughness", "α", rmse);
  md +=
      "## RMSE of the scaled error (%) by roughness α\n\n|v − r| / (the point's largest reference), all rows: how much "
      "the error shows next to the brightest light position.\n\n" +
      table("roughness", "α", rmse_scaled);
  md +=
      "## Near the highlight: SMAPE / maximum relative error (%) by roughness α\n\nOnly the light positions within "
      "one width of the mirror direction (mirror, toward-normal, toward-horizon, side); the tables above include the "
      "lobe's tails too.\n\n" +
      table("roughness_near_lobe", "α", both);
  md += "## Where each method breaks: SMAPE / maximum relative error (%)\n\n";
  md += "By view angle (all α, λ, positions):\n\n" + table("view_cos", "view_cos", both);
  md += "By light sharpness:\n\n" + table("light_sharpness", "λ", both);
  md += "By light position:\n\n" + table("position", "position", both);
  return md + whole_grid_table(rows);
}

}  // namespace sglab::experiments
