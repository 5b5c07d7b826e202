// The native half of the Python module `sglab` (sglab._sglab; python/sglab/__init__.py is the
// documented interface and calls these). Everything goes through the code the `sglab` command
// runs: the method registry and its row checks (registry.hpp: row_error), the number parser of
// `sglab eval` (parse_number.hpp), the constant sets of `--constants` (constant_sets.hpp: read by
// load_constant_sets, applied by sglab::bind), the fitters and their JSON record
// (fit_record.hpp), and the scene loading, options and stats of `sglab render` (render_job.hpp).
// The evaluation is eval_binding.cpp's (module_parts.hpp declares what this file calls).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "input_error.hpp"
#include "constant_sets.hpp"
#include "driver.hpp"
#include "parse_number.hpp"
#include "fit_record.hpp"
#include "record.hpp"
#include "environment_render.hpp"
#include "render_job.hpp"
#include "sglab/render/vsgl_generation.hpp"
#include "sglab/render/vsgl_specular_methods.hpp"
#include "sglab/registry.hpp"
#include "sglab/simd.hpp"
#include "module_parts.hpp"

namespace py = pybind11;

namespace sglab::python {
namespace {

// ---- registry ------------------------------------------------------------------------------

std::string joined_names(const auto& items) {
  std::vector<std::string> names;
  for (const auto& x : items) names.push_back(x.name);
  return fmt::format("{}", fmt::join(names, ", "));
}

}  // namespace

const Quantity& quantity_named(const std::string& name) {
  if (const Quantity* q = find_quantity(name)) return *q;
  throw py::value_error(fmt::format("unknown quantity '{}'; valid quantities: {}", name, joined_names(quantities())));
}

const Method& method_named(const Quantity& q, const std::string& name) {
  if (const Method* m = q.find(name)) return *m;
  throw py::value_error(
      fmt::format("unknown method '{}' for quantity '{}'; valid methods: {}", name, q.name, joined_names(q.methods)));
}

namespace {

py::list quantities_list() {
  py::list out;
  for (const auto& q : quantities()) {
    py::list columns;
    for (const auto& c : q.columns)
      columns.append(py::dict(py::arg("name") = c.name, py::arg("kind") = std::string(column_kind_name(c.kind)),
                              py::arg("description") = c.description));
    py::list methods;
    for (const auto& m : q.methods) methods.append(m.name);
    out.append(py::dict(py::arg("name") = q.name, py::arg("description") = q.description, py::arg("columns") = columns,
                        py::arg("reference_method") = q.reference_method, py::arg("methods") = methods));
  }
  return out;
}

py::list methods_list(const std::string& quantity) {
  const Quantity& q = quantity_named(quantity);
  py::list out;
  for (const auto& m : q.methods) {
    py::dict d(py::arg("name") = m.name, py::arg("source") = m.source, py::arg("flaws") = m.flaws,
               py::arg("may_be_negative") = m.may_be_negative, py::arg("has_domain_check") = bool(m.domain_error),
               py::arg("reference") = (m.name == q.reference_method));
    // Its constants, with the fields of `sglab eval --list --json`.
    py::list parameters;
    for (const auto& p : m.parameters)
      parameters.append(py::dict(py::arg("name") = p.name, py::arg("fit") = p.fit, py::arg("published") = p.published,
                                 py::arg("source") = p.source));
    d["parameters"] = parameters;
    out.append(std::move(d));
  }
  return out;
}

// ---- fits ----------------------------------------------------------------------------------

py::list fits_list() {
  py::list out;
  for (const auto& f : fit::fitters())
    out.append(py::dict(py::arg("name") = f.name, py::arg("description") = f.description,
                        py::arg("objectives") = f.objectives));
  return out;
}

// The fit's JSON record (`sglab fit NAME --json FILE`), as text.
std::string run_fit(const std::string& name, const std::string& objective, const std::string& precision) {
  const fit::Fitter* f = fit::find_fitter(name);
  if (!f) throw py::value_error(fmt::format("unknown fit '{}'; fits: {}", name, joined_names(fit::fitters())));
  const fit::FitOptions o = fit::checked_options(*f, objective, precision);
  fit::FitResult r;
  {
    py::gil_scoped_release release;
    r = f->run(o);
  }
  return sglab::frontend::fit_record_json(r, sglab::frontend::judge(*f, r), o.precision).dump();
}

// ---- render --------------------------------------------------------------------------------

// An (height, width, 3) float64 array over the layer's own memory (moved, not copied).
py::array layer_array(std::vector<render::Rgb>&& layer, int width, int height) {
  static_assert(sizeof(render::Rgb) == 3 * sizeof(double), "Rgb must be three packed doubles");
  auto* owned = new std::vector<render::Rgb>(std::move(layer));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<render::Rgb>*>(p); });
  return py::array_t<double>({py::ssize_t(height), py::ssize_t(width), py::ssize_t(3)},
                             reinterpret_cast<const double*>(owned->data()), free_when_done);
}

