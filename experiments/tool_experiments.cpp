// The experiments whose steps run the general tools of cli/ (`sglab fit`, `sglab render`, `sglab
// envmap`) and the stability atlas: their registry entries and reproduce steps.
#include <string>
#include <utility>
#include <vector>

#include "registry.hpp"

namespace sglab::cli {
void add_stability_command(CLI::App& app, const runner::RunContext& run);  // stability.cpp: `sglab stability`
}  // namespace sglab::cli

namespace sglab::experiments {
Experiment fits_experiment() {
  return {"fits", "`sglab fit`: re-derive every published constant (constants.*), and the λ_d fits under other objectives",
          nullptr, [](const Places& p) {
            std::vector<Step> v = {sglab_step("fit-all", "re-derive every published constant (paper_tables/constants.*)",
                                              {"fit", "all", "--json-dir", p.out + "/fits"}, {}, "--tables-dir")};
            // The other objectives of lambda-d, for the λ_d render sweep (which reads them by path).
            for (const char* objective : {"theta", "hemisphere"})
              v.push_back(sglab_step(std::string("fit-lambda-d-") + objective,
                                     std::string("lambda-d under the l2-") + objective +
                                         " objective (a constant set for the λ_d render sweep)",
                                     {"fit", "lambda-d", "--objective", std::string("l2-") + objective, "--json",
                                      p.out + "/fits-objectives/lambda-d-l2-" + objective + ".json"}));
            return v;
          }};
}

Experiment stability_experiment() {
  return {"stability", "stability atlas: NaN/Inf/negative/>1 % counts and rounding error of every method (stability.*)",
          cli::add_stability_command, [](const Places& p) {
            return std::vector<Step>{
                sglab_step("stability",
                           "stability atlas: NaN/Inf/negative/>1 % counts and rounding error of every method "
                           "(paper_tables/stability.*)",
                           {"stability", "--out", p.out + "/stability"}, {"--quick"}, "--tables", true),
                plot_step("plot-stability", "stability heat map per method, float and double side by side",
                          {"plots/stability_heatmap.py", p.out + "/stability/stability_cells.csv", p.out + "/figures/stability"},
                          {"--quick"})};
          }};
}

// The VSGL renderer on the shipped scenes, and two VSGLs as in Tokuyoshi 2015 (own Gaussian per
// component, λ_d = 2): the receiver's cosine pulled out against the poster's SG cosine with
// A(λ_d) ≈ π (after its Fig. 1).
Experiment renders_experiment() {
  return {"renders", "`sglab render`: the VSGL renderer on the shipped scenes against the exact VPL sum", nullptr,
          [](const Places& p) {
            struct Scene {
              const char* name;
              const char* what;
              int width, height, quick_height;
            };
            static const Scene kScenes[] = {
                {"cornell-glossy", "VSGL renderer: glossy Cornell box, 256×256, two VSGLs vs the exact VPL sum", 256, 256, 64},
                {"diffuse-only", "VSGL renderer: Lambert-only Cornell box (no specular VSGL, no ASG)", 256, 256, 64},
                {"sg-light-near-wall", "VSGL renderer: a spotlight close to a wall (a sharp VSGL)", 256, 192, 48}};
            std::vector<Step> v;
            std::vector<std::string> plot = {"plots/render_images.py", p.key_figures()};
            for (const Scene& s : kScenes) {
              v.push_back(render_step(p, std::string("render-") + s.name, s.what, std::string("scenes/") + s.name + ".json", s.name,
                                      s.width, s.height, {"--width", "64", "--height", std::to_string(s.quick_height)}));
              plot.push_back(p.out + "/renders/" + s.name + ".csv");
            }
            v.push_back(plot_step("plot-renders", "figures of the three renders: VSGL and reference, indirect alone, signed error", plot));
            for (const auto& [name, extra] : std::vector<std::pair<std::string, std::vector<std::string>>>{
                     {"punctual", {"--diffuse", "punctual"}}, {"sg-cosine", {"--diffuse", "sg-cosine", "--sg-cosine-a-pi"}}}) {
              std::vector<std::string> args = {"--vsgl", "two"};
              args.insert(args.end(), extra.begin(), extra.end());
              v.push_back(render_step(p, "render-two-vsgls-" + name, "diffuse-only scene, two VSGLs, diffuse " + name,
                                      "scenes/diffuse-only.json", "two-vsgls-" + name, 192, 192, {"--width", "64", "--height", "64"},
                                      args));
            }
            v.push_back(plot_step("plot-two-vsgls-cosine", "two VSGLs: cosine pulled out vs SG cosine (after Tokuyoshi 2015 Fig. 1)",
                                  {"plots/two_vsgls_cosine.py", p.key_figures(), p.out + "/renders/two-vsgls-punctual.csv",
                                   p.out + "/renders/two-vsgls-sg-cosine.csv"}));
            return v;
          }};
}

// SG environment maps: the three generated environments, the fits and renders against N
// (paper_tables/envmap_lobes.*), and the figures.
Experiment envmap_experiment() {
  return {"envmap", "`sglab envmap`: SG mixture fits of environment maps and shading error against the lobe count (envmap_lobes.*)",
          nullptr, [](const Places& p) {
            std::vector<Step> v;
            std::vector<std::string> lobes = {"envmap", "lobes", "--out", p.out + "/envmap"};
            for (const char* kind : {"sky", "studio", "mixture"}) {
              const std::string path = p.out + "/envmap/" + kind + ".exr";
              v.push_back(sglab_step(std::string("envmap-make-") + kind, std::string("generated environment: ") + kind + " (512×256 EXR)",
                                     {"envmap", "make", kind, "--out", path}));
              lobes.insert(lobes.end(), {"--env", std::string(kind) + "=" + path});
            }
            v.push_back(timed(sglab_step("envmap-lobes", "SG mixture fits and shading error against N (paper_tables/envmap_lobes.*)",
                                         lobes, {"--quick"}, "--tables-dir")));
            v.push_back(plot_step("plot-envmap", "environment error against N, and each map beside its reconstructions",
                                  {"plots/envmap_lobes.py", p.tables + "/envmap_lobes.csv", p.out + "/envmap/envmap_images.csv",
                                   p.key_figures()}));
            return v;
          }};
}

}  // namespace sglab::experiments
