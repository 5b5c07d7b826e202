// `sglab recommend`'s sections on what an engine ships: the environment-lighting basis and the
// exported shaders (recommendations_detail.hpp).
#include "recommendations_detail.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "envmap_bases.hpp"
#include "sglab/registry.hpp"

namespace sglab::experiments::recommendations::detail {

// ---- environment basis -----------------------------------------------------------------------------

namespace {

// The layers the basis section weighs, with their targets (envmap_bases.hpp).
struct BasisLayer {
  std::string key, label;
  double target;
};

// One basis at one size ("sg-fixed nnls N=16"), over the environments.
struct BasisFit {
  std::string family, size;
  double floats = 0, lobes = 0;                     // lobes: N, 0 for a basis of another size symbol (SH's L)
  std::map<std::string, double> seconds, ns, zero;  // per environment
  std::map<std::string, std::map<std::string, double>> error;  // layer → environment → relative L2
};

// The values of a map, in key order.
std::vector<double> values(const std::map<std::string, double>& m) {
  std::vector<double> v;
  for (const auto& [k, x] : m) v.push_back(x);
  return v;
}

// The largest value of a map and its key.
std::pair<double, std::string> max_at(const std::map<std::string, double>& m) {
  std::pair<double, std::string> w{-INFINITY, ""};
  for (const auto& [k, x] : m)
    if (x > w.first) w = {x, k};
  return w;
}

// The basis table read into fits (one per basis and size, over the environments), and the parts of
// the section written from them.
struct BasisSection {
  const Table* t;
  std::string& b;  // the section's body
  std::vector<BasisLayer> layers;
  std::vector<std::string> order, envs, families;
  std::map<std::string, BasisFit> fits;
  std::vector<std::string> verdicts;  // per layer: where its target is reached (the headline)

