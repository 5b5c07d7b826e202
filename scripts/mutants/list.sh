# The mutants of scripts/mutants.sh: mutant ID FILE SED-SCRIPT TEST...
# Each is one small, plausible edit of main's code (a constant mistyped, a switch point moved, a
# factor dropped or doubled, a check loosened) and the tests that own the edited code: the test
# executable of the module (optionally a gtest filter), or a CTest test for the Python module.
# The sed script must change exactly the line(s) it names; the report says "not applied" otherwise.
# Removed as equivalent (no output can change), with the reason:
#  - `if (!ok || i != s.size())` → `if (!ok)` in runner/parse_number.cpp: from_chars_checked refuses
#    every text it does not consume whole, so a grammar that stops early is refused there (with
#    the same message); NumberGrammar.RefusedTextsNameTheReason holds either way.
# Removed with the code they edited: simd-sglab-t, simd-t2024-tail, simd-sg-integral and simd-expm1-series mutated the
# hand-written diffuse kernels, which are now the formulas' own templates on SIMD lanes (their
# mutants above reach the lanes through simd_test); the series' lane form has its own two mutants.
# Replaced: simd-asg-nu (ν = λ/2 mistyped in the hand-written `specular/asg` kernel) by asg-nu, the
# same edit of the template, which that kernel now is on SIMD lanes (simd_specular.hpp).
# Replaced: cli-unknown-command-status edited the first `return 2;` of cli/app.cpp, which became
# the refusal of a bad --results/--tables when those were taken off the command line ahead of the
# command (its owning tests never reach it: it survived); it now anchors on the unknown-command
# message, and cli-places-status edits the places' refusal.
# Replaced: sg-product-scale once changed the constant kProductScaleSharpness itself, which a
# static_assert in core/render/src/simd/render_dispatch.cpp pins to its SIMD copy (the build
# fails: no test runs); it now moves the switch of product_sharpness alone.

# ---- core formulas and constants (core/include/sglab) -------------------------------------------
mutant hill-c0 core/include/sglab/clamped_cosine.hpp 's#c0 = 0\.36;#c0 = 0.3636;#' \
  clamped_cosine_test registry_test
mutant i0-switch-up core/include/sglab/asg_integral.hpp 's#const V threshold = -log(V(epsilon<T>()));#const V threshold = -10 * log(V(epsilon<T>()));#' \
  asg_test registry_test
mutant i0-switch-down core/include/sglab/asg_integral.hpp 's#const V threshold = -log(V(epsilon<T>()));#const V threshold = -log(V(epsilon<T>())) / 10;#' \
  asg_test registry_test
mutant cc-bounds-series-switch core/include/sglab/clamped_cosine.hpp 's#const auto below_one = value_of(l) < 1;#const auto below_one = value_of(l) < 10;#' \
  clamped_cosine_test
mutant t2022-alpha-switch core/include/sglab/clamped_cosine.hpp 's#abs(value_of(lambda)) < 0\.5,#abs(value_of(lambda)) < 0.0005,#' \
  clamped_cosine_test
mutant t2024-D-digits core/include/sglab/clamped_cosine.hpp 's#D = 15\.219156263147211;#D = 15.291156263147211;#' \
  clamped_cosine_test
mutant t2024-large-switch core/include/sglab/clamped_cosine.hpp 's#value_of(l) > 1e4,#value_of(l) > 1e14,#' \
  clamped_cosine_test hardening_test:HardeningNumerics.*
mutant meder-offset core/include/sglab/clamped_cosine_meder.hpp 's#offset = 31\.7003;#offset = 31.7030;#' \
  clamped_cosine_test hemispherical_test
mutant meder-p2 core/include/sglab/hemispherical_meder.hpp 's#p2 = 10\.8438;#p2 = 10.4838;#' \
  hemispherical_test clamped_cosine_test
mutant asg-nu core/include/sglab/asg.hpp 's#const T nu = sharpness / T(2);#const T nu = sharpness / T(4);#' \
  asg_test specular_test
