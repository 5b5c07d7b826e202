// Library calls on a command's input: the library refuses a value outside a function's domain with
// std::invalid_argument (its message naming the value); a command reports it as bad input.
#pragma once

#include <stdexcept>
#include <utility>

#include "input_error.hpp"

namespace sglab::runner {

// f(), with a std::invalid_argument from the library (a value outside a function's domain, its
// message naming the value) raised as InputError.
template <class F>
decltype(auto) input_checked(F&& f) {
  try {
    return std::forward<F>(f)();
  } catch (const std::invalid_argument& e) {
    throw InputError(e.what());
  }
}

}  // namespace sglab::runner
