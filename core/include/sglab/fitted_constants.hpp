// A method's fitted constants, written once as a list LIST(X) of X(name, value) lines and read
// three times: SGLAB_FITTED_CONSTANTS(Constants, Params, LIST) defines the struct Constants of static
// constexpr doubles (Constants::name, the values as the fit printed them) with the list itself as
// Constants::all (each name as text and its value, in the list's order: what its fit names and
// starts from), and the aggregate template Params<T> of the same names as values of T (the fitter
// passes Jets, the SIMD kernels lanes), whose fitted() is Constants' values converted to T.
#pragma once

namespace sglab {
// One entry of a Constants::all list.
struct FittedConstant {
  const char* name;
  double value;
};
}  // namespace sglab

#define SGLAB_FITTED_CONSTANT(name, value) static constexpr double name = value;
#define SGLAB_FITTED_ENTRY(name, value) ::sglab::FittedConstant{#name, value},
#define SGLAB_FITTED_MEMBER(name, value) T name;
#define SGLAB_FITTED_AS_T(name, value) T(value),
#define SGLAB_FITTED_CONSTANTS(Constants, Params, LIST)                          \
  struct Constants {                                                             \
    LIST(SGLAB_FITTED_CONSTANT)                                                  \
    static constexpr ::sglab::FittedConstant all[] = {LIST(SGLAB_FITTED_ENTRY)}; \
  };                                                                             \
  template <class T>                                                             \
  struct Params {                                                                \
    LIST(SGLAB_FITTED_MEMBER)                                                    \
    static Params fitted() { return {LIST(SGLAB_FITTED_AS_T)}; }                 \
  };
