// The experiments whose steps run only general tools of cli/ (`sglab fit`, `sglab render`): their
// registry entries and reproduce steps.
#include <string>
#include <utility>
#include <vector>

#include "fit_all.hpp"
#include "registry.hpp"

namespace sglab::experiments {
Experiment fits_experiment() {
  return {
      "fits", "`sglab fit`: re-derive every published constant (constants.*), and the λ_d fits under other objectives",
      nullptr, [](const runner::Places& p) {
        // The records go to the run's fits' directory, which the later steps read (--constants).
        std::vector<Step> v = {sglab_step("fit-all", "re-derive every published constant (paper_tables/constants.*)",
                                          {"fit", "all", "--json-dir", p.dir(fit_all::kDir)}, {"--quick"})};
        // The other objectives of lambda-d, for the λ_d render sweep (which reads them by path).
        for (const char* objective : {"theta", "hemisphere"})
          v.push_back(sglab_step(std::string("fit-lambda-d-") + objective,
                                 std::string("lambda-d under the l2-") + objective +
                                     " objective (a constant set for the λ_d render sweep)",
                                 {"fit", "lambda-d", "--objective", std::string("l2-") + objective, "--json",
                                  p.dir(fit_all::kObjectivesDir) + "/lambda-d-l2-" + objective + ".json"}));
        return v;
      }};
}

// The VSGL renderer on the shipped scenes, and two VSGLs as in Tokuyoshi 2015 (own Gaussian per
// component, λ_d = 2): the receiver's cosine pulled out against the poster's SG cosine with
// A(λ_d) ≈ π (after its Fig. 1).
Experiment renders_experiment() {
  return {
      "renders", "`sglab render`: the VSGL renderer on the shipped scenes against the exact VPL sum", nullptr,
      [](const runner::Places& p) {
        struct Scene {
          const char* name;
          const char* what;
          int width, height, quick_height;
        };
        static const Scene kScenes[] = {
            {"cornell-glossy", "VSGL renderer: glossy Cornell box, 256×256, two VSGLs vs the exact VPL sum", 256, 256,
             64},
            {"diffuse-only", "VSGL renderer: Lambert-only Cornell box (no specular VSGL, no ASG)", 256, 256, 64},
            {"sg-light-near-wall", "VSGL renderer: a spotlight close to a wall (a sharp VSGL)", 256, 192, 48}};
        std::vector<Step> v;
        std::vector<std::string> plot = {"plots/render_images.py", p.key_figures()};
        for (const Scene& s : kScenes) {
          v.push_back(render_step(p, std::string("render-") + s.name, s.what, std::string("scenes/") + s.name + ".json",
                                  s.name, s.width, s.height,
                                  {"--width", "64", "--height", std::to_string(s.quick_height)}));
          plot.push_back(p.dir(kRendersDir) + "/" + s.name + ".csv");
        }
        v.push_back(plot_step("plot-renders",
                              "figures of the three renders: VSGL and reference, indirect alone, signed error", plot));
        for (const auto& [name, extra] : std::vector<std::pair<std::string, std::vector<std::string>>>{
                 {"punctual", {"--diffuse", "punctual"}},
                 {"sg-cosine", {"--diffuse", "sg-cosine", "--sg-cosine-a-pi"}}}) {
          std::vector<std::string> args = {"--vsgl", "two"};
          args.insert(args.end(), extra.begin(), extra.end());
          v.push_back(render_step(p, "render-two-vsgls-" + name, "diffuse-only scene, two VSGLs, diffuse " + name,
                                  "scenes/diffuse-only.json", "two-vsgls-" + name, 192, 192,
                                  {"--width", "64", "--height", "64"}, args));
        }
        v.push_back(plot_step(
            "plot-two-vsgls-cosine", "two VSGLs: cosine pulled out vs SG cosine (after Tokuyoshi 2015 Fig. 1)",
            {"plots/two_vsgls_cosine.py", p.key_figures(), p.dir(kRendersDir) + "/two-vsgls-punctual.csv",
             p.dir(kRendersDir) + "/two-vsgls-sg-cosine.csv"}));
        return v;
      }};
}

}  // namespace sglab::experiments
