// `sglab`: the command-line front of the toolkit. Parses arguments and calls core/, fit/, the
// runner and the experiments; computes nothing itself.
#include <string>
#include <vector>

#include "run_sglab.hpp"

int main(int argc, char** argv) { return sglab::cli::run_sglab(std::vector<std::string>(argv + 1, argv + argc)); }