// `sglab render SCENE WORDS…` into numpy arrays: WORDS are the command's own options (--vsgl …,
// --set …, --specular …), parsed by the very CLI11 options of `sglab render`, so that Python takes
// exactly what the command takes and refuses (ValueError) what it refuses. `scene` is a path, or
// the scene's JSON text when `is_text` (`source` names it in messages; an environment's relative
// paths are taken from the working directory then). Progress on stderr only when `verbose`.
py::dict run_render(const std::string& scene_text, bool is_text, const std::string& source,
                    const std::vector<std::string>& words, bool verbose) {
  sglab::frontend::RenderJob job;
  std::string specular(render::kDefaultSpecularMethod);
  {
    CLI::App app{"sglab.render"};
    sglab::frontend::add_render_job_options(app, job);
    sglab::frontend::add_specular_option(app, specular);
    std::vector<std::string> reversed(words.rbegin(), words.rend());  // CLI11 takes the vector last-argument-first
    try {
      app.parse(reversed);
    } catch (const CLI::ParseError& e) {
      throw py::value_error(fmt::format("sglab.render: {}", e.what()));
    }
  }
  job.scene_path = source;
  render::Scene scene = is_text ? sglab::frontend::scene_from_document(
                                      sglab::frontend::scene_document_from_text(scene_text, source, job.overrides), job)
                                : sglab::frontend::load_scene(job);
  sglab::frontend::RenderJobRun run(job, specular, std::move(scene));
  std::vector<std::string> args = sglab::frontend::render_job_arguments(job);
  if (specular != render::kDefaultSpecularMethod) args.insert(args.end(), {"--specular", specular});
  const std::string command = fmt::format("sglab.render({}{}) (as `sglab render` {})",
                                          is_text ? "a scene dict" : "'" + source + "'", args.empty() ? "" : ", …",
                                          fmt::join(args, " "));
  if (verbose)
    run.options.progress = [](std::string_view stage, double fraction) {
      if (fraction == 0 || fraction == 1)
        std::fprintf(stderr, "sglab.render: %.*s %s\n", int(stage.size()), stage.data(), fraction == 0 ? "…" : "done");
    };
  sglab::frontend::RenderJobRun::Output r;
  {
    py::gil_scoped_release release;
    r = run.run(command);
  }
  py::dict out;
  const int w = r.result.width, h = r.result.height;
  for (auto& layer : r.layers) out[py::str(layer.name)] = layer_array(std::move(layer.pixels), w, h);
  py::array_t<bool> hit({py::ssize_t(h), py::ssize_t(w)});
  std::transform(r.result.hit.begin(), r.result.hit.end(), hit.mutable_data(), [](char c) { return c != 0; });
  out["hit"] = hit;
  out["stats"] = py::module_::import("json").attr("loads")(r.stats.dump());
  if (verbose) std::fprintf(stderr, "sglab.render: %s\n", command.c_str());
  return out;
}

}  // namespace
}  // namespace sglab::python

PYBIND11_MODULE(_sglab, m) {
  using namespace sglab::python;
  m.doc() = "Native part of the sglab module; use the documented functions of `sglab`.";
  // Bad input from the library's front-end helpers (scene fields, render options, fit names).
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const sglab::runner::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const sglab::runner::NumberError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  m.def("quantities", &quantities_list);
  m.def("methods", &methods_list, py::arg("quantity"));
  m.def("eval_float", &eval_numeric<float>, py::arg("quantity"), py::arg("method"), py::arg("columns"),
        py::arg("constants"), py::arg("vectorized"));
  m.def("eval_double", &eval_numeric<double>, py::arg("quantity"), py::arg("method"), py::arg("columns"),
        py::arg("constants"), py::arg("vectorized"));
  m.def("eval_mp50", &eval_mp50, py::arg("quantity"), py::arg("method"), py::arg("columns"), py::arg("shape"),
        py::arg("constants"));
  m.def("fits", &fits_list);
  m.def("fit", &run_fit, py::arg("name"), py::arg("objective"), py::arg("precision"));
  m.def("vsgl_modes", &sglab::render::vsgl_mode_names);
  m.def("render", &run_render, py::arg("scene"), py::arg("is_text"), py::arg("source"), py::arg("words"),
        py::arg("verbose"));
  // The options of `sglab render` (the words run_render parses): Python's render() and its stub
  // are checked against this list.
  m.def("render_options", [] {
    CLI::App app;
    sglab::frontend::RenderJob job;
    std::string specular;
    sglab::frontend::add_render_job_options(app, job);
    sglab::frontend::add_specular_option(app, specular);
    py::list names;
    for (const CLI::Option* o : app.get_options())
      if (!o->get_lnames().empty() && o->get_lnames().front() != "help") names.append(o->get_lnames().front());
    return names;
  });
}
