// `sglab envmap bases`' tables: the Markdown and CSV of a computed Result (envmap_bases.hpp), the
// storage targets, the free-lobe fit's section; the computation is envmap_bases.cpp.
#include "envmap_bases.hpp"

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "envmap_basis.hpp"
#include "sglab/text_limits.hpp"
#include "table.hpp"

namespace sglab::experiments::envmap_bases {

namespace {

std::string num(double v) { return fmt::format("{:.3g}", v); }

std::string label(const Row& row) { return row.variant.empty() ? row.basis : row.basis + " " + row.variant; }

std::size_t roughness_index(const Options& a, double rough) {
  return std::size_t(std::find(a.roughness.begin(), a.roughness.end(), rough) - a.roughness.begin());
}

// The per-environment summary: the smallest storage reaching the diffuse and specular targets.
std::string targets_markdown(const Result& r) {
  const std::size_t r03 = roughness_index(r.options, kTargetRoughness);
  std::string md = fmt::format(
      "| environment | basis | floats for diffuse ≤ {:g} % | floats for specular (α = {:g}) ≤ {:g} % "
      "|\n|---|---|---|---|\n",
      100 * kDiffuseTarget, kTargetRoughness, 100 * kSpecularTarget);
  for (const auto& env : r.environments) {
    std::vector<std::string> order;
    std::map<std::string, std::pair<int, int>> best;
    for (const auto& row : env.rows) {
      const std::string l = label(row);
      if (!best.count(l)) order.push_back(l), best[l] = {0, 0};
      auto& b = best[l];
      if (row.diffuse_error <= kDiffuseTarget && (b.first == 0 || row.floats < b.first)) b.first = row.floats;
      if (row.specular_error[r03] <= kSpecularTarget && (b.second == 0 || row.floats < b.second)) b.second = row.floats;
    }
    for (const auto& l : order)
      md += fmt::format("| {} | {} | {} | {} |\n", env.name, l,
                        best[l].first ? std::to_string(best[l].first) : "not reached",
                        best[l].second ? std::to_string(best[l].second) : "not reached");
  }
  return md;
}

// What the free-lobe section lists after its table: where a bar fails, the rungs the guard kept, the
// cost at the largest N, vMF EM's rises, the rungs whose diffuse error rose.
struct FreeLobeFindings {
  std::vector<std::string> fails_half, fails_fixed, kept, cost, vmf_rises, diffuse_rises;
};

// A fit's iterations and level: "595 (128×64 + 4 tiles)".
std::string level(const Row* row) {
  return fmt::format("{} ({}×{}{})", row->iterations, row->fit_width, row->fit_height,
                     row->detail_tiles > 0 ? fmt::format(" + {} tiles", row->detail_tiles) : "");
}

// v's items joined by ", " after `prefix`; `none` for no items.
std::string list(const std::vector<std::string>& v, const std::string& none = "", const std::string& prefix = "") {
  if (v.empty()) return none;
  std::string s = prefix;
  for (std::size_t k = 0; k < v.size(); ++k) s += (k ? ", " : "") + v[k];
  return s;
}

// One environment's rows of the free-lobe table, and its findings.
void free_lobe_environment(const Environment& env, std::string& md, FreeLobeFindings& found) {
  std::map<int, const Row*> free, vmf;
  std::map<int, double> fixed;
  for (const auto& row : env.rows) {
    if (row.basis == "sg-free") free[row.size] = &row;
    if (row.basis == "vmf-em") vmf[row.size] = &row;
    if (row.basis == "sg-fixed")
      fixed[row.size] = fixed.count(row.size) ? std::min(fixed[row.size], row.map_error) : row.map_error;
  }
  for (const auto& [n, row] : vmf)
    if (vmf.count(n / 2) && row->map_error > vmf.at(n / 2)->map_error)
      found.vmf_rises.push_back(
          fmt::format("{} N = {} ({} after {})", env.name, n, num(row->map_error), num(vmf.at(n / 2)->map_error)));
  for (const auto& [n, row] : free) {
    const Row* half = free.count(n / 2) ? free.at(n / 2) : nullptr;
    if (half && row->map_error <= half->map_error && row->diffuse_error > half->diffuse_error)
      found.diffuse_rises.push_back(fmt::format("{} N = {} (map {} → {}, diffuse {} → {})", env.name, n,
                                                num(half->map_error), num(row->map_error), num(half->diffuse_error),
                                                num(row->diffuse_error)));
    const bool has_fixed = fixed.count(n) > 0;
    const Row* v = vmf.count(n) ? vmf.at(n) : nullptr;
    const bool ok_half = !half || row->map_error <= half->map_error,
               ok_fixed = !has_fixed || row->map_error <= fixed.at(n);
    if (!ok_half) found.fails_half.push_back(fmt::format("{} N = {}", env.name, n));
    if (!ok_fixed) found.fails_fixed.push_back(fmt::format("{} N = {}", env.name, n));
    if (row->kept_lobes > 0) {
      // The rung whose lobes these are: the smallest N with the same error (a guard's result is
      // kept by every later rung that also ends above it).
      int origin = n;
      for (const auto& [m, other] : free)
        if (m < origin && other->map_error == row->map_error) origin = m;
      found.kept.push_back(
          fmt::format("{} N = {} (kept {}{})", env.name, n, row->kept_lobes,
                      origin < n / 2 ? fmt::format(": the lobes of N = {}, the fit stalls there", origin) : ""));
    }
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2f} | {} | {} | {} | {} |\n", env.name, n,
                      num(row->map_error), half ? num(half->map_error) : "—", half ? (ok_half ? "yes" : "**no**") : "—",
                      row->kept_lobes > 0 ? std::to_string(row->kept_lobes) : "—", has_fixed ? num(fixed.at(n)) : "—",
                      has_fixed ? (ok_fixed ? "yes" : "**no**") : "—", v ? num(v->map_error) : "—", row->seconds,
                      v ? fmt::format("{:.2f}", v->seconds) : "—",
                      v && v->seconds > 0 ? fmt::format("{:.2f}", row->seconds / v->seconds) : "—", level(row),
                      v ? level(v) : "—");
  }
  if (!free.empty() && vmf.count(free.rbegin()->first)) {
    const Row* f = free.rbegin()->second;
    const Row* v = vmf.at(free.rbegin()->first);
    found.cost.push_back(
        fmt::format("{} {:.1f}× ({:.1f} ms of fit time per LM iteration against {:.1f} ms per EM iteration, {} "
                    "against {} iterations)",
                    env.name, v->seconds > 0 ? f->seconds / v->seconds : 0.0,
                    f->iterations > 0 ? 1e3 * f->seconds / f->iterations : 0.0,
                    v->iterations > 0 ? 1e3 * v->seconds / v->iterations : 0.0, f->iterations, v->iterations));
  }
}

