// mp50: 50 significant decimal digits (Boost.Multiprecision's cpp_bin_float_50), the "exact
// evaluation of the same formula" against which float and double rounding error is measured.
// Its own header, included only by the units that evaluate, parse or print in 50 digits: the
// multiprecision headers cost about 1.5 CPU s of compilation in every unit that includes them.
#pragma once

#include <type_traits>

#include <boost/multiprecision/cpp_bin_float.hpp>

#include "sglab/scalar.hpp"

namespace sglab {

using mp50 = boost::multiprecision::cpp_bin_float_50;

// (scalar.hpp's is_mp_v, for every Boost.Multiprecision number.)
template <class Backend, boost::multiprecision::expression_template_option Templates>
struct is_mp<boost::multiprecision::number<Backend, Templates>> : std::true_type {};
static_assert(is_mp_v<mp50>, "mp50 must be a multiprecision number to the formulas that branch on is_mp_v");

}  // namespace sglab
