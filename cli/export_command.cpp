// `sglab export QUANTITY/METHOD… --lang glsl|hlsl|c [--constants SET] [--out FILE]`: the methods'
// formulas as self-contained source (the emitter is shader/emit.hpp; docs/export.md). Every
// method is looked up and traced, and the constant set read, before anything is written.
#include <algorithm>
#include <cstddef>
#include <iostream>
#include <memory>

#include <fmt/core.h>
#include <fmt/ranges.h>

#include "atomic_file.hpp"
#include "commands.hpp"
#include "constant_sets.hpp"
#include "emit.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::cli {
namespace {

struct ExportOptions {
  std::vector<std::string> methods;
  std::string lang;
  std::string out;
  frontend::Constants constants;
  bool list = false;
};

void run_export(const ExportOptions& o, const std::string& command) {
  if (o.list) {
    for (const auto& name : shader::exportable_methods()) std::cout << name << '\n';
    return;
  }
  if (o.methods.empty()) throw runner::InputError("export: name at least one QUANTITY/METHOD (`sglab export --list`)");
  if (o.lang.empty()) throw runner::InputError("export: --lang is required (glsl, hlsl or c)");
  const shader::Language lang = *shader::parse_language(o.lang);  // checked by CLI11
  if (!o.out.empty()) {
    std::vector<runner::NamedPath> inputs;
    for (const auto& c : o.constants.paths) inputs.push_back({"--constants", c});
    runner::check_output_paths({{"--out", o.out}}, inputs);
  }
  const ConstantSet& set = o.constants.set;
  std::vector<shader::TracedMethod> traced;
  traced.reserve(o.methods.size());
  for (std::size_t i = 0; i < o.methods.size(); ++i) {
    const std::string& name = o.methods[i];
    // The same method twice would define its function twice: a source that does not compile.
    if (std::find(o.methods.begin(), o.methods.begin() + std::ptrdiff_t(i), name) !=
        o.methods.begin() + std::ptrdiff_t(i))
      throw runner::InputError(fmt::format("export: {} is given twice", quote(name)));
    const shader::MethodRef ref = shader::find_exportable(name);
    traced.push_back(shader::trace_method(*ref.quantity, *ref.method, set));
  }
  const std::string source = shader::emit(traced, lang, command);
  if (o.out.empty()) std::cout << source << std::flush;
  else runner::write_file_atomically(o.out, source);
}

}  // namespace

void add_export_command(CLI::App& app) {
  auto opts = std::make_shared<ExportOptions>();
  auto* sub = app.add_subcommand(
      "export", "A method's formula as GLSL, HLSL or C (float; constants as literals with their provenance)");
  sub->add_option(
      "methods", opts->methods,
      fmt::format("QUANTITY/METHOD, one or more; exportable: {}", fmt::join(shader::exportable_methods(), ", ")));
  sub->add_option("--lang", opts->lang, "glsl, hlsl or c")->check(CLI::IsMember(shader::language_names()));
  sub->add_option("--out", opts->out, "write the source to FILE (default: standard output)");
  frontend::add_constants_option(*sub, opts->constants);
  sub->add_flag("--list", opts->list, "list the exportable methods");
  sub->callback([opts] {
    std::string command = "sglab export";
    for (const auto& m : opts->methods) command += " " + m;
    if (!opts->lang.empty()) command += " --lang " + opts->lang;
    for (const auto& a : frontend::constants_arguments(opts->constants)) command += " " + a;
    run_export(*opts, command);
  });
}

}  // namespace sglab::cli