// The free-lobe fit against its own N/2, the best fixed-lobe fit at equal N, and vMF EM's time;
// then where either bar fails, the rungs the ladder's guard kept, and the cost per iteration of
// both fits at the largest N.
std::string free_lobe_markdown(const Result& r) {
  std::string md =
      "| environment | N | sg-free map error | at N/2 | ≤ N/2? | kept from N/2 | best sg-fixed at N | ≤ sg-fixed? | "
      "vmf-em | "
      "sg-free s | vmf-em s | time ratio free/vMF | sg-free LM iterations (level) | vmf-em EM iterations (level) |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  FreeLobeFindings found;
  for (const auto& env : r.environments) free_lobe_environment(env, md, found);
  md += "\n**Error at N ≤ error at N/2**: " +
        list(found.fails_half, "holds at every N on every environment", "fails at ") +
        ". **Error at N ≤ the best fixed-lobe fit at N**: " +
        list(found.fails_fixed, "holds at every N on every environment", "fails at ") +
        ". The ladder warm-starts each rung from the previous rung's lobes plus new lobes seeded on the positive "
        "residual, so "
        "the cost on the fitted level cannot rise; the map error is measured on the full map, where it can, so a "
        "rung "
        "whose "
        "full-map error ends above its predecessor's reports the predecessor's lobes plus zero-amplitude lobes (column "
        "\"kept from N/2\"; they count in \"zero lobes\" below): " +
        list(found.kept, "no rung needed it") + ".\n\n";
  md +=
      "**Time at the largest N, free-lobe against vMF EM** (fit seconds over iterations: the whole ladder's time over "
      "all "
      "its LM iterations; vMF's including its k-means start and amplitude solve): " +
      list(found.cost) +
      ". Why the free-lobe fit is slower: its time at N covers the whole ladder (rungs 2, 4, …, N, each an amplitude "
      "solve "
      "and a full solve, then the sharp lobes refitted on the full map), where vMF EM fits N once; and one "
      "Levenberg–Marquardt "
      "iteration evaluates the residuals and the Jacobian (3 residuals × 7 parameters × the lobes reaching each texel, "
      "up to N) "
      "and solves the normal equations by conjugate gradients (several Jacobian products), where one EM iteration "
      "costs one "
      "exponential per texel and lobe. The per-iteration times above are the measured ratio of that cost. What "
      "the "
      "fit "
      "already does for speed: the first rung is fitted coarse to fine from a 32-texel-wide level, every later rung "
      "only on "
      "the finest level its Jacobian budget allows (the level column), the problem is sparse (one residual block per "
      "8×8-texel "
      "tile, touching only the lobes that reach it) and its residuals and Jacobian are evaluated on the Ceres threads; "
      "every rung has the same iteration cap (60 per solve), which is what is left to trade against the error.\n\n";
  md +=
      "**vMF EM's level and its error against N.** EM is fitted on the finest level whose texel count × N is at most "
      "2^20 "
      "(the exponentials of one EM iteration; the level column), the whole 128 × 64 map at every N here (on a resolved "
      "map, the "
      "sparse map's texels: the reduced map and its full-resolution tiles). A coarser level "
      "(the 64 × 32 level the Ceres fit's dense-Jacobian budget would choose from N = 64 on) puts a sun below a texel "
      "and "
      "caps its lobe's κ by that texel, which more than doubles the sky's map error there. EM "
      "maximises the likelihood of the Ω·(mean RGB)-weighted directions from a fresh k-means++ start at each N, not "
      "the map's "
      "L2 and not from the fit at N/2, so its map error need not fall with N; it rises at: " +
      list(found.vmf_rises, "no N on any environment") + ".\n\n";
  md +=
      "**Map error against diffuse error.** The free-lobe fit minimises the map's L2, which on the sky and sun maps is "
      "dominated by the sun's texel (the floor of the sky and sun rows); the diffuse layer sees only the low "
      "frequencies of the error (the clamped cosine's zonal coefficients beyond L = 2 carry under 1 % of its energy, "
      "Ramamoorthi & Hanrahan 2001), which the L2 objective does not "
      "hold down: a rung can lower the map error while moving error into the low frequencies. Rungs where the map "
      "error "
      "did not rise and the diffuse error did: " +
      list(found.diffuse_rises, "none") +
      ". For diffuse shading the map's L2 is the wrong objective (a diffuse-weighted objective, or the SH projection "
      "at L = 2, "
      "targets it directly: see the sh rows).\n";
  return md;
}

