// The registry's vectorized `specular` methods evaluated at Fresnel f0 = 0 and f0 = 1 in one pass
// (docs/simd.md). Every `specular` method depends on f0 only through Schlick's Fresnel factor,
// which is linear in f0, so a caller shading many f0 values (the VSGL renderer, one per pixel)
// evaluates each row once and mixes v(f0) = v(0) + f0·(v(1) − v(0)). Each of the two results is,
// bit for bit, the method's batch_double at that f0; the pass costs about one evaluation, since
// everything before the Fresnel factor is computed once.
#pragma once

#include <cstddef>
#include <functional>
#include <span>

#include "sglab/registry.hpp"

namespace sglab::simd {

// The columns of a row: the `specular` columns without f0 (roughness, light_sharpness, light_cos,
// view_cos, light_azimuth).
inline constexpr std::size_t kSpecularPairArity = 5;

// Evaluates args.size() / kSpecularPairArity rows into at_f0_zero and at_f0_one (one value each
// per row; both at least that long).
using SpecularPairFn =
    std::function<void(std::span<const double> args, std::span<double> at_f0_zero, std::span<double> at_f0_one)>;

// The pair evaluator of `method` when it is one of the registry's own vectorized `specular` methods
// (the object find_quantity("specular") holds, with its published constants); empty otherwise
// (a bound method, a method without a vector kernel): the caller then evaluates batch_double at
// f0 = 0 and f0 = 1. Each call runs on the instruction set active then (active_isa()).
SpecularPairFn specular_pair_evaluator(const Method& method);

}  // namespace sglab::simd