mutant sg-integral-2l core/include/sglab/sg.hpp 's#return T(2) \* two_pi<T>() \* expm1_over_x(x, em);#return two_pi<T>() * expm1_over_x(x, em);#' \
  sg_test
mutant sg-log-amplitude core/include/sglab/sg.hpp 's#return T(-2) \* sharpness1 \* sharpness2 \* (T(1) - c) / denom;#return T(-2) * sharpness1 * sharpness2 * (T(1.01) - c) / denom;#' \
  sg_test
mutant sg-product-scale core/include/sglab/sg.hpp '/^T product_sharpness(/,/^}/ s#value_of(s) > kProductScaleSharpness#value_of(s) > 1e30#' \
  sg_test hardening_test:HardeningNumerics.*
mutant expm1-series core/include/sglab/scalar.hpp 's#return T(1) + x \* (T(0\.5) + x \* (T(1) / T(6) + x \* (T(1) / T(24))));#return T(1) + x * (T(0.5) + x * (T(1) / T(6) + x * (T(1) / T(12))));#' \
  sg_test clamped_cosine_test simd_test
mutant glossy-theta-node-pole core/include/sglab/sphere_quadrature.hpp 's#t\.pole_factor = pole_factor_(2 \* t\.sin_half \* t\.sin_half);#t.pole_factor = pole_factor_(t.sin_half * t.sin_half);#' \
  glossy_reference_test
mutant glossy-theta-node-bound core/include/sglab/sphere_quadrature.hpp 's#if (found == panels_\.end() && panels_\.size() < kMaxThetaPanels)#if (found == panels_.end())#' \
  glossy_reference_test
mutant glossy-rule-at-once-order core/include/sglab/sphere_quadrature.hpp 's#for (unsigned i = 1; i < abscissa\.size(); i += 2, k += 2) kronrod += (fx\[k\] + fx\[k + 1\]) \* weight\[i\];#for (unsigned i = 1; i < abscissa.size(); i += 2, k += 2) kronrod += fx[k] * weight[i] + fx[k + 1] * weight[i];#' \
  glossy_reference_test
mutant gndf-grazing-light-pole core/include/sglab/gaussian_ndf.hpp 's#const auto light = \[lambda\](double one_minus_cos) { return std::exp(-lambda \* one_minus_cos); };#const auto light = [lambda](double one_minus_cos) { return std::exp(-0.5 * lambda * one_minus_cos); };#' \
  gaussian_ndf_test hardening_extremes_test

# ---- SIMD kernels (core/src/simd, core/render/src/simd) ----------------------------------------
mutant hill-c1 core/include/sglab/clamped_cosine.hpp 's#const T c1 = T(1) / (T(4) \* c0);#const T c1 = T(1) / (T(2) * c0);#' \
  clamped_cosine_test simd_test
mutant simd-series-coefficient core/src/simd/simd_kernels.hpp 's#inner\[n\] = T(double(n) / factorial(n + 1));#inner[n] = T(double(n + 1) / factorial(n + 1));#' \
  simd_test
mutant simd-series-terms core/src/simd/simd_kernels.hpp 's#kSeriesTerms = sizeof(T) == 4 ? 13 : 20;#kSeriesTerms = sizeof(T) == 4 ? 13 : 9;#' \
  simd_test
mutant simd-erfc-saturation core/src/simd/simd_math.hpp 's#T(26\.54) : T(9\.19)#T(26.54) : T(3.19)#' \
  simd_test simd_specular_test
mutant simd-exp-c4 core/src/simd/simd_exp.hpp 's#c4(0x1\.55555cf172b91p-5)#c4(0x1.55555cf172b91p-4)#' \
  simd_test:Simd.ExpBatch*
mutant render-ggx-ndf core/render/src/simd/render_kernels_vpl.hpp 's#a2 / (T(kPi) \* dn \* dn)#a2 / (T(kPi) * dn)#' \
  render_test vsgl_shading_test
mutant render-vpl-clamp core/render/src/simd/render_kernels_vpl.hpp 's#const T k = T(1) / (d2 + a\.r2\[i\]);#const T k = T(1) / (d2 + 2 * a.r2[i]);#' \
  render_test vsgl_shading_test