// The CSV (one line per row and layer), the Markdown of every row and of the quadratures' convergence.
void rows_tables(const Result& r, Tables& t, std::string& rows_md, std::string& conv_md) {
  const Options& a = r.options;
  for (const auto& env : r.environments) {
    for (const auto& c : env.convergence)
      conv_md += fmt::format("| {} | {}×{} | {} | {}×{} | {}{} |\n", env.name, env.width, env.height,
                             c.roughness > 0 ? fmt::format("specular α = {}", c.roughness) : std::string("diffuse"),
                             c.subsamples, c.subsamples, num(c.change),
                             c.change <= a.tolerance ? "" : " (**not converged**)");
    for (const auto& row : env.rows) {
      const std::string prefix = fmt::format("{},{},{},{},{},{},{},{:.4f},{}", env.name, env.width, row.basis,
                                             row.variant, row.size_symbol, row.size, row.floats, row.seconds,
                                             row.zero_lobes);
      auto line = [&](const std::string& layer, const std::string& rough, double e) {
        t.csv += fmt::format("{},{},{},{:.6g},{:.1f}\n", prefix, layer, rough, e, row.diffuse_ns);
      };
      line("map", "", row.map_error);
      line("diffuse", "", row.diffuse_error);
      line("diffuse-engine", "", row.engine_diffuse_error);
      for (std::size_t k = 0; k < a.roughness.size(); ++k)
        line("specular", fmt::format("{}", a.roughness[k]), row.specular_error[k]);
      rows_md += fmt::format("| {} | {} | {}={} | {} | {} | {} | {} |", env.name, label(row), row.size_symbol, row.size,
                             row.floats, num(row.map_error), num(row.diffuse_error), num(row.engine_diffuse_error));
      for (double e : row.specular_error) rows_md += fmt::format(" {} |", num(e));
      rows_md += fmt::format(" {:.3f} | {} | {:.0f} |\n", row.seconds, row.zero_lobes, row.diffuse_ns);
    }
  }
}

