// A small Vulkan compute harness (libvulkan): runs one SPIR-V compute shader over a float buffer on
// a real Vulkan implementation — Mesa's lavapipe (llvmpipe) on a machine without a GPU, which is
// what the tests and the shader-export table use. The shader's contract: entry point "main",
// local size 64, descriptor set 0 binding 0 the input floats, binding 1 the output floats, one
// output per invocation.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace sglab::shader {

class VulkanCompute {
 public:
  // Creates an instance and a device on a CPU implementation (lavapipe) if there is one, else on
  // the first device with a compute queue. std::runtime_error when there is none.
  VulkanCompute();
  ~VulkanCompute();
  VulkanCompute(const VulkanCompute&) = delete;
  VulkanCompute& operator=(const VulkanCompute&) = delete;

  // "llvmpipe (LLVM 15.0.6, 256 bits)" and the driver's version, as the device reports them.
  const std::string& device_name() const;

  // Runs `spirv` with `groups` workgroups of 64 invocations; `input` is the input buffer, the
  // output has groups·64 floats.
  std::vector<float> run(std::span<const std::uint32_t> spirv, std::span<const float> input, std::uint32_t groups);

  struct State;  // the instance, device and queue (vulkan_compute.cpp)

 private:
  std::unique_ptr<State> s_;
};

// Whether a Vulkan device with a compute queue is available (for tests that skip without one).
bool vulkan_available();

}  // namespace sglab::shader