mutant render-float-sin2 core/render/src/simd/render_kernels_vpl.hpp 's#if constexpr (std::is_same_v<T, float>) {#if constexpr (std::is_same_v<T, void>) {#' \
  render_precision_test
mutant render-vpl-skip core/render/src/simd/render_kernels_vpl.hpp 's#        any = any | h\.on;#        any = g.on;#' \
  render_precision_test
mutant render-env-skip core/render/src/simd/render_kernels.hpp 's#if constexpr (kTwo) above = above | (p2\.nx#if constexpr (kTwo) above = above \&\& (p2.nx#' \
  envmap_test

# ---- renderer (core/render/src) ------------------------------------------------------------------
mutant vsgl-diffuse-pi core/render/src/vsgl_shading.cpp 's#sum \* points\[i\]\.diffuse_reflectance / pi<double>()#sum * points[i].diffuse_reflectance / two_pi<double>()#' \
  vsgl_shading_test
mutant rsm-spot-falloff core/render/src/rsm.cpp 's#w \* (0\.5 - t \* t \* t + 0\.5 \* t \* t \* t \* t)#w * (0.5 - t * t + 0.5 * t * t * t * t)#' \
  render_test
mutant camera-fov core/render/src/raycast.cpp 's#std::tan(0\.5 \* camera\.vertical_fov)#std::tan(camera.vertical_fov)#' \
  raycast_test
mutant vsgl-gen-variance core/render/src/vsgl_generation.cpp 's#std::log(two_pi<double>() \* p\.variance)#std::log(pi<double>() * p.variance)#' \
  vsgl_generation_test vsgl_shading_test

# ---- filtering (core/include/sglab/filtering_weights.hpp, core/render/src/filtering.cpp) -------
mutant lobe-beta-twice core/include/sglab/filtering_weights.hpp 's#return exp(detail::sg_lobe_log_weight(one_minus_cosine, li, lj, beta));#return exp(detail::sg_lobe_log_weight(one_minus_cosine, li, lj, T(beta * beta)));#' \
  filtering_weights_test
mutant sigma-n2-kappa core/include/sglab/filtering_weights.hpp 's#return (T(1) / lambda_c + T(2) / kappa) / beta;#return (T(1) / lambda_c + T(1) / kappa) / beta;#' \
  filtering_weights_test fit_test
mutant smoothed-sharpness core/include/sglab/filtering_weights.hpp 's#const T s = T(1) / (T(1) / sharpness + T(1) / kappa);#const T s = T(1) / (T(1) / sharpness + T(2) / kappa);#' \
  filtering_weights_test
mutant filter-depth-sigma core/render/src/filtering.cpp 's#const double sz = a\.depth_sigma \* p\.depth;#const double sz = a.depth_sigma;#' \
  filtering_test
mutant filter-radius-bound core/render/src/filtering.cpp 's#p\.radius > 16)#p.radius > 64)#' \
  filtering_test filter_command_test
mutant filter-positional-dimension core/render/src/filtering.cpp 's#a\.beta, 3);#a.beta, 2);#' \
  filtering_test

# ---- fits (fit/) ---------------------------------------------------------------------------------
mutant fit-grid-weights fit/grid2d.cpp 's#std::sqrt(qc\.w\[i\] / n_lambda)#std::sqrt(qc.w[i] * l / n_lambda)#' \
  fit_test
mutant fit-lambda-d-target fit/lambda_d.cpp 's#std::max(t, 0\.0) / pi<double>()#std::max(t, 0.0) / 3.1416#' \
  fit_test
mutant fit-hill-domain fit/hill_irradiance.cpp '/kClampedCosineTarget,/,/{1, 100, 20}/ s#{1, 100, 20}}#{1, 100, 10}}#' \
  fit_test
mutant fit-float-roundoff fit/driver.cpp 's#std::ldexp(1\.0, -24)#std::ldexp(1.0, -23)#' \
  fit_test
mutant fit-lambda-c-similarity fit/lambda_c.cpp 's#(kPi - phi) \* std::cos(phi)#(kPi + phi) * std::cos(phi)#' \
  fit_test

