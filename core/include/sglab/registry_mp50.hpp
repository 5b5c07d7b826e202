// The registry's 50-digit evaluators (registry.hpp Mp50Evaluator): included by the units that
// register methods (set_evaluators, make_method…) or evaluate them in mp50 (eval_as<mp50>,
// m.eval_mp50(args)); the others compile without Boost.Multiprecision.
#pragma once

#include <span>

#include "sglab/mp50.hpp"
#include "sglab/registry.hpp"

namespace sglab {

struct Mp50Function {
  MethodFn<mp50> fn;
};

}  // namespace sglab
