// Compiling and running exported code (docs/export.md): GLSL and HLSL through glslang (the
// library; HLSL by its HLSL front end) to SPIR-V, validated by SPIRV-Tools and run as a
// compute shader on the Vulkan harness; C through the system C compiler as a shared library,
// loaded with dlopen. Each exported function is wrapped in a small entry point that evaluates it
// on every row of a float buffer.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "emit.hpp"
#include "vulkan_compute.hpp"

namespace sglab::shader {

// A compute shader for `m`: entry point "main", 64 invocations a group, row i of the input
// buffer (m.inputs.size() floats) → output i. `exported` is emit()'s source holding m.
std::string compute_shader_source(const std::string& exported, const TracedMethod& m, Language lang);

struct Spirv {
  std::vector<std::uint32_t> words;
  // Instructions inside the module's functions (OpFunction … OpFunctionEnd), as glslang emits
  // them unoptimized (its HLSL front end inlines every call into main).
  std::size_t function_instructions = 0;
};

// glslang (as `glslangValidator -V --target-env vulkan1.1`, HLSL: `-D -e main -S comp`) then
// SPIRV-Tools' validator (spirv-val's checks), both in-process. std::runtime_error with their
// messages when either fails.
Spirv compile_to_spirv(const std::string& shader_source, Language lang);

// The instructions of the exported method and its helpers in a module compile_to_spirv made
// from compute_shader_source: the module's function instructions less those of the same entry
// point around a function that returns its first argument. A cost proxy, not a cycle count.
std::size_t method_instructions(const Spirv& spirv, Language lang, std::size_t arity);

// Runs the compiled shader on `rows` (arity floats each) on `gpu`: one result per row.
std::vector<float> run_compute(VulkanCompute& gpu, const Spirv& spirv, std::span<const float> rows, std::size_t arity);

// Compiles the C source (cc -std=c99 -O2, no fast-math) as a shared library with an entry
// evaluating `m` per row, loads it, and evaluates `rows`. std::runtime_error on failure.
std::vector<float> run_c(const std::string& exported, const TracedMethod& m, std::span<const float> rows);

}  // namespace sglab::shader