// The opening: the reduction, the suns, the resolved environments.
std::string opening_markdown(const Result& r) {
  const Options& a = r.options;
  std::string md = "# Environment lighting at equal storage: SH, fixed-lobe SG, vMF EM and free-lobe SG\n\n";
  md += fmt::format("Generated by `{}` ({:.0f} s). ", r.provenance.command, r.seconds);
  md += fmt::format(
      "Every environment (equirectangular, z up: row 0 is +z, φ = 0 is +x at the map's centre column; see README) is "
      "reduced by "
      "solid-angle-weighted 2×2 means to at most {0} texels wide, then represented by every basis at every size; "
      "the x axis of the comparison is the stored float count (SH order L: 3(L+1)²; fixed-lobe SG: 3N; free-lobe SG "
      "and vMF: 6N).\n\n"
      "**Suns and the reduced width.** A texel of a {0}-wide map spans 360/{0} = {1:.2g}°, so a sun smaller than that "
      "(the "
      "sky's 2° disk, the sun map's 0.53° disk of the same power) lies within one texel of the reduced map, held as "
      "that "
      "texel's mean; resolving a sun of diameter d by two texels needs a width ≥ 720/d (360 for the 2° sun, 1359 for "
      "the 0.53° "
      "sun). The width is kept for run time: every doubling quadruples the texel count of the map-error texel means, "
      "of the "
      "converged quadratures and of the representations' quadrature grids.",
      a.width, 360.0 / a.width);
  std::vector<std::string> resolved;
  for (const auto& env : r.environments)
    if (env.full_width > 0)
      resolved.push_back(
          fmt::format("{} ({}×{}: {} tiles of {}×{} texels; relative L2 against the full map {} for the reduced map "
                      "alone, {} with the tiles)",
                      env.name, env.full_width, env.full_height, env.tiles, env.full_width / env.width,
                      env.full_width / env.width, num(env.reduced_l2), num(env.sparse_l2)));
  if (resolved.empty()) {
    md += " No environment is resolved here (`--resolve`): a sun is held as one texel's mean.\n\n";
  } else {
    std::string list;
    for (std::size_t k = 0; k < resolved.size(); ++k) list += (k ? "; " : "") + resolved[k];
    md += fmt::format(
        " **Resolved environments** (`--resolve`, fit/envmap_sparse.cpp) are held at full resolution where the reduced "
        "map "
        "loses detail: the reduced map plus detail tiles, each a reduced texel replaced by the full map's texels "
        "inside it, "
        "added greedily (the largest squared L2 lost first) until the sparse map is within τ = {} relative L2 of the "
        "full map: "
        "{}. On them vmf-em runs its E and M steps and its amplitude solve on the sparse map's texels, sg-free runs "
        "its full-map "
        "steps once more on them (its sharp lobes refitted, then its weakest lobes moved onto the brightest residual "
        "texels, each "
        "kept only if the sparse map's cost falls; the level column's \"+ k tiles\"), sh and sg-fixed are "
        "fitted on the reduced map. Every basis's map error there is against the full map, by the sparse map's "
        "quadrature (the "
        "reduced map's sum plus, per tile, the full-resolution sum minus the reduced texel it replaces; 4×4 points per "
        "texel on "
        "both), and an SG fit's specular is integrated with each lobe convolved with the quadrature's texel (integral "
        "kept) "
        "rather than point-sampled. The diffuse and specular references stay the reduced map's converged quadratures "
        "(a 2×2 "
        "mean keeps every texel's integral). What one lobe per sun can reach: one isotropic Gaussian fitted in L2 to a "
        "uniform "
        "disk leaves relative L2 {} of the disk's own L2 (closed form, independent of the disk's size, derived in "
        "tests/envmap_bases_test.cpp), so a fit that gives a sun one lobe keeps that share of the sun's L2 in its map "
        "error.\n\n",
        a.resolve_tolerance, list, kOneLobeDiskFloor);
  }
  return md;
}

