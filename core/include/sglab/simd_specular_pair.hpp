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

// The rows as columns (structure of arrays): the receivers' (a surface point and its view:
// roughness, view_cos; `receivers` values each) and the lights' (light_sharpness, and the light's
// unit axis ξ in the receiver's frame: light_cos = ξ·n, axis_t = ξ·t and axis_b = ξ·b, t being the
// tangent at azimuth 0, towards the view; one value per row, row j·receivers + g being light j at
// receiver g). The kernel takes ξ = (axis_t, axis_b, light_cos clamped to [−1, 1]) as given: no
// angle, no sine, cosine or square root of the azimuth (the scalar template's ξ for light_cos c and
// azimuth φ is (s·cos φ, s·sin φ, c), s = √(1 − c²): specular_input.hpp specular_light_axis).
// Read without transposition, so the columns need no gathering; each receiver's part of the method
// (`_receiver` in specular.hpp: the warped NDF lobe, ωo) is computed once for all its lights.
struct SpecularPairColumns {
  std::size_t receivers;
  const double *roughness, *view_cos;                           // per receiver
  const double *light_sharpness, *light_cos, *axis_t, *axis_b;  // per row
};
// Evaluates lights × rows.receivers rows into at_f0_zero and at_f0_one (one value each per row).
using SpecularPairColumnsFn =
    std::function<void(const SpecularPairColumns& rows, std::size_t lights, double* at_f0_zero, double* at_f0_one)>;
// The column evaluator of `method`, for the same methods as specular_pair_evaluator (empty for the
// others). Its values are the pair evaluator's with the light's axis the given one instead of the
// one it forms from light_cos and φ: for the scalar template's axis, the pair kernel's values to its
// tolerance; and each row's value does not depend on the other rows (how many lights share its
// receiver).
SpecularPairColumnsFn specular_pair_columns_evaluator(const Method& method);

}  // namespace sglab::simd
