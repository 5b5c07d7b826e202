// `sglab recommend --from DIR [--out DIR] [--tables-dir DIR]`: recommendations.md from the tables
// of a full `sglab reproduce` (recommendations.hpp). Runs last in `sglab reproduce`, after every
// table it reads.
#include "recommendations.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "atomic_file.hpp"
#include "csv.hpp"
#include "envmap_bases.hpp"
#include "option_checks.hpp"
#include "parse_number.hpp"
#include "registry.hpp"
#include "sglab/registry.hpp"

namespace sglab::experiments::recommendations {

const std::vector<std::string>& input_tables() {
  static const std::vector<std::string> files = {"error_vs_time.csv",       "stability.csv",
                                                 "near_wall_smape.csv",     "near_wall_smape_sweep.csv",
                                                 "hemispherical_rmse.csv",  "specular_vs_roughness.csv",
                                                 "vsgl_error_vs_count.csv", "vsgl_error_vs_roughness_distance.csv",
                                                 "vsgl_visibility_off.csv", "vsgl_visibility_on.csv",
                                                 "filtering.csv",           "filtering_denoise.csv",
                                                 "envmap_lobes.csv",        "envmap_bases.csv",
                                                 "shader_export.csv"};
  return files;
}

std::vector<Candidate> pareto_front(std::vector<Candidate> all) {
  std::stable_sort(all.begin(), all.end(), [](const Candidate& a, const Candidate& b) {
    return a.cost < b.cost || (a.cost == b.cost && a.error < b.error);
  });
  std::vector<Candidate> front;
  for (const auto& c : all)
    if (std::isfinite(c.cost) && std::isfinite(c.error) && (front.empty() || c.error < front.back().error))
      front.push_back(c);
  return front;
}

namespace {

namespace fs = std::filesystem;

std::string g(double x) { return std::isfinite(x) ? fmt::format("{:.3g}", x) : "—"; }
// A count (instructions, ulps, points, floats): every digit.
std::string count(double x) { return std::isfinite(x) ? fmt::format("{:.0f}", x) : "—"; }
// A measured cost: three significant digits, every integer digit from 1000 up (2249, not 2.25e+03).
std::string magnitude(double x) {
  return std::isfinite(x) && std::abs(x) >= 1000 && std::abs(x) < 1e9 ? count(x) : g(x);
}

// The shader section's "cheapest within": a max error of 1 % of the reference, the generator's own
// choice of a diffuse error small enough to trade for instructions (the most accurate export is
// named beside it).
constexpr double kShaderTolerance = 0.01;
// Two environments whose rows in the basis table differ by a median below this (relative) are
// named as ones the table barely tells apart.
constexpr double kSameEnvironment = 0.01;

// One committed table: its rows, and the command its header names.
struct Table {
  std::string file, command;
  runner::CsvTable csv;

  bool has(const std::string& column) const { return csv.column(column) != runner::CsvTable::npos; }
  const std::string& text(const runner::CsvRecord& r, const std::string& column) const {
    const std::size_t c = csv.column(column);
    if (c == runner::CsvTable::npos) throw runner::InputError("recommend: " + file + " has no column '" + column + "'");
    return r.fields[c];
  }
  // The field as a number; NaN when empty ("—" in the Markdown tables). runner::parse_table_number:
  // strtod took "nan", "inf" and "1e400" in a table and carried them into the recommendations.
  double number(const runner::CsvRecord& r, const std::string& column) const {
    const std::string& s = text(r, column);
    if (s.empty()) return NAN;
    try {
      return runner::parse_table_number(s);
    } catch (const runner::NumberError& e) {
      throw runner::InputError(
          fmt::format("recommend: {} line {}, column '{}': {} {}", file, r.line, column, quote(s), e.what()));
    }
  }
  std::string source() const {
    return "[" + file + "](" + file + ")" + (command.empty() ? "" : " (`" + command + "`)");
  }
};

// The tables read, by file name; a table that is not there is listed in `missing`.
class Tables {
 public:
  Tables(std::string dir, std::vector<std::string>& missing) : dir_(std::move(dir)), missing_(missing) {}
  const Table* get(const std::string& file) {
    // Every table read is in input_tables(): `sglab reproduce` fingerprints those for its marker.
    if (std::find(input_tables().begin(), input_tables().end(), file) == input_tables().end())
      throw std::logic_error("recommend: " + file + " is read but not listed in input_tables()");
    if (auto it = cache_.find(file); it != cache_.end()) return it->second.get();
    const fs::path path = fs::path(dir_) / file;
    std::ifstream in(path, std::ios::binary);
    std::unique_ptr<Table> t;
    if (in) {
      t = std::make_unique<Table>();
      t->file = file;
      std::string body, line;
      while (std::getline(in, line)) {
        if (line.rfind('#', 0) == 0) {  // "# Generated by `CMD` (…)": the command that made it
          const auto a = line.find('`'), b = line.rfind('`');
          if (t->command.empty() && a != std::string::npos && b > a) t->command = line.substr(a + 1, b - a - 1);
          continue;
        }
        body += line + "\n";
      }
      std::istringstream s(body);
      t->csv = runner::read_csv(s, path.string());
    } else {
      missing_.push_back(file);
    }
    return (cache_[file] = std::move(t)).get();
  }