// The bases, the layers and the converged references.
std::string bases_and_layers_markdown(const Options& a) {
  std::string md;
  md += "Bases (fit/envmap_basis*.cpp):\n\n";
  for (const auto& b : fit::envmap_bases()) md += "- `" + b.name + "`: " + b.description + ".\n";
  md += fmt::format(
      "\nLayers: **map** = solid-angle relative L2 of the representation's texel means (4×4 points per texel) against "
      "the map; "
      "**diffuse** = relative L2 over {} Fibonacci normals of the representation's exact diffuse (1/π)∫L⟨ω·n⟩dω (SH: "
      "the "
      "zonal convolution; SG: the exact clamped-cosine integral per lobe) against the map's; **diffuse-engine** = the "
      "same with "
      "the shading an engine runs (SH: the same convolution; SG: `{}`, Hill's fitted irradiance), whose cost is the "
      "ns/pixel "
      "column (single thread, {} normals, this machine: compare ratios); **specular α** = relative L2 over a {}² "
      "sphere (view "
      "+x) of ∫L f_GGX⟨ω·n⟩dω (GGX, height-correlated Smith, Schlick f0 = {}) of the representation against the map's. "
      "SG specular here is the representation integrated by quadrature (what the basis loses), not an SG specular "
      "approximation (those are compared in envmap_lobes.md); SH specular likewise by quadrature of the SH "
      "reconstruction.\n\n",
      a.normals, kEngineDiffuse, a.normals, a.sphere_res, a.f0);
  md += fmt::format(
      "Converged references: the map's diffuse and specular integrals are computed with s × s equal-(θ, φ) sub-texels "
      "per "
      "texel of exact solid angle, s = 1, 2, 4, … until the relative L2 change from s/2 to s is ≤ {} (at most s = {}); "
      "the "
      "representation is integrated on the same nodes (its values at the sub-texel centres). Fit times: wall seconds, "
      "one fit "
      "at a time; the free-lobe rows of one environment are the rungs of one fit at the largest N, each timed from "
      "that fit's "
      "start.\n\n",
      a.tolerance, kMaxSubsamples);
  return md;
}

}  // namespace

Tables tables(const Result& r) {
  const Options& a = r.options;
  Tables t;
  t.csv =
      "environment,width,basis,variant,size_symbol,size,floats,fit_seconds,zero_lobes,layer,roughness,relative_l2,"
      "diffuse_ns_per_pixel\n";
  std::string rows_md, conv_md;
  rows_tables(r, t, rows_md, conv_md);
  std::string md = opening_markdown(r) + bases_and_layers_markdown(a);
  md +=
      "## Quadrature convergence of the map layers\n\n| environment | map | layer | s × s | change from s/2 "
      "|\n|---|---|---|---|---|\n" +
      conv_md;
  md += "\n## Smallest storage reaching the targets\n\n" + targets_markdown(r);
  md += "\n## Free-lobe fit against its own N/2, the best fixed-lobe fit and vMF EM (map error)\n\n" +
        free_lobe_markdown(r);
  md += "\n## All rows (relative L2)\n\n| environment | basis | size | floats | map | diffuse | diffuse-engine |";
  for (double rough : a.roughness) md += fmt::format(" specular α = {} |", rough);
  md += " fit s | zero lobes | diffuse ns/pixel |\n|";
  for (std::size_t k = 0; k < 10 + a.roughness.size(); ++k) md += "---|";
  t.markdown = md + "\n" + rows_md;
  return t;
}

void write(const Result& r) {
  const Tables t = tables(r);
  const std::filesystem::path dir = runner::tables_place(r.options.tables_dir, r.options.out);
  runner::write_table(dir, "envmap_bases", r.provenance, t.markdown, t.csv);
  std::printf("envmap bases: %.1f s; wrote %s/envmap_bases.{md,csv}\n", r.seconds, dir.c_str());
}

}  // namespace sglab::experiments::envmap_bases
