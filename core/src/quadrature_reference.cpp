// The double and mp50 instantiations of the quadrature references (sglab/reference.hpp and
// sglab/reference_mp50.hpp declare them extern), compiled once instead of in every unit that calls them.
#include "sglab/reference_mp50.hpp"

namespace sglab {

template double hemispherical_reference<double>(const double&, const double&);
template mp50 hemispherical_reference<mp50>(const mp50&, const mp50&);
template double clamped_cosine_reference<double>(const double&, const double&);
template mp50 clamped_cosine_reference<mp50>(const mp50&, const mp50&);

}  // namespace sglab