# ---- runner (runner/) ----------------------------------------------------------------------------
mutant parse-plus-sign runner/parse_number.cpp "s#^  if (s\\[i\\] == '+' || s\\[i\\] == '-') ++i;#  if (s[i] == '-') ++i;#" \
  parser_fuzz_test
mutant parse-trim-tab runner/parse_number.cpp 's#const auto first = s\.find_first_not_of(" \\t");#const auto first = s.find_first_not_of(" ");#' \
  parser_fuzz_test
mutant parse-subnormal runner/parse_number.cpp 's#std::fabs(value) < std::numeric_limits<F>::min()#std::fabs(value) < std::numeric_limits<F>::denorm_min()#' \
  parser_fuzz_test
mutant csv-quote-needs runner/csv.cpp 's#find_first_of(",\\"\\r\\n")#find_first_of(",\\r\\n")#' \
  sweep_test parser_fuzz_test eval_command_test:EvalCommand.ExtraColumns*
mutant csv-crlf runner/csv.cpp "s#if (at(i_) == '\\\\r') ++i_;#;#" \
  sweep_test parser_fuzz_test eval_command_test
mutant atomic-signal-unlink runner/fatal_signal.cpp 's#if (slot\.state\.load() == 2) ::unlink(slot\.path);#if (slot.state.load() == 3) ::unlink(slot.path);#' \
  hardening_test:Hardening.Group07*
mutant signal-ends-child-groups runner/fatal_signal.cpp 's#    if (slot\.state\.load() == 2) {#    if (slot.state.load() == 3) {#' \
  reproduce_test:PlotServerEnd.*
mutant sweep-resume runner/sweep.cpp 's#if (!run\.done\[j\]) run\.todo\.push_back(j);#run.todo.push_back(j);#' \
  sweep_test
mutant merge-manifest-digits runner/sweep_merge.cpp 's#digits(rest\.substr(0, of)) && digits(rest\.substr(of + 4))#digits(rest.substr(0, of))#' \
  sweep_test:SweepTest.Merge*

# ---- CLI (cli/) ----------------------------------------------------------------------------------
mutant cli-places-status cli/app.cpp '/run = take_places(args, given);/,/return 2;/ s#return 2;#return 1;#' \
  reproduce_command_test:ReproduceCommand.PlacesBeforeTheCommandSteerWhereItWrites
mutant cli-unknown-command-status cli/app.cpp '/unknown command/,/return 2;/ s#return 2;#return 1;#' \
  eval_command_test hardening_test:Hardening.*
mutant cli-parse-error-status cli/app.cpp 's#return status == 0 ? 0 : 2;#return status == 0 ? 0 : 1;#' \
  eval_command_test hardening_test:Hardening.*
mutant cli-eval-default-precision cli/eval_command.cpp 's#std::string precision = "double";#std::string precision = "float";#' \
  eval_command_test

# ---- Python bindings (python/sglab_module.cpp, eval_binding.cpp) -----------------------------------------------
mutant py-broadcast python/eval_binding.cpp 's#if (++idx\[d\] < shape\[d\]) break;#if (++idx[d] <= shape[d]) break;#' \
  build:sglab_python build:sglab 'ctest:^python_sglab'
mutant py-reference-flag python/sglab_module.cpp 's#py::arg("reference") = (m\.name == q\.reference_method)#py::arg("reference") = (m.name != q.reference_method)#' \
  build:sglab_python build:sglab 'ctest:^python_sglab'

# ---- code added since the list was first written: denoising, environment bases, shader export,
# the own specular method, the plot queue's process groups ----------------------------------------
mutant denoise-box-footprint core/render/src/denoise.cpp 's#std::abs(d) == radius ? 0\.5 : 1\.0#std::abs(d) == radius ? 1.0 : 1.0#' \
  denoise_test:DenoiseFilter.*
mutant denoise-subset-weight core/render/src/denoise.cpp 's#const double weight = double(subsets);#const double weight = double(m);#' \
  denoise_test:NoisyInput.Interleaved*
