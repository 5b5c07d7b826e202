// The quadrature references of sglab/reference.hpp in 50 digits, compiled once, in
// core/src/quadrature_reference.cpp: the units that evaluate them in mp50 (the registry's reference
// methods, the tests) include this header and link them instead of instantiating tanh-sinh on mp50
// again. (Apart from reference.hpp so that its many other users compile without the 50-digit type.)
#pragma once

#include "sglab/mp50.hpp"
#include "sglab/reference.hpp"

namespace sglab {

extern template mp50 hemispherical_reference<mp50>(const mp50&, const mp50&);
extern template mp50 clamped_cosine_reference<mp50>(const mp50&, const mp50&);

}  // namespace sglab