  BasisSection(const Table* table, std::string& body) : t(table), b(body) {
    namespace eb = envmap_bases;
    layers = {{"diffuse", "diffuse", eb::kDiffuseTarget},
              {"diffuse-engine", "diffuse-engine", eb::kDiffuseTarget},
              {"specular", fmt::format("specular α = {:g}", eb::kTargetRoughness), eb::kSpecularTarget}};
    for (const auto& r : t->csv.rows) {
      const std::string env = t->text(r, "environment"), variant = t->text(r, "variant");
      const std::string family = t->text(r, "basis") + (variant.empty() ? "" : " " + variant);
      const std::string size = t->text(r, "size_symbol") + "=" + t->text(r, "size"), name = family + " " + size;
      remember(order, name);
      remember(envs, env);
      remember(families, family);
      BasisFit& f = fits[name];
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
  }

  // per layer, the Pareto front of the median error against stored floats, and its verdict
  void fronts() {
    b += fmt::format(
        "The table's x axis is storage: per basis and size, its stored float count, and the median over the table's {} "
        "environments of each layer's relative L2 (with the largest, the median fit seconds and the median ns per "
        "pixel "
        "of "
        "the engine's diffuse shading). Pareto front of the median error against stored floats, per layer:\n",
        envs.size());
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
        BasisFit& f = fits[c.name];
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
  }

  // the smallest storage reaching each target, per environment and basis
  void smallest_storage() {
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
            BasisFit& f = fits[name];
            if (f.family != fam || !f.error[layer.key].count(env)) continue;
            if (f.error[layer.key][env] <= layer.target) smallest = std::min(smallest, f.floats);
          }
          cell.push_back(std::isfinite(smallest) ? count(smallest) : "not reached");
        }
        b += fmt::format(" {} |", fmt::join(cell, " / "));
      }
      b += "\n";
    }
  }

  // caveat: zero-amplitude lobes
  void zero_lobes() {
    // Zero-amplitude lobes.
    for (const auto& fam : families) {
      double most = 0, of = 0;
      int with = 0, n = 0;
      std::string at;
      for (const auto& name : order) {
        BasisFit& f = fits[name];
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
  }

  // caveat: negatives, when the table does not count them
  void negatives() {
    if (!t->has("negatives"))
      b += "- The table counts no negative values: where a least-squares fit (signed amplitudes, `sg-fixed ls`) or SH "
           "ringing makes the "
           "representation negative is not measured.\n";
  }

  // caveat: error growing with storage, per basis and layer
  void growth() {
    // Error growing with storage, per basis and layer (each environment's sizes in the table's order).
    for (const auto& fam : families)
      for (const auto& layer : layers) {
        int rises = 0, steps = 0;
        double most = 1;
        std::string at;
        for (const auto& env : envs) {
          const BasisFit* prev = nullptr;
          for (const auto& name : order) {
            BasisFit& f = fits[name];
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
  }

  // caveat: the engine's diffuse shading against the exact diffuse of the same representation
  void engine() {
    // The engine's diffuse shading against the exact diffuse of the same representation.
    for (const auto& fam : families) {
      double most = 1;
      std::string at;
      for (const auto& name : order) {
        BasisFit& f = fits[name];
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
  }

  // caveat: environments the table barely tells apart
  void alike() {
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
  }
};

}  // namespace

Section bases(Tables& tables) {
  return section(tables, "Environment lighting: the basis", {"envmap_bases.csv"}, [&](Section& sec, const Table* t) {
    BasisSection s(t, sec.body);
    s.fronts();
    sec.headline = fmt::format("median over {} environments — {}", s.envs.size(), fmt::join(s.verdicts, "; "));
    s.smallest_storage();
    sec.body += "\nCaveats measured:\n\n";
    s.zero_lobes();
    s.negatives();
    s.growth();
    s.engine();
    s.alike();
  });
}

// ---- exported shaders --------------------------------------------------------------------------------

namespace {

// One exported method in one evaluator (a row of shader_export.csv).
struct Export {
  double instructions = NAN, error = NAN, ulps = NAN, compiles = 1, grid_bad = 0, stiff = 0, stiff_negative = 0,
         stiff_bad = 0;
};

// The shader table read by quantity, method and evaluator, and the parts of the section written
// from it.
struct ShaderSection {
  const Table* t;
  std::string& b;                                              // the section's body
  std::string& headline;                                       // the section's headline
  std::vector<std::string> quantities, evaluators, languages;  // languages: the evaluators with a SPIR-V count
  std::map<std::string, std::vector<std::string>> methods;     // quantity → methods, in the table's order
  std::map<std::string, std::map<std::string, std::map<std::string, Export>>> ex;  // quantity → method → evaluator
  std::string headline_quantity;  // clamped-cosine when the table has it, else its first quantity

  ShaderSection(const Table* table, std::string& body, std::string& head) : t(table), b(body), headline(head) {
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
    headline_quantity = quantities.empty() ? "" : quantities.front();
    if (std::find(quantities.begin(), quantities.end(), "clamped-cosine") != quantities.end())
      headline_quantity = "clamped-cosine";
  }

  // One value per language: once when every language has it, else each with its language.
  std::string per_language(const std::function<std::string(const std::string&)>& value) const {
    std::vector<std::string> v;
    std::set<std::string> distinct;
    for (const auto& l : languages) v.push_back(value(l) + " " + l), distinct.insert(value(l));
    return distinct.size() == 1 ? *distinct.begin() : fmt::format("{}", fmt::join(v, " / "));
  }

  // The opening: what the columns are.
  void intro() {
    b += fmt::format(
        "Per quantity, every exported method: its max error against the quantity's reference ({}), the largest "
        "difference from "
        "sglab's own float evaluation in ulps, and the SPIR-V instruction count of the compiled shader — glslang's "
        "unoptimized "
        "count, a proxy for cost, not a cycle count. The fronts: max error against SPIR-V instructions, per "
        "language.\n",
        fmt::join(evaluators, ", "));
  }

  // One quantity: its methods' errors, ulps and SPIR-V counts, its fronts per language, and for the
  // headline quantity the verdict.
  void quantity(const std::string& q) {
    b += "\n**" + q + "**:\n\n| method | " + fmt::format("{}", fmt::join(evaluators, " max error | ")) + " max error |";
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
    if (!find_quantity(q)) return;
    std::map<std::string, std::vector<Candidate>> fronts;
    for (const auto& l : languages) {
      std::vector<Candidate> all;
      for (const auto& m : methods[q])
        if (ex[q][m].count(l) && ex[q][m][l].compiles > 0)
          all.push_back({m, ex[q][m][l].instructions, ex[q][m][l].error});
      fronts[l] = pareto_front(all);
      b += "\n" + l + " front:\n\n" + front_text(fronts[l], "SPIR-V instructions", "max error", count);
    }
    if (q != headline_quantity || languages.empty()) return;
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
      for (const auto& [l, m] : best) v.push_back(fmt::format("{} **{}** (max error {})", l, m, g(ex[q][m][l].error)));
      verdict = fmt::format("{}", fmt::join(v, ", "));
    }
    headline = fmt::format("{}: paste {}", q, verdict);
    if (cheap != best) {
      const std::string c = describe(cheap);
      headline += fmt::format("; cheapest within max error {}: {}", g(kShaderTolerance),
                              c.empty() ? "the languages disagree (see the fronts)" : c);
    }
    headline += "; measured on lavapipe (a CPU), not a GPU";
  }

  // Caveat: the device the shaders ran on.
  void device() {
    if (!languages.empty())
      b += fmt::format(
          "- The {} rows ran on lavapipe, Vulkan on the CPU (shader_export.md names the device), not on a GPU, whose "
          "exp, log and "
          "sqrt approximations may change the ulps; the SPIR-V counts are unoptimized and compare within a language "
          "only.\n",
          fmt::join(languages, " and "));
  }

  // Caveats per method: compile failures, non-finite and negative outputs, a port's rounding.
  void method_notes() {
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
  }

  // Caveat: what `sglab export` refuses by name.
  void not_exportable() {
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
  }
};

}  // namespace

Section shaders(Tables& tables) {
  return section(tables, "Shaders: the exported methods", {"shader_export.csv"}, [&](Section& sec, const Table* t) {
    ShaderSection s(t, sec.body, sec.headline);
    s.intro();
    for (const auto& q : s.quantities) s.quantity(q);
    sec.body += "\nCaveats measured:\n\n";
    s.device();
    s.method_notes();
    s.not_exportable();
  });
}

}  // namespace sglab::experiments::recommendations::detail
