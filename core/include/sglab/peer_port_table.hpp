// The naive peer ports (peer_ports.hpp) by name, for the units that time them against sglab's batch
// evaluators (`sglab error-vs-time`, benchmarks/core_bench.cpp). The table is compiled in
// core/src/peer_ports.cpp, so that a unit that only looks a port up does not include the published
// formulas' headers, and an edit of a method's formula recompiles that one small unit, not the
// experiments that time it (docs/testing.md, "Rebuilding after a method's header").
#pragma once

#include <cstddef>
#include <span>
#include <string_view>

namespace sglab::peer {

struct Port {
  std::string_view quantity, method;
  void (*batch_float)(const float*, float*, std::size_t);
  void (*batch_double)(const double*, double*, std::size_t);
};

// Every port, in the order of the table.
std::span<const Port> ports();

// The naive port of `quantity/method`, or nullptr if there is none.
const Port* find_port(std::string_view quantity, std::string_view method);

}  // namespace sglab::peer
