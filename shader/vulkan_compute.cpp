// The Vulkan compute harness (vulkan_compute.hpp): plain Vulkan 1.1, one queue, host-visible
// coherent storage buffers, one dispatch per run.
#include "vulkan_compute.hpp"

#include <algorithm>
#include <cstring>
#include <functional>
#include <stdexcept>

#include <fmt/core.h>
#include <vulkan/vulkan.h>

namespace sglab::shader {
namespace {

void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw std::runtime_error(fmt::format("Vulkan: {} failed (VkResult {})", what, int(r)));
}

// A zeroed Vulkan info structure of type `type`.
template <class Info>
Info info(VkStructureType type) {
  Info x{};
  x.sType = type;
  return x;
}

}  // namespace

struct VulkanCompute::State {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  std::uint32_t family = 0;
  std::string name;

  std::uint32_t memory_type(std::uint32_t bits, VkMemoryPropertyFlags want) const {
    VkPhysicalDeviceMemoryProperties props;
    vkGetPhysicalDeviceMemoryProperties(physical, &props);
    for (std::uint32_t i = 0; i < props.memoryTypeCount; ++i)
      if ((bits & (1u << i)) && (props.memoryTypes[i].propertyFlags & want) == want) return i;
    throw std::runtime_error("Vulkan: no host-visible coherent memory type");
  }
};

// A storage buffer with its host-visible memory, destroyed with the device's handles.
struct Buffer {
  VkDevice device;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;
  Buffer(const VulkanCompute::State& s, VkDeviceSize bytes) : device(s.device) {
    auto bi = info<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
    bi.size = bytes;
    bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    check(vkCreateBuffer(device, &bi, nullptr, &buffer), "vkCreateBuffer");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device, buffer, &req);
    auto ai = info<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = s.memory_type(req.memoryTypeBits,
                                       VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    check(vkAllocateMemory(device, &ai, nullptr, &memory), "vkAllocateMemory");
    check(vkBindBufferMemory(device, buffer, memory, 0), "vkBindBufferMemory");
    check(vkMapMemory(device, memory, 0, bytes, 0, &mapped), "vkMapMemory");
  }
  ~Buffer() {
    if (mapped) vkUnmapMemory(device, memory);
    vkDestroyBuffer(device, buffer, nullptr);
    vkFreeMemory(device, memory, nullptr);
  }
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
};