mutant denoise-random-count core/render/src/denoise.cpp 's#1 / (double(count) \* sampler\.pdf\[i\] / sampler\.cdf\.back())#1 / (sampler.pdf[i] / sampler.cdf.back())#' \
  denoise_test:NoisyInput.*
mutant envmap-sh-diffuse-pi fit/envmap_basis.cpp 's#const double a = sh_clamped_cosine_band<double>(l) / M_PI;#const double a = sh_clamped_cosine_band<double>(l) / (2 * M_PI);#' \
  envmap_bases_test:Sh.*
mutant envmap-sg-fixed-sharpness fit/envmap_basis_sg_fixed.cpp 's#return 0\.5 \* n \* std::log(2\.0);#return n * std::log(2.0);#' \
  envmap_bases_test:SgFixed.*
mutant envmap-sg-product-2r fit/envmap_basis_sg_fixed.cpp 's#-std::expm1(-2 \* r) / r#-std::expm1(-r) / r#' \
  envmap_bases_test:SgFixed.*
mutant shader-expm1-switch shader/emit.cpp 's#return abs(x) > 0\.5f ? e : s;#return abs(x) > 5.0f ? e : s;#' \
  shader_export_test:ShaderExport.EveryMethod*
mutant specular-sglab-t-power core/include/sglab/specular_sglab.hpp 's#const T half_inv_nu = T(0\.5) + inv_nu;#const T half_inv_nu = T(1) + inv_nu;#' \
  specular_sglab_test
mutant plot-server-own-group experiments/plot_queue.cpp 's#POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK#POSIX_SPAWN_SETSIGMASK#' \
  reproduce_test:PlotServerEnd.*
mutant env-maps-same-nodes core/render/src/environment_shading.cpp 's#\[\](const Node& a, const Node& b) { return a\.texel == b\.texel; }#[](const Node\&, const Node\&) { return true; }#' \
  envmap_test:EnvMapQuadrature.SpecularOfMany*
mutant env-maps-tail-lane core/render/src/simd/render_kernels.hpp 's#for (std::size_t c = 0; c < C; ++c) s\[i\]\[c\]\[0\] += wk \* a\.channel\[c\]\[k\];#for (std::size_t c = 0; c < C; ++c) s[i][c][1] += wk * a.channel[c][k];#' \
  envmap_test:EnvMapQuadrature.SpecularOfMany*
mutant vmf-estep-row-sum fit/envmap_vmf_em.cpp 's#r < rows; ++r) z\[r\] += e\[r \* n + j\];#r < rows; ++r) z[r] += e[j];#' \
  envmap_bases_test:VmfEm.*
mutant envmap-level-cost-texel fit/envmap.cpp 's#blurred_exponent(rate\[j\], level\.dirs\[t\]\.dot(m\[j\]\.axis))#blurred_exponent(rate[j], level.dirs[t0].dot(m[j].axis))#' \
  envmap_bases_test:SgFree.* envmap_sparse_test envmap_test:EnvMapFit.*
mutant render-schlick-upper-end core/render/src/simd/render_table.hpp 's#cos_oh > 1 ? f0 + T(0) : inside#cos_oh > 1 ? f0 : inside#' \
  render_precision_test:RenderKernels.*
mutant render-method-scale-row core/render/src/simd/render_kernels_shading.hpp 's#\*sj = rows\.scale + r0, \*vj#*sj = rows.scale + k0, *vj#' \
  vsgl_specular_methods_test
mutant vsgl-scale-for-method core/render/src/vsgl_shading.cpp 's#if (pass\.any_diffuse || (d\.options\.specular \&\& d\.options\.specular_method)) pass\.scale();#if (pass.any_diffuse) pass.scale();#' \
  vsgl_specular_methods_test
mutant render-method-axis-tangent core/render/src/simd/render_kernels_shading.hpp 's#at\[g\] = dot3(x, y, z, tx\[g\], ty\[g\], tz\[g\]);#at[g] = dot3(x, y, z, bx[g], by[g], bz[g]);#' \
  vsgl_specular_methods_test