 private:
  std::string dir_;
  std::vector<std::string>& missing_;
  std::map<std::string, std::unique_ptr<Table>> cache_;
};

// The choice per budget along a front.
std::string budget_text(const std::vector<Candidate>& front, const std::string& cost_label,
                        std::string (*cost)(double) = g) {
  std::string s = "By budget (" + cost_label + "): ";
  for (std::size_t i = 0; i < front.size(); ++i)
    s += fmt::format("{}from {}: **{}**", i ? "; " : "", cost(front[i].cost), front[i].name) +
         (i + 1 < front.size() ? fmt::format(" (below {})", cost(front[i + 1].cost)) : " and above");
  return s + ".\n";
}

// The front as a Markdown table, and the choice per budget.
std::string front_text(const std::vector<Candidate>& front, const std::string& cost_label,
                       const std::string& error_label, std::string (*cost)(double) = g) {
  std::string s = fmt::format("| choice | {} | {} |\n|---|---|---|\n", cost_label, error_label);
  for (const auto& c : front) s += fmt::format("| {} | {} | {} |\n", c.name, cost(c.cost), g(c.error));
  return s + "\n" + budget_text(front, cost_label, cost);
}

const Candidate* named(const std::vector<Candidate>& v, const std::string& name) {
  for (const auto& c : v)
    if (c.name == name) return &c;
  return nullptr;
}

// The section titled `title` drawn from the tables `files`: fill(sec, table…) sets its headline
// and body when every one is present, and their sources close the body; without them it stays
// empty (compute leaves it out).
template <std::size_t N, class Fill>
Section section(Tables& tables, std::string title, const char* const (&files)[N], Fill fill) {
  Section sec{std::move(title), "", ""};
  std::array<const Table*, N> t{};
  for (std::size_t k = 0; k < N; ++k) t[k] = tables.get(files[k]);
  if (std::find(t.begin(), t.end(), nullptr) != t.end()) return sec;
  std::apply([&](const auto*... table) { fill(sec, table...); }, t);
  std::string sources;
  for (std::size_t k = 0; k < N; ++k) sources += (k ? ", " : "") + t[k]->source();
  sec.body += "\nSources: " + sources + ".\n";
  return sec;
}

// ---- clamped cosine (diffuse) ----------------------------------------------------------------

std::vector<Candidate> grid_candidates(const Table& t, const std::string& quantity, const std::string& error_column) {
  const Quantity* q = find_quantity(quantity);
  std::vector<Candidate> out;
  for (const auto& r : t.csv.rows) {
    const std::string& m = t.text(r, "method");
    if (t.text(r, "quantity") != quantity || t.text(r, "precision") != "double" || m.find('[') != std::string::npos ||
        (q && m == q->reference_method))
      continue;
    out.push_back({m, t.number(r, "ns_per_eval"), t.number(r, error_column)});
  }
  return out;
}

// The methods of `quantity` that return negatives or non-finite values on error-vs-time's grid.
std::string grid_flaws(const Table& t, const std::string& quantity) {
  std::string s;
  for (const auto& r : t.csv.rows) {
    if (t.text(r, "quantity") != quantity || t.text(r, "method").find('[') != std::string::npos) continue;
    const double neg = t.number(r, "negatives"), bad = t.number(r, "non_finite");
    if (neg > 0 || bad > 0)
      s += fmt::format("- {} ({}): {} negative and {} non-finite outputs on error-vs-time's grid.\n",
                       t.text(r, "method"), t.text(r, "precision"), g(neg), g(bad));
  }
  return s;
}

// From the stability atlas: each front member's NaN/Inf/negative/>1 % counts and where its error is worst.
std::string stability_caveats(const Table* st, const std::string& quantity, const std::vector<Candidate>& front) {
  if (!st) return "";
  std::string s;
  for (const auto& c : front)
    for (const auto& r : st->csv.rows)
      if (st->text(r, "quantity") == quantity && st->text(r, "method") == c.name)
        s += fmt::format(
            "- {} ({}), stability atlas: {} NaN, {} Inf, {} negative, {} of {} points > 1 % off; worst error "
            "relative to the peak {} at {}.\n",
            c.name, st->text(r, "precision"), st->text(r, "nan"), st->text(r, "inf"), st->text(r, "negative"),
            st->text(r, "wrong_rel_1pct"), st->text(r, "compared"), st->text(r, "max_peak_error"),
            st->text(r, "max_peak_error_at"));
  return s.empty() ? "" : s + "  (" + st->source() + ")\n";
}

// The headline choice: the most accurate member of the front, and the cheapest one within `good`.
std::string headline(const std::vector<Candidate>& front, const std::string& cost_unit, const std::string& error_name,
                     double good) {
  if (front.empty()) return "no data";
  const Candidate& best = front.back();
  std::string s = fmt::format("**{}** (the most accurate: {} {}, {} {})", best.name, error_name, g(best.error),
                              g(best.cost), cost_unit);
  for (const auto& c : front)
    if (c.error <= good && c.name != best.name) {
      s += fmt::format("; cheapest within {} {}: **{}** ({}, {} {})", error_name, g(good), c.name, g(c.error),
                       g(c.cost), cost_unit);
      break;
    }
  return s;
}

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

// ---- helpers of the sections below ---------------------------------------------------------------

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string signed_percent(double x) { return fmt::format("{:+.1f} %", 100 * x); }

// Appends `s` to `order` unless it is there: the table's order of first appearance.
void remember(std::vector<std::string>& order, const std::string& s) {
  if (std::find(order.begin(), order.end(), s) == order.end()) order.push_back(s);
}

// ---- denoising ---------------------------------------------------------------------------------

// The receiver classes of the denoising table: the column of their relative L2 and their name.
struct ReceiverClass {
  const char* column;
  const char* name;
};
constexpr ReceiverClass kReceiverClasses[] = {{"glossy_relative_l2", "glossy"}, {"diffuse_relative_l2", "diffuse"}};

Section denoise(Tables& tables) {
  return section(tables, "Denoising: the filter", {"filtering_denoise.csv"}, [&](Section& sec, const Table* t) {
    const bool timed = t->has("ns_per_pixel");
    using Rows = std::vector<const runner::CsvRecord*>;
    std::vector<std::string> inputs, weights;
    std::map<std::string, std::map<std::string, Rows>> rows;  // noisy input → weights → one row per floor roughness
    for (const auto& r : t->csv.rows) {
      remember(inputs, t->text(r, "noisy"));
      remember(weights, t->text(r, "weights"));
      rows[t->text(r, "noisy")][t->text(r, "weights")].push_back(&r);
    }
    const auto mean = [&](const Rows& rs, const std::string& column) {
      double s = 0;
      for (const auto* r : rs) s += t->number(*r, column);
      return rs.empty() ? NAN : s / double(rs.size());
    };
    // The weighting of `input` with the lowest mean of `column`.
    const auto lowest = [&](const std::string& input, const std::string& column) {
      std::pair<double, std::string> best{INFINITY, ""};
      for (const auto& w : weights)
        if (rows[input].count(w)) best = std::min(best, {mean(rows[input][w], column), w});
      return best;
    };
    const auto cost = [&](const std::string& input, const std::string& w) {
      return timed ? fmt::format(", {} ns/pixel", magnitude(mean(rows[input][w], "ns_per_pixel"))) : std::string();
    };
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
    sec.headline = fmt::format("lowest mean relative L2 over the floor roughnesses, per noisy input — {}{}",
                               fmt::join(verdicts, "; "), timed ? "" : "; the table measures no cost");
    std::string& b = sec.body;
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
    if (timed)
      for (const auto& in : inputs) {
        std::vector<Candidate> all;
        for (const auto& w : weights)
          if (rows[in].count(w))
            all.push_back({w, mean(rows[in][w], "ns_per_pixel"), mean(rows[in][w], "relative_l2")});
        b += "\nPareto front of " + in + " (mean relative L2, all pixels, against mean ns per pixel):\n\n" +
             front_text(pareto_front(all), "ns/pixel", "relative L2", magnitude);
      }
    b += "\nCaveats measured:\n\n";
    for (const auto& in : inputs) {
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
                most = e / o - 1, at = t->text(*r, "floor_roughness"),
                values = fmt::format("{} against {}", g(e), g(o));
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
        b += fmt::format("- {}, all pixels: {} has the lowest mean relative L2 ({}), {} the lowest worst row ({}).\n",
                         in, best_mean.second, g(best_mean.first), best_worst.second, g(best_worst.first));
    }
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
  });
}

// ---- environment basis -----------------------------------------------------------------------------

// The layers the basis section weighs, with their targets (envmap_bases.hpp).
struct BasisLayer {
  std::string key, label;
  double target;
};

Section bases(Tables& tables) {
  namespace eb = envmap_bases;
  return section(tables, "Environment lighting: the basis", {"envmap_bases.csv"}, [&](Section& sec, const Table* t) {
    // diffuse-engine (the shading an engine runs: SG by hill-fitted) is held to the diffuse target too.
    const std::vector<BasisLayer> layers = {
        {"diffuse", "diffuse", eb::kDiffuseTarget},
        {"diffuse-engine", "diffuse-engine", eb::kDiffuseTarget},
        {"specular", fmt::format("specular α = {:g}", eb::kTargetRoughness), eb::kSpecularTarget}};
    // One basis at one size ("sg-fixed nnls N=16"), over the environments.
    struct Fit {
      std::string family, size;
      double floats = 0, lobes = 0;                     // lobes: N, 0 for a basis of another size symbol (SH's L)
      std::map<std::string, double> seconds, ns, zero;  // per environment
      std::map<std::string, std::map<std::string, double>> error;  // layer → environment → relative L2
    };
    std::vector<std::string> order, envs, families;
    std::map<std::string, Fit> fits;
    for (const auto& r : t->csv.rows) {
      const std::string env = t->text(r, "environment"), variant = t->text(r, "variant");
      const std::string family = t->text(r, "basis") + (variant.empty() ? "" : " " + variant);
      const std::string size = t->text(r, "size_symbol") + "=" + t->text(r, "size"), name = family + " " + size;
      remember(order, name);
      remember(envs, env);
      remember(families, family);
      Fit& f = fits[name];
      f.family = family, f.size = size, f.floats = t->number(r, "floats");
      f.lobes = t->text(r, "size_symbol") == "N" ? t->number(r, "size") : 0;
      f.seconds[env] = t->number(r, "fit_seconds");
      f.ns[env] = t->number(r, "diffuse_ns_per_pixel");
      f.zero[env] = t->number(r, "zero_lobes");
      std::string layer = t->text(r, "layer");
      if (layer == "specular") {
        if (t->number(r, "roughness") != eb::kTargetRoughness) continue;  // the other roughnesses: envmap_bases.md
      }
      f.error[layer][env] = t->number(r, "relative_l2");
    }
    const auto values = [](const std::map<std::string, double>& m) {
      std::vector<double> v;
      for (const auto& [k, x] : m) v.push_back(x);
      return v;
    };
    const auto max_at = [](const std::map<std::string, double>& m) {
      std::pair<double, std::string> w{-INFINITY, ""};
      for (const auto& [k, x] : m)
        if (x > w.first) w = {x, k};
      return w;
    };
    std::string& b = sec.body;
    b += fmt::format(
        "The table's x axis is storage: per basis and size, its stored float count, and the median over the table's {} "
        "environments of each layer's relative L2 (with the largest, the median fit seconds and the median ns per "
        "pixel "
        "of "
        "the engine's diffuse shading). Pareto front of the median error against stored floats, per layer:\n",
        envs.size());
    std::vector<std::string> verdicts;
    for (const auto& layer : layers) {
      std::vector<Candidate> all;
      for (const auto& name : order)
        if (fits[name].error.count(layer.key))
          all.push_back({name, fits[name].floats, median(values(fits[name].error[layer.key]))});
      const auto front = pareto_front(all);
      b += fmt::format(
          "\n**{}** (target {:g} %):\n\n| choice | floats | median relative L2 | max (environment) | median fit s | "
          "median ns/pixel |\n"
          "|---|---|---|---|---|---|\n",
          layer.label, 100 * layer.target);
      for (const auto& c : front) {
        Fit& f = fits[c.name];
        const auto w = max_at(f.error[layer.key]);
        b += fmt::format("| {} | {} | {} | {} ({}) | {} | {} |\n", c.name, count(c.cost), g(c.error), g(w.first),
                         w.second, g(median(values(f.seconds))), magnitude(median(values(f.ns))));
      }
      b += "\n" + budget_text(front, "stored floats", count);
      const Candidate* reach = nullptr;
      for (const auto& c : front)
        if (c.error <= layer.target) {
          reach = &c;
          break;
        }
      if (reach) {
        const auto w = max_at(fits[reach->name].error[layer.key]);
        verdicts.push_back(fmt::format("{} ≤ {:g} % from **{}** ({} floats: median {}, max {} {})", layer.label,
                                       100 * layer.target, reach->name, count(reach->cost), g(reach->error), g(w.first),
                                       w.second));
      } else if (!front.empty()) {
        verdicts.push_back(fmt::format("{} ≤ {:g} % not reached; the most accurate **{}** ({} floats: median {})",
                                       layer.label, 100 * layer.target, front.back().name, count(front.back().cost),
                                       g(front.back().error)));
      }
    }
    sec.headline = fmt::format("median over {} environments — {}", envs.size(), fmt::join(verdicts, "; "));
    // The smallest storage reaching each target, per environment and basis.
    std::vector<std::string> targets;
    for (const auto& l : layers) targets.push_back(fmt::format("{} ≤ {:g} %", l.label, 100 * l.target));
    b += fmt::format(
        "\nSmallest stored-float count at which each basis reaches the targets, per environment (each cell: {}; "
        "relative "
        "L2):\n\n| environment |",
        fmt::join(targets, " / "));
    for (const auto& fam : families) b += " " + fam + " |";
    b += "\n|---|" + [&] {
      std::string s;
      for (std::size_t i = 0; i < families.size(); ++i) s += "---|";
      return s;
    }() + "\n";
    for (const auto& env : envs) {
      b += "| " + env + " |";
      for (const auto& fam : families) {
        std::vector<std::string> cell;
        for (const auto& layer : layers) {
          double smallest = INFINITY;
          for (const auto& name : order) {
            Fit& f = fits[name];
            if (f.family != fam || !f.error[layer.key].count(env)) continue;
            if (f.error[layer.key][env] <= layer.target) smallest = std::min(smallest, f.floats);
          }
          cell.push_back(std::isfinite(smallest) ? count(smallest) : "not reached");
        }
        b += fmt::format(" {} |", fmt::join(cell, " / "));
      }
      b += "\n";
    }
    b += "\nCaveats measured:\n\n";
    // Zero-amplitude lobes.
    for (const auto& fam : families) {
      double most = 0, of = 0;
      int with = 0, n = 0;
      std::string at;
      for (const auto& name : order) {
        Fit& f = fits[name];
        if (f.family != fam) continue;
        for (const auto& [env, z] : f.zero) {
          ++n;
          if (z > 0) ++with;
          if (z > most) most = z, of = f.lobes, at = env + " " + f.size;
        }
      }
      if (with)
        b += fmt::format(
            "- {}: zero-amplitude lobes in {} of {} fits, up to {} of {} ({}): stored floats that carry nothing.\n",
            fam, with, n, count(most), count(of), at);
    }
    if (!t->has("negatives"))
      b += "- The table counts no negative values: where a least-squares fit (signed amplitudes, `sg-fixed ls`) or SH "
           "ringing makes the "
           "representation negative is not measured.\n";
    // Error growing with storage, per basis and layer (each environment's sizes in the table's order).
    for (const auto& fam : families)
      for (const auto& layer : layers) {
        int rises = 0, steps = 0;
        double most = 1;
        std::string at;
        for (const auto& env : envs) {
          const Fit* prev = nullptr;
          for (const auto& name : order) {
            Fit& f = fits[name];
            if (f.family != fam || !f.error[layer.key].count(env)) continue;
            if (prev) {
              ++steps;
              const double a = prev->error.at(layer.key).at(env), e = f.error[layer.key][env];
              if (e > a) {
                ++rises;
                if (e / a > most)
                  most = e / a, at = fmt::format("{}: {} at {} → {} at {}", env, g(a), prev->size, g(e), f.size);
              }
            }
            prev = &f;
          }
        }
        if (rises)
          b += fmt::format("- {}, {}: the error grows with storage in {} of {} steps to the next size; most at {}.\n",
                           fam, layer.label, rises, steps, at);
      }
    // The engine's diffuse shading against the exact diffuse of the same representation.
    for (const auto& fam : families) {
      double most = 1;
      std::string at;
      for (const auto& name : order) {
        Fit& f = fits[name];
        if (f.family != fam || !f.error.count("diffuse-engine")) continue;
        for (const auto& [env, e] : f.error["diffuse-engine"])
          if (f.error["diffuse"].count(env) && e / f.error["diffuse"][env] > most)
            most = e / f.error["diffuse"][env],
            at = fmt::format("{} {}: {} against the exact {}", env, f.size, g(e), g(f.error["diffuse"][env]));
      }
      if (!at.empty())
        b += fmt::format(
            "- {}: the engine's diffuse shading (layer diffuse-engine) is furthest above the exact diffuse at {}.\n",
            fam, at);
    }
    // Environments the table barely tells apart: the median relative difference of their rows.
    for (std::size_t i = 0; i < envs.size(); ++i)
      for (std::size_t j = i + 1; j < envs.size(); ++j) {
        std::vector<double> diff;
        double most = -1;
        std::string at;
        for (const auto& name : order)
          for (auto& [layer, per_env] : fits[name].error)
            if (per_env.count(envs[i]) && per_env.count(envs[j])) {
              const double a = per_env[envs[i]], c = per_env[envs[j]], d = std::abs(a - c) / std::max(a, c);
              if (!std::isfinite(d)) continue;
              diff.push_back(d);
              if (d > most) most = d, at = name + ", " + layer;
            }
        if (!diff.empty() && median(diff) < kSameEnvironment)
          b += fmt::format(
              "- {} and {}: their {} rows differ by a median {:.2g} % (max {:.2g} % at {}): the table barely tells "
              "them "
              "apart "
              "(see its text).\n",
              envs[i], envs[j], diff.size(), 100 * median(diff), 100 * most, at);
      }
  });
}

// ---- exported shaders --------------------------------------------------------------------------------

Section shaders(Tables& tables) {
  return section(tables, "Shaders: the exported methods", {"shader_export.csv"}, [&](Section& sec, const Table* t) {
    struct Export {
      double instructions = NAN, error = NAN, ulps = NAN, compiles = 1, grid_bad = 0, stiff = 0, stiff_negative = 0,
             stiff_bad = 0;
    };
    std::vector<std::string> quantities, evaluators, languages;  // languages: the evaluators with a SPIR-V count
    std::map<std::string, std::vector<std::string>> methods;     // quantity → methods, in the table's order
    std::map<std::string, std::map<std::string, std::map<std::string, Export>>> ex;  // quantity → method → evaluator
    for (const auto& r : t->csv.rows) {
      const std::string& full = t->text(r, "method");
      const auto slash = full.find('/');
      if (slash == std::string::npos)
        throw runner::InputError(
            fmt::format("recommend: {} line {}: method '{}' is not QUANTITY/METHOD", t->file, r.line, clip_text(full)));
      const std::string q = full.substr(0, slash), m = full.substr(slash + 1), e = t->text(r, "evaluator");
      remember(quantities, q);
      remember(methods[q], m);
      remember(evaluators, e);
      Export& x = ex[q][m][e];
      const double instructions = t->number(r, "spirv_instructions");
      x.instructions = instructions >= 0 ? instructions : NAN;  // -1: not compiled to SPIR-V (sglab float, C)
      if (instructions >= 0) remember(languages, e);
      x.error = t->number(r, "max_error");
      x.ulps = t->number(r, "max_ulps_vs_sglab_float");
      x.compiles = t->number(r, "compiles");
      x.grid_bad = t->number(r, "grid_non_finite");
      x.stiff = t->number(r, "stiff_points");
      x.stiff_negative = t->number(r, "stiff_negatives");
      x.stiff_bad = t->number(r, "stiff_non_finite");
    }
    // One value per language: once when every language has it, else each with its language.
    const auto per_language = [&](const std::function<std::string(const std::string&)>& value) {
      std::vector<std::string> v;
      std::set<std::string> distinct;
      for (const auto& l : languages) v.push_back(value(l) + " " + l), distinct.insert(value(l));
      return distinct.size() == 1 ? *distinct.begin() : fmt::format("{}", fmt::join(v, " / "));
    };
    std::string& b = sec.body;
    b += fmt::format(
        "Per quantity, every exported method: its max error against the quantity's reference ({}), the largest "
        "difference from "
        "sglab's own float evaluation in ulps, and the SPIR-V instruction count of the compiled shader — glslang's "
        "unoptimized "
        "count, a proxy for cost, not a cycle count. The fronts: max error against SPIR-V instructions, per "
        "language.\n",
        fmt::join(evaluators, ", "));
    std::string headline_quantity = quantities.empty() ? "" : quantities.front();
    if (std::find(quantities.begin(), quantities.end(), "clamped-cosine") != quantities.end())
      headline_quantity = "clamped-cosine";
    for (const auto& q : quantities) {
      b += "\n**" + q + "**:\n\n| method | " + fmt::format("{}", fmt::join(evaluators, " max error | ")) +
           " max error |";
      for (const auto& l : languages) b += " " + l + " ulps | " + l + " SPIR-V |";
      b += "\n|---|";
      for (std::size_t i = 0; i < evaluators.size() + 2 * languages.size(); ++i) b += "---|";
      b += "\n";
      for (const auto& m : methods[q]) {
        b += "| " + m + " |";
        for (const auto& e : evaluators) b += " " + (ex[q][m].count(e) ? g(ex[q][m][e].error) : "—") + " |";
        for (const auto& l : languages)
          b += " " + (ex[q][m].count(l) ? count(ex[q][m][l].ulps) : "—") + " | " +
               (ex[q][m].count(l) ? count(ex[q][m][l].instructions) : "—") + " |";
        b += "\n";
      }
      // The export-only formulas (`filtering/…`: the filtering weights) answer different questions,
      // each against its own double evaluation: no front between them.
      if (!find_quantity(q)) continue;
      std::map<std::string, std::vector<Candidate>> fronts;
      for (const auto& l : languages) {
        std::vector<Candidate> all;
        for (const auto& m : methods[q])
          if (ex[q][m].count(l) && ex[q][m][l].compiles > 0)
            all.push_back({m, ex[q][m][l].instructions, ex[q][m][l].error});
        fronts[l] = pareto_front(all);
        b += "\n" + l + " front:\n\n" + front_text(fronts[l], "SPIR-V instructions", "max error", count);
      }
      if (q != headline_quantity || languages.empty()) continue;
      // The verdict: the most accurate export, and the cheapest within kShaderTolerance, each per language.
      const auto pick = [&](bool within) {
        std::map<std::string, std::string> by;
        for (const auto& l : languages) {
          const auto& f = fronts[l];
          if (f.empty()) continue;
          if (!within) by[l] = f.back().name;
          else
            for (const auto& c : f)
              if (c.error <= kShaderTolerance) {
                by[l] = c.name;
                break;
              }
        }
        return by;
      };
      const auto describe = [&](const std::map<std::string, std::string>& by) {
        std::set<std::string> names;
        for (const auto& [l, m] : by) names.insert(m);
        if (names.size() != 1 || by.size() != languages.size()) return std::string();
        const std::string m = *names.begin();
        return fmt::format("**{}** (max error {}, ≤ {} ulps from sglab float; SPIR-V instructions {})", m,
                           per_language([&](const std::string& l) { return g(ex[q][m][l].error); }),
                           per_language([&](const std::string& l) { return count(ex[q][m][l].ulps); }),
                           per_language([&](const std::string& l) { return count(ex[q][m][l].instructions); }));
      };
      const auto best = pick(false), cheap = pick(true);
      std::string verdict = describe(best);
      if (verdict.empty()) {  // the languages disagree: each its own
        std::vector<std::string> v;
        for (const auto& [l, m] : best)
          v.push_back(fmt::format("{} **{}** (max error {})", l, m, g(ex[q][m][l].error)));
        verdict = fmt::format("{}", fmt::join(v, ", "));
      }
      sec.headline = fmt::format("{}: paste {}", q, verdict);
      if (cheap != best) {
        const std::string c = describe(cheap);
        sec.headline += fmt::format("; cheapest within max error {}: {}", g(kShaderTolerance),
                                    c.empty() ? "the languages disagree (see the fronts)" : c);
      }
      sec.headline += "; measured on lavapipe (a CPU), not a GPU";
    }
    b += "\nCaveats measured:\n\n";
    if (!languages.empty())
      b += fmt::format(
          "- The {} rows ran on lavapipe, Vulkan on the CPU (shader_export.md names the device), not on a GPU, whose "
          "exp, log and "
          "sqrt approximations may change the ulps; the SPIR-V counts are unoptimized and compare within a language "
          "only.\n",
          fmt::join(languages, " and "));
    for (const auto& q : quantities)
      for (const auto& m : methods[q]) {
        std::vector<std::string> notes;
        std::map<std::string, std::vector<std::string>> by_note;  // the same finding for several evaluators: said once
        for (const auto& e : evaluators) {
          if (!ex[q][m].count(e)) continue;
          const Export& x = ex[q][m][e];
          if (x.compiles <= 0) by_note["does not compile"].push_back(e);
          if (x.grid_bad > 0) by_note[fmt::format("{} NaN/Inf on the grid", count(x.grid_bad))].push_back(e);
          if (x.stiff_negative > 0)
            by_note[fmt::format("{} negative of {} stiff points", count(x.stiff_negative), count(x.stiff))].push_back(
                e);
          if (x.stiff_bad > 0)
            by_note[fmt::format("{} NaN/Inf of {} stiff points", count(x.stiff_bad), count(x.stiff))].push_back(e);
        }
        for (const auto& [note, es] : by_note)
          notes.push_back(es.size() == evaluators.size() ? note + " (every evaluator)"
                                                         : fmt::format("{} ({})", note, fmt::join(es, ", ")));
        // A shader whose max error is not sglab float's: the port's rounding shows at the error's size.
        if (ex[q][m].count("sglab float"))
          for (const auto& l : languages)
            if (ex[q][m].count(l) && g(ex[q][m][l].error) != g(ex[q][m]["sglab float"].error))
              notes.push_back(fmt::format("{} max error {} against sglab float's {} ({} ulps apart)", l,
                                          g(ex[q][m][l].error), g(ex[q][m]["sglab float"].error),
                                          count(ex[q][m][l].ulps)));
        if (!notes.empty()) b += fmt::format("- {}/{}: {}.\n", q, m, fmt::join(notes, "; "));
      }
    // What `sglab export` refuses by name: the registry's methods of these quantities without a traced formula.
    for (const auto& q : quantities)
      if (const Quantity* reg = find_quantity(q)) {
        std::vector<std::string> refused;
        for (const auto& m : reg->methods)
          if (!m.trace && m.name != reg->reference_method) refused.push_back(m.name);
        if (!refused.empty())
          b += fmt::format("- {}: not exportable (`sglab export` refuses them by name, so they have no row): {}.\n", q,
                           fmt::join(refused, ", "));
      }
  });
}

}  // namespace

Result compute(const Options& o) {
  Result r;
  r.provenance.command = "sglab recommend" + runner::option_argument("--from", o.from, Options{}.from) +
                         (o.tables_dir.empty() ? runner::option_argument("--out", o.out, Options{}.out)
                                               : runner::option_argument("--tables-dir", o.tables_dir));
  // A --from that is not a directory, or holds none of the tables, is bad input: the report would
  // be all "no data" (it was written with exit status 0).
  std::error_code ec;
  if (!fs::is_directory(o.from, ec))
    throw runner::InputError(fmt::format("recommend: --from {} is not a directory", quote(o.from)));
  Tables tables(o.from, r.missing);
  for (Section s : {diffuse(tables), hemispherical(tables), specular(tables), vsgl(tables), filtering(tables),
                    denoise(tables), environment(tables), bases(tables), shaders(tables)})
    if (!s.body.empty()) r.sections.push_back(std::move(s));
  if (r.sections.empty())
    throw runner::InputError(
        fmt::format("recommend: --from {} holds none of the tables it reads (a full `sglab reproduce`'s: {}, …)",
                    quote(o.from), input_tables().front()));
  return r;
}

std::string markdown(const Result& r) {
  std::string md =
      "# Recommendations: which method to ship\n\n"
      "Read from the tables of a full `sglab reproduce` (each section names its tables and the command that wrote "
      "them): per "
      "quantity, the Pareto front of error against cost (no method off it is both cheaper and more accurate), the "
      "choice per "
      "cost budget, and the caveats the tables measured. Every number here is a table's, or the mean, median or "
      "maximum of a "
      "table's rows where the text says so. Costs are CPU measures of this machine's run; compare within a table, not "
      "across.\n\n"
      "## Headlines\n\n";
  for (const auto& s : r.sections) md += "- **" + s.title + "**: " + s.headline + "\n";
  for (const auto& s : r.sections) md += "\n## " + s.title + "\n\n" + s.body;
  if (!r.missing.empty())
    md += fmt::format("\nNot present when this was generated (their sections are left out): {}.\n",
                      fmt::join(r.missing, ", "));
  return md;
}

void write(const Options& o, const Result& r) {
  const fs::path dir = runner::tables_place(o.tables_dir, o.out);
  write_table(dir, "recommendations", r.provenance, markdown(r), "");
  std::fprintf(stderr, "recommend: wrote %s/recommendations.md (%zu sections)\n", dir.c_str(), r.sections.size());
}

}  // namespace sglab::experiments::recommendations

