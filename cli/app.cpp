// The `sglab` app: every command on one CLI11 app, and run_sglab, which runs one command line
// in-process (main.cpp, `sglab reproduce`, and the tests that parse every reproduce step).
#include <algorithm>
#include <cstdio>
#include <exception>
#include <new>
#include <utility>

#include "commands.hpp"
#include "parse_number.hpp"
#include "registry.hpp"
#include "sglab/simd.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::cli {

// One line per general tool (each defined in its own file; `sweep` and `envmap` register the
// experiments grouped under them), then every other registered experiment's own command; the help
// ends with the registry's experiments.
void add_all_commands(CLI::App& app, const runner::RunContext& run) {
  add_eval_command(app);
  add_fit_command(app, run);
  add_reproduce_command(app);
  add_render_command(app);
  add_sweep_command(app, run);
  add_merge_command(app);
  add_filter_command(app);
  add_envmap_command(app, run);
  add_export_command(app);
  experiments::add_experiment_commands(app, "", run);
  std::string footer = "\nExperiments (`sglab reproduce` runs each; `sglab reproduce --list` shows the steps):\n";
  for (const auto& e : experiments::experiment_registry()) {
    footer += "  " + e.name + std::string(e.name.size() < 16 ? 16 - e.name.size() : 1, ' ') + e.summary + "\n";
  }
  app.footer(footer);
}

// Every real-valued option of every command (CLI11's type name "FLOAT") is first read as a strict
// decimal (runner::parse_decimal, as the numbers of every input file): "1e400", "1e-400", "1e-310",
// "nan", "inf" and "0x1p-3" are refused quoting the text as typed. CLI11's own conversion (strtod)
// makes them inf, 0, a subnormal, NaN or 0.125, which a command's range check then named by the
// parsed value ("--tolerance inf must be in (0, 1)"). Checked once here for all commands, so an
// option added later is covered too; the commands' range checks see only finite normal doubles.
void require_decimal_reals(CLI::App& app) {
  for (CLI::Option* opt : app.get_options([](const CLI::Option* o) { return o->get_type_name() == "FLOAT"; }))
    opt->check(CLI::Validator(
        [](std::string& text) -> std::string {
          try {
            (void)runner::parse_decimal<double>(text);
            return {};
          } catch (const runner::NumberError& e) {
            return quote(text) + " " + e.what();
          }
        },
        ""));
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) require_decimal_reals(*sub);
}

namespace {

// The run's places from the options before the command (`sglab --results DIR --tables DIR
// COMMAND …`, or OPTION=DIR), taken off the front of `args`: the rest is the command line.
runner::RunContext take_places(std::vector<std::string>& args, runner::RunContext run) {
  std::size_t i = 0;
  for (; i < args.size(); ++i) {
    std::string* place = nullptr;
    std::string value;
    for (const auto& [option, field] :
         {std::pair{runner::kResultsOption, &run.places.out}, std::pair{runner::kTablesOption, &run.places.tables}}) {
      const std::string name(option);
      if (args[i] == name && i + 1 < args.size()) {
        place = field;
        value = args[++i];
      } else if (args[i].rfind(name + "=", 0) == 0) {
        place = field;
        value = args[i].substr(name.size() + 1);
      }
      if (place) {
        if (value.empty() || value[0] == '-')
          throw runner::InputError(name + " " + quote(value) + ": expected a directory");
        break;
      }
    }
    if (!place) break;
    *place = value;
  }
  args.erase(args.begin(), args.begin() + static_cast<std::ptrdiff_t>(i));
  return run;
}

}  // namespace

int run_sglab(std::vector<std::string> args, const runner::RunContext& given) {
  runner::RunContext run;
  try {
    run = take_places(args, given);
    run.command = runner::command_line(run.places, args);
  } catch (const runner::InputError& e) {
    std::fprintf(stderr, "sglab: error: %s\n", bounded_message(e.what()).c_str());
    return 2;
  }
  CLI::App app{"sglab: spherical Gaussian lighting research toolkit"};
  app.require_subcommand(1);
  // Shown by --help; taken off the command line by take_places before the app parses it.
  std::string shown;
  app.add_option(std::string(runner::kResultsOption), shown,
                 "before the command: every output directory under DIR (the command's --out defaults to "
                 "DIR/ITS_DIR; default: " +
                     runner::Places{}.out + ")");
  app.add_option(std::string(runner::kTablesOption), shown,
                 "before the command: every table into DIR (default: beside the command's other outputs)");
  add_all_commands(app, run);
  require_decimal_reals(app);
  // CLI11's own messages quote the bad value whole ("--width: Value … could not be converted").
  app.failure_message(
      [](const CLI::App* a, const CLI::Error& e) { return bounded_message(CLI::FailureMessage::simple(a, e)); });
  // CLI11 would report an unknown command as "A subcommand is required".
  std::string names;
  bool known = false;
  for (const auto* sub : app.get_subcommands([](CLI::App*) { return true; })) {
    names += (names.empty() ? "" : ", ") + sub->get_name();
    known = known || (!args.empty() && sub->check_name(args.front()));
  }
  if (!args.empty() && !args.front().empty() && args.front()[0] != '-' && !known) {
    std::fprintf(stderr, "sglab: error: unknown command '%s' (commands: %s)\n", clip_text(args.front()).c_str(),
                 names.c_str());
    return 2;
  }
  try {
    (void)simd::active_isa();  // a bad SGLAB_SIMD is bad input: refused before any work
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "sglab: error: %s\n", bounded_message(e.what()).c_str());
    return 2;
  } catch (const std::runtime_error& e) {  // no kernel of this build runs on this CPU
    std::fprintf(stderr, "sglab: error: %s\n", e.what());
    return 1;
  }
  try {
    std::reverse(args.begin(), args.end());  // CLI11 takes the vector form last-argument-first
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every parse error is bad usage: exit status 2 (CLI11's own
    // codes, 104–109, would say nothing the message does not).
    const int status = app.exit(e);
    return status == 0 ? 0 : 2;
  } catch (const runner::InputError& e) {
    std::fprintf(stderr, "sglab: error: %s\n", bounded_message(e.what()).c_str());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "sglab: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sglab: error: %s\n", bounded_message(e.what()).c_str());
    return 1;
  }
  return 0;
}

}  // namespace sglab::cli