VulkanCompute::VulkanCompute() : s_(std::make_unique<State>()) {
  auto app = info<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
  app.pApplicationName = "sglab";
  app.apiVersion = VK_API_VERSION_1_1;
  auto ici = info<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
  ici.pApplicationInfo = &app;
  check(vkCreateInstance(&ici, nullptr, &s_->instance), "vkCreateInstance");
  std::uint32_t count = 0;
  vkEnumeratePhysicalDevices(s_->instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(s_->instance, &count, devices.data());
  // A CPU implementation first (the measurements name lavapipe), then any device.
  for (int pass = 0; pass < 2 && !s_->physical; ++pass)
    for (VkPhysicalDevice d : devices) {
      VkPhysicalDeviceProperties props;
      vkGetPhysicalDeviceProperties(d, &props);
      if (pass == 0 && props.deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU) continue;
      std::uint32_t nf = 0;
      vkGetPhysicalDeviceQueueFamilyProperties(d, &nf, nullptr);
      std::vector<VkQueueFamilyProperties> families(nf);
      vkGetPhysicalDeviceQueueFamilyProperties(d, &nf, families.data());
      for (std::uint32_t f = 0; f < nf; ++f)
        if (families[f].queueFlags & VK_QUEUE_COMPUTE_BIT) {
          s_->physical = d;
          s_->family = f;
          s_->name = fmt::format("{} (driver {}.{}.{})", props.deviceName, VK_VERSION_MAJOR(props.driverVersion),
                                 VK_VERSION_MINOR(props.driverVersion), VK_VERSION_PATCH(props.driverVersion));
          break;
        }
      if (s_->physical) break;
    }
  if (!s_->physical) {
    vkDestroyInstance(s_->instance, nullptr);
    throw std::runtime_error("Vulkan: no device with a compute queue (install mesa-vulkan-drivers for lavapipe)");
  }
  const float priority = 1;
  auto qi = info<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
  qi.queueFamilyIndex = s_->family;
  qi.queueCount = 1;
  qi.pQueuePriorities = &priority;
  auto dci = info<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qi;
  if (VkResult r = vkCreateDevice(s_->physical, &dci, nullptr, &s_->device); r != VK_SUCCESS) {
    vkDestroyInstance(s_->instance, nullptr);
    check(r, "vkCreateDevice");
  }
  vkGetDeviceQueue(s_->device, s_->family, 0, &s_->queue);
}

VulkanCompute::~VulkanCompute() {
  vkDestroyDevice(s_->device, nullptr);
  vkDestroyInstance(s_->instance, nullptr);
}

const std::string& VulkanCompute::device_name() const { return s_->name; }

std::vector<float> VulkanCompute::run(std::span<const std::uint32_t> spirv, std::span<const float> input,
                                      std::uint32_t groups) {
  const VkDevice dev = s_->device;
  const std::size_t outputs = std::size_t(groups) * 64;
  Buffer in(*s_, std::max<std::size_t>(input.size_bytes(), 4));
  Buffer out(*s_, outputs * sizeof(float));
  std::memcpy(in.mapped, input.data(), input.size_bytes());

  // Every handle below is destroyed at the end of the run, also when a step throws.
  VkShaderModule module = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkCommandPool commands = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  struct Cleanup {
    std::function<void()> f;
    ~Cleanup() { f(); }
  } cleanup{[&] {
    vkDestroyFence(dev, fence, nullptr);
    vkDestroyCommandPool(dev, commands, nullptr);
    vkDestroyDescriptorPool(dev, pool, nullptr);
    vkDestroyPipeline(dev, pipeline, nullptr);
    vkDestroyPipelineLayout(dev, layout, nullptr);
    vkDestroyDescriptorSetLayout(dev, set_layout, nullptr);
    vkDestroyShaderModule(dev, module, nullptr);
  }};

  auto mi = info<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
  mi.codeSize = spirv.size_bytes();
  mi.pCode = spirv.data();
  check(vkCreateShaderModule(dev, &mi, nullptr, &module), "vkCreateShaderModule");

  VkDescriptorSetLayoutBinding bindings[2] = {};
  for (std::uint32_t b = 0; b < 2; ++b) {
    bindings[b].binding = b;
    bindings[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    bindings[b].descriptorCount = 1;
    bindings[b].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  auto li = info<VkDescriptorSetLayoutCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
  li.bindingCount = 2;
  li.pBindings = bindings;
  check(vkCreateDescriptorSetLayout(dev, &li, nullptr, &set_layout), "vkCreateDescriptorSetLayout");
  auto pli = info<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
  pli.setLayoutCount = 1;
  pli.pSetLayouts = &set_layout;
  check(vkCreatePipelineLayout(dev, &pli, nullptr, &layout), "vkCreatePipelineLayout");
  auto ci = info<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
  ci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  ci.stage.module = module;
  ci.stage.pName = "main";
  ci.layout = layout;
  check(vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline), "vkCreateComputePipelines");

  VkDescriptorPoolSize ps{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2};
  auto dpi = info<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  dpi.maxSets = 1;
  dpi.poolSizeCount = 1;
  dpi.pPoolSizes = &ps;
  check(vkCreateDescriptorPool(dev, &dpi, nullptr, &pool), "vkCreateDescriptorPool");
  auto dai = info<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
  dai.descriptorPool = pool;
  dai.descriptorSetCount = 1;
  dai.pSetLayouts = &set_layout;
  VkDescriptorSet set;
  check(vkAllocateDescriptorSets(dev, &dai, &set), "vkAllocateDescriptorSets");
  VkDescriptorBufferInfo infos[2] = {{in.buffer, 0, VK_WHOLE_SIZE}, {out.buffer, 0, VK_WHOLE_SIZE}};
  VkWriteDescriptorSet writes[2] = {};
  for (int b = 0; b < 2; ++b) {
    writes[b].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[b].dstSet = set;
    writes[b].dstBinding = std::uint32_t(b);
    writes[b].descriptorCount = 1;
    writes[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[b].pBufferInfo = &infos[b];
  }
  vkUpdateDescriptorSets(dev, 2, writes, 0, nullptr);

  auto cpi = info<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  cpi.queueFamilyIndex = s_->family;
  check(vkCreateCommandPool(dev, &cpi, nullptr, &commands), "vkCreateCommandPool");
  auto cai = info<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  cai.commandPool = commands;
  cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cai.commandBufferCount = 1;
  VkCommandBuffer cmd;
  check(vkAllocateCommandBuffers(dev, &cai, &cmd), "vkAllocateCommandBuffers");
  auto bi = info<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &set, 0, nullptr);
  vkCmdDispatch(cmd, groups, 1, 1);
  // The shader's writes made visible to the host's read of the mapped memory.
  auto barrier = info<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0,
                       nullptr, 0, nullptr);
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  auto fi = info<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
  check(vkCreateFence(dev, &fi, nullptr, &fence), "vkCreateFence");
  auto si = info<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  check(vkQueueSubmit(s_->queue, 1, &si, fence), "vkQueueSubmit");
  check(vkWaitForFences(dev, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  std::vector<float> result(outputs);
  std::memcpy(result.data(), out.mapped, outputs * sizeof(float));
  return result;
}

bool vulkan_available() {
  try {
    VulkanCompute v;
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace sglab::shader
