// `sglab`: the command-line front of the toolkit. Parses arguments and calls core/, fit/ and the
// experiments; computes nothing itself.
#include <cstdio>
#include <exception>

#include "commands.hpp"

namespace sglab::cli {
// One line per sub-command (defined in its own file).
}  // namespace sglab::cli

int main(int argc, char** argv) {
  CLI::App app{"sglab: spherical Gaussian lighting research toolkit"};
  app.require_subcommand(1);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const sglab::cli::UsageError& e) {
    std::fprintf(stderr, "sglab: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sglab: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