namespace sglab::experiments {

void add_recommend_command(CLI::App& app, const runner::RunContext& run) {
  auto o = std::make_shared<recommendations::Options>();
  auto* sub = app.add_subcommand("recommend",
                                 "Which method to ship, per quantity: Pareto fronts and caveats read from the tables");
  sub->add_option("--from", o->from, "directory of the tables to read (a full `sglab reproduce`'s)")
      ->capture_default_str();
  frontend::add_places_options(*sub, o->out, o->tables_dir, "directory for recommendations.md",
                               "where recommendations.md goes (default: the --out directory)");
  sub->callback([o, run] { recommendations::write(*o, runner::with_run(recommendations::compute(*o), run)); });
}

Experiment recommendations_experiment() {
  return {"recommend", "which method to ship, per quantity, from the tables (recommendations.md)",
          add_recommend_command, [](const Places& p) {
            Step s = sglab_step("recommend", "recommendations.md: Pareto fronts, budgets and caveats from every table",
                                {"recommend", "--from", p.tables, "--out", p.out + "/recommendations"}, {},
                                "--tables-dir");
            for (const auto& f : recommendations::input_tables()) s.reads.push_back(p.tables + "/" + f);
            return std::vector<Step>{s};
          }};
}

}  // namespace sglab::experiments
