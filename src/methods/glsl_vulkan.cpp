#include "methods/glsl_vulkan.h"

#include <fmt/core.h>
#include <glslang/Include/glslang_c_interface.h>
#include <glslang/Public/resource_limits_c.h>
#include <vulkan/vulkan.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <mutex>
#include <sstream>

#include "methods/glsl_source.h"

namespace rayproof::glsl {

namespace {

constexpr const char* kNoDevice =
    "no Vulkan device: install a Vulkan driver (on Debian: mesa-vulkan-drivers, whose lavapipe runs Vulkan on the "
    "CPU; or your GPU's driver) and the loader (libvulkan1; libvulkan-dev to build rayproof); `vulkaninfo --summary` "
    "(vulkan-tools) shows what the loader finds";

/// Cases per dispatch at most: 65536 cases, 8 MB of double inputs.
constexpr std::size_t kMaxCases = 65536;

std::string version(std::uint32_t v) {
  return fmt::format("{}.{}.{}", VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v), VK_API_VERSION_PATCH(v));
}

std::string type_name(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    default: return "other";
  }
}

std::string vk_error(const char* what, VkResult r) { return fmt::format("Vulkan: {} failed (VkResult {})", what, int(r)); }

/// An instance (Vulkan 1.2 where the loader has it) or a message.
std::variant<VkInstance, std::string> make_instance() {
  std::uint32_t loader = VK_API_VERSION_1_0;
  auto enum_version = reinterpret_cast<PFN_vkEnumerateInstanceVersion>(
      vkGetInstanceProcAddr(nullptr, "vkEnumerateInstanceVersion"));
  if (enum_version) (void)enum_version(&loader);
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "rayproof";
  app.apiVersion = loader >= VK_API_VERSION_1_2 ? VK_API_VERSION_1_2 : loader;
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  VkInstance inst = VK_NULL_HANDLE;
  const VkResult r = vkCreateInstance(&ci, nullptr, &inst);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER) return std::string(kNoDevice);
  if (r != VK_SUCCESS) return vk_error("vkCreateInstance", r) + "; " + kNoDevice;
  return inst;
}

DeviceInfo read_info(VkPhysicalDevice pd) {
  DeviceInfo info;
  VkPhysicalDeviceProperties props{};
  vkGetPhysicalDeviceProperties(pd, &props);
  info.name = props.deviceName;
  info.type = type_name(props.deviceType);
  info.api = version(props.apiVersion);
  info.driver = fmt::format("driver version {:#x}", props.driverVersion);
  if (props.apiVersion >= VK_API_VERSION_1_2) {
    VkPhysicalDeviceDriverProperties drv{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceFloatControlsProperties fc{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FLOAT_CONTROLS_PROPERTIES};
    drv.pNext = &fc;
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    p2.pNext = &drv;
    vkGetPhysicalDeviceProperties2(pd, &p2);
    info.driver = fmt::format("{} {}", drv.driverName, drv.driverInfo);
    info.float_controls = true;
    info.denorm_preserve32 = fc.shaderDenormPreserveFloat32;
    info.denorm_flush32 = fc.shaderDenormFlushToZeroFloat32;
    info.denorm_preserve64 = fc.shaderDenormPreserveFloat64;
    info.denorm_flush64 = fc.shaderDenormFlushToZeroFloat64;
  }
  VkPhysicalDeviceFeatures feats{};
  vkGetPhysicalDeviceFeatures(pd, &feats);
  info.float64 = feats.shaderFloat64;
  return info;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance inst) {
  std::uint32_t n = 0;
  if (vkEnumeratePhysicalDevices(inst, &n, nullptr) != VK_SUCCESS) return {};
  std::vector<VkPhysicalDevice> out(n);
  if (vkEnumeratePhysicalDevices(inst, &n, out.data()) < 0) return {};
  out.resize(n);
  return out;
}

std::string device_list(const std::vector<VkPhysicalDevice>& pds) {
  std::string s;
  for (std::size_t i = 0; i < pds.size(); ++i) s += fmt::format("\n  {}: {}", i, read_info(pds[i]).describe());
  return s;
}

std::variant<std::vector<std::uint32_t>, std::string> compile(const std::string& source, io::Kind k, Precision p) {
  static std::once_flag once;
  std::call_once(once, [] { glslang_initialize_process(); });
  glslang_input_t in{};
  in.language = GLSLANG_SOURCE_GLSL;
  in.stage = GLSLANG_STAGE_COMPUTE;
  in.client = GLSLANG_CLIENT_VULKAN;
  in.client_version = GLSLANG_TARGET_VULKAN_1_1;
  in.target_language = GLSLANG_TARGET_SPV;
  in.target_language_version = GLSLANG_TARGET_SPV_1_3;
  in.code = source.c_str();
  in.default_version = 450;
  in.default_profile = GLSLANG_NO_PROFILE;
  in.messages = static_cast<glslang_messages_t>(GLSLANG_MSG_DEFAULT_BIT | GLSLANG_MSG_SPV_RULES_BIT |
                                                GLSLANG_MSG_VULKAN_RULES_BIT);
  in.resource = glslang_default_resource();
  glslang_shader_t* sh = glslang_shader_create(&in);
  std::variant<std::vector<std::uint32_t>, std::string> out;
  auto log = [](const char* text) {
    // glslang's log: "ERROR: FILE:LINE: 'x' : message" lines, then a count; keep the lines that say what.
    std::string s, all = text ? text : "";
    for (std::size_t pos = 0; pos < all.size();) {
      const std::size_t end = std::min(all.find('\n', pos), all.size());
      std::string line = all.substr(pos, end - pos);
      pos = end + 1;
      if (line.empty() || line.find("compilation errors.") != std::string::npos) continue;
      if (line.rfind("ERROR: ", 0) == 0) line = line.substr(7) ;
      s += line + "\n";
    }
    return s;
  };
  if (!glslang_shader_preprocess(sh, &in) || !glslang_shader_parse(sh, &in)) {
    out = explain_compile_error(log(glslang_shader_get_info_log(sh)), k, p);
    glslang_shader_delete(sh);
    return out;
  }
  glslang_program_t* prog = glslang_program_create();
  glslang_program_add_shader(prog, sh);
  if (!glslang_program_link(prog, in.messages)) {
    out = explain_compile_error(log(glslang_program_get_info_log(prog)), k, p);
  } else {
    glslang_program_SPIRV_generate(prog, GLSLANG_STAGE_COMPUTE);
    std::vector<std::uint32_t> words(glslang_program_SPIRV_get_size(prog));
    glslang_program_SPIRV_get(prog, words.data());
    out = std::move(words);
  }
  glslang_program_delete(prog);
  glslang_shader_delete(sh);
  return out;
}

}  // namespace

std::string DeviceInfo::describe() const { return fmt::format("{} ({}; driver {}; Vulkan {})", name, type, driver, api); }

std::string DeviceInfo::subnormals(Precision p) const {
  const char* what = p == Precision::float32 ? "float" : "double";
  if (!float_controls) return fmt::format("subnormal {}s: the device does not say (no Vulkan 1.2 float controls)", what);
  const bool keep = p == Precision::float32 ? denorm_preserve32 : denorm_preserve64;
  const bool flush = p == Precision::float32 ? denorm_flush32 : denorm_flush64;
  if (keep && flush) return fmt::format("subnormal {}s: the device can preserve or flush them; the shader asks for neither", what);
  if (keep) return fmt::format("subnormal {}s: the device can preserve them; the shader does not ask, so it may flush them", what);
  if (flush) return fmt::format("subnormal {}s: the device can flush them to zero, and may", what);
  return fmt::format("subnormal {}s: may be flushed (the device promises neither preserving nor flushing them)", what);
}

std::variant<std::vector<std::string>, std::string> list_devices() {
  auto inst = make_instance();
  if (auto* why = std::get_if<std::string>(&inst)) return *why;
  const VkInstance vi = std::get<VkInstance>(inst);
  std::vector<std::string> out;
  const auto pds = physical_devices(vi);
  for (std::size_t i = 0; i < pds.size(); ++i) out.push_back(fmt::format("{}: {}", i, read_info(pds[i]).describe()));
  vkDestroyInstance(vi, nullptr);
  if (out.empty()) return std::string(kNoDevice);
  return out;
}

struct Buffer {
  VkBuffer buf = VK_NULL_HANDLE;
  VkDeviceMemory mem = VK_NULL_HANDLE;
  void* map = nullptr;
  VkDeviceSize size = 0;
};

struct Runner::Impl {
  RunnerSpec spec;
  DeviceInfo info;
  std::vector<io::Kind> kinds;
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  std::uint32_t family = 0;
  Buffer in, out;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkDescriptorSet set = VK_NULL_HANDLE;
  std::array<VkShaderModule, 6> modules{};
  std::array<VkPipeline, 6> pipelines{};
  VkCommandPool cmd_pool = VK_NULL_HANDLE;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  bool lost = false;

  ~Impl() {
    if (device) {
      if (!lost) vkDeviceWaitIdle(device);
      if (fence) vkDestroyFence(device, fence, nullptr);
      if (cmd_pool) vkDestroyCommandPool(device, cmd_pool, nullptr);
      for (auto p : pipelines)
        if (p) vkDestroyPipeline(device, p, nullptr);
      for (auto m : modules)
        if (m) vkDestroyShaderModule(device, m, nullptr);
      if (pool) vkDestroyDescriptorPool(device, pool, nullptr);
      if (layout) vkDestroyPipelineLayout(device, layout, nullptr);
      if (set_layout) vkDestroyDescriptorSetLayout(device, set_layout, nullptr);
      for (Buffer* b : {&in, &out}) {
        if (b->buf) vkDestroyBuffer(device, b->buf, nullptr);
        if (b->mem) vkFreeMemory(device, b->mem, nullptr);
      }
      vkDestroyDevice(device, nullptr);
    }
    if (instance) vkDestroyInstance(instance, nullptr);
  }

  std::string make_buffer(Buffer& b, VkDeviceSize size) {
    VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bi.size = size;
    bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    if (auto r = vkCreateBuffer(device, &bi, nullptr, &b.buf); r != VK_SUCCESS) return vk_error("vkCreateBuffer", r);
    VkMemoryRequirements req{};
    vkGetBufferMemoryRequirements(device, b.buf, &req);
    VkPhysicalDeviceMemoryProperties mp{};
    vkGetPhysicalDeviceMemoryProperties(physical, &mp);
    const VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    std::uint32_t type = UINT32_MAX;
    for (std::uint32_t i = 0; i < mp.memoryTypeCount && type == UINT32_MAX; ++i)
      if ((req.memoryTypeBits & (1u << i)) && (mp.memoryTypes[i].propertyFlags & want) == want) type = i;
    if (type == UINT32_MAX) return "Vulkan: the device has no host-visible, coherent memory for the case buffers";
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = type;
    if (auto r = vkAllocateMemory(device, &ai, nullptr, &b.mem); r != VK_SUCCESS) return vk_error("vkAllocateMemory", r);
    if (auto r = vkBindBufferMemory(device, b.buf, b.mem, 0); r != VK_SUCCESS) return vk_error("vkBindBufferMemory", r);
    if (auto r = vkMapMemory(device, b.mem, 0, size, 0, &b.map); r != VK_SUCCESS) return vk_error("vkMapMemory", r);
    b.size = size;
    return {};
  }

  std::string open() {
    auto inst = make_instance();
    if (auto* why = std::get_if<std::string>(&inst)) return *why;
    instance = std::get<VkInstance>(inst);
    const auto pds = physical_devices(instance);
    if (pds.empty()) return kNoDevice;
    if (spec.device < 0 || static_cast<std::size_t>(spec.device) >= pds.size())
      return fmt::format("--device {}: there is no such Vulkan device; the devices here:{}", spec.device, device_list(pds));
    physical = pds[static_cast<std::size_t>(spec.device)];
    info = read_info(physical);
    const bool dbl = spec.precision == Precision::float64;
    if (dbl && !info.float64)
      return fmt::format("device {} ({}) has no shaderFloat64, so it cannot run a double shader: run it in float "
                         "(NAME:float=FILE) or choose another device with --device N; the devices here:{}",
                         spec.device, info.name, device_list(pds));
    std::uint32_t nq = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &nq, nullptr);
    std::vector<VkQueueFamilyProperties> qf(nq);
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &nq, qf.data());
    family = UINT32_MAX;
    for (std::uint32_t i = 0; i < nq && family == UINT32_MAX; ++i)
      if (qf[i].queueFlags & VK_QUEUE_COMPUTE_BIT) family = i;
    if (family == UINT32_MAX) return fmt::format("device {} ({}) has no compute queue", spec.device, info.name);
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qi.queueFamilyIndex = family;
    qi.queueCount = 1;
    qi.pQueuePriorities = &priority;
    VkPhysicalDeviceFeatures feats{};
    feats.shaderFloat64 = dbl ? VK_TRUE : VK_FALSE;
    VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    di.queueCreateInfoCount = 1;
    di.pQueueCreateInfos = &qi;
    di.pEnabledFeatures = &feats;
    if (auto r = vkCreateDevice(physical, &di, nullptr, &device); r != VK_SUCCESS) return vk_error("vkCreateDevice", r);
    vkGetDeviceQueue(device, family, 0, &queue);

    const VkDeviceSize real = dbl ? 8 : 4;
    if (auto e = make_buffer(in, kMaxCases * kInReals * real); !e.empty()) return e;
    if (auto e = make_buffer(out, kMaxCases * kOutReals * real); !e.empty()) return e;

    std::array<VkDescriptorSetLayoutBinding, 2> binds{};
    for (std::uint32_t i = 0; i < 2; ++i) {
      binds[i].binding = i;
      binds[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      binds[i].descriptorCount = 1;
      binds[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    VkDescriptorSetLayoutCreateInfo sli{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    sli.bindingCount = 2;
    sli.pBindings = binds.data();
    if (auto r = vkCreateDescriptorSetLayout(device, &sli, nullptr, &set_layout); r != VK_SUCCESS)
      return vk_error("vkCreateDescriptorSetLayout", r);
    VkPushConstantRange pcr{VK_SHADER_STAGE_COMPUTE_BIT, 0, 4};
    VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pli.setLayoutCount = 1;
    pli.pSetLayouts = &set_layout;
    pli.pushConstantRangeCount = 1;
    pli.pPushConstantRanges = &pcr;
    if (auto r = vkCreatePipelineLayout(device, &pli, nullptr, &layout); r != VK_SUCCESS)
      return vk_error("vkCreatePipelineLayout", r);
    VkDescriptorPoolSize ps{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2};
    VkDescriptorPoolCreateInfo dpi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dpi.maxSets = 1;
    dpi.poolSizeCount = 1;
    dpi.pPoolSizes = &ps;
    if (auto r = vkCreateDescriptorPool(device, &dpi, nullptr, &pool); r != VK_SUCCESS)
      return vk_error("vkCreateDescriptorPool", r);
    VkDescriptorSetAllocateInfo dsa{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    dsa.descriptorPool = pool;
    dsa.descriptorSetCount = 1;
    dsa.pSetLayouts = &set_layout;
    if (auto r = vkAllocateDescriptorSets(device, &dsa, &set); r != VK_SUCCESS)
      return vk_error("vkAllocateDescriptorSets", r);
    std::array<VkDescriptorBufferInfo, 2> bufs{{{in.buf, 0, VK_WHOLE_SIZE}, {out.buf, 0, VK_WHOLE_SIZE}}};
    std::array<VkWriteDescriptorSet, 2> writes{};
    for (std::uint32_t i = 0; i < 2; ++i) {
      writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
      writes[i].dstSet = set;
      writes[i].dstBinding = i;
      writes[i].descriptorCount = 1;
      writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      writes[i].pBufferInfo = &bufs[i];
    }
    vkUpdateDescriptorSets(device, 2, writes.data(), 0, nullptr);
    VkCommandPoolCreateInfo cpi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    cpi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    cpi.queueFamilyIndex = family;
    if (auto r = vkCreateCommandPool(device, &cpi, nullptr, &cmd_pool); r != VK_SUCCESS)
      return vk_error("vkCreateCommandPool", r);
    VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    cai.commandPool = cmd_pool;
    cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cai.commandBufferCount = 1;
    if (auto r = vkAllocateCommandBuffers(device, &cai, &cmd); r != VK_SUCCESS)
      return vk_error("vkAllocateCommandBuffers", r);
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    if (auto r = vkCreateFence(device, &fi, nullptr, &fence); r != VK_SUCCESS) return vk_error("vkCreateFence", r);
    return {};
  }

  std::array<std::vector<std::uint32_t>, 6> spirv{};

  /// Compiles every kind's shader (no device needed): empty, or the compiler's message.
  std::string compile_all(const std::string& user_text) {
    for (io::Kind k : kinds) {
      auto spv = compile(wrap(user_text, spec.file, k, spec.precision), k, spec.precision);
      if (auto* why = std::get_if<std::string>(&spv)) return *why;
      auto words = std::get<std::vector<std::uint32_t>>(std::move(spv));
      if (spec.no_contraction) {
        words = decorate_no_contraction(words);
        if (words.empty()) return "rayproof: cannot decorate the compiled shader with NoContraction";
      }
      spirv[static_cast<std::size_t>(k)] = std::move(words);
    }
    return {};
  }

  std::string build() {
    for (io::Kind k : kinds) {
      const auto& words = spirv[static_cast<std::size_t>(k)];
      const auto ki = static_cast<std::size_t>(k);
      VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
      mi.codeSize = words.size() * 4;
      mi.pCode = words.data();
      if (auto r = vkCreateShaderModule(device, &mi, nullptr, &modules[ki]); r != VK_SUCCESS)
        return vk_error("vkCreateShaderModule", r);
      VkComputePipelineCreateInfo pi{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
      pi.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
      pi.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
      pi.stage.module = modules[ki];
      pi.stage.pName = "main";
      pi.layout = layout;
      if (auto r = vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &pi, nullptr, &pipelines[ki]); r != VK_SUCCESS)
        return vk_error(("vkCreateComputePipelines for " + function_name(k)).c_str(), r);
    }
    return {};
  }
};

Runner::Runner(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Runner::~Runner() = default;
const DeviceInfo& Runner::info() const { return impl_->info; }
const std::vector<io::Kind>& Runner::kinds() const { return impl_->kinds; }
std::size_t Runner::max_cases() const { return kMaxCases; }

std::variant<std::unique_ptr<Runner>, std::string> Runner::create(const RunnerSpec& spec) {
  std::ifstream f(spec.file, std::ios::binary);
  if (!f) return spec.file + ": cannot read the file";
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string text = ss.str();
  if (text.find('\0') != std::string::npos) return spec.file + ": not a GLSL text file (it holds a NUL byte)";
  auto impl = std::make_unique<Impl>();
  impl->spec = spec;
  impl->kinds = defined_kinds(text);
  if (impl->kinds.empty()) {
    std::string names;
    for (int k = 0; k < 6; ++k) names += (k ? ", " : "") + function_name(static_cast<io::Kind>(k));
    return spec.file + ": defines none of the functions rayproof calls (" + names + "; docs/shaders.md)";
  }
  if (auto e = impl->compile_all(text); !e.empty()) return e;
  if (auto e = impl->open(); !e.empty()) return e;
  if (auto e = impl->build(); !e.empty()) return e;
  auto runner = std::unique_ptr<Runner>(new Runner(std::move(impl)));
  // Some drivers (lavapipe) compile a pipeline at its first dispatch: one dispatch of no case per
  // kind here (every invocation returns before the user's code), so that the time of a batch is
  // the shader's own, not the compiler's.
  for (io::Kind k : runner->kinds())
    if (auto e = runner->run(k, nullptr, 0, nullptr); !e.empty()) return e;
  return runner;
}

std::string Runner::run(io::Kind k, const void* in, std::size_t n, void* out) {
  Impl& m = *impl_;
  if (m.lost) return "the Vulkan device was lost";
  const auto ki = static_cast<std::size_t>(k);
  if (!m.pipelines[ki]) return "the shader has no " + function_name(k);
  if (n > kMaxCases) return "too many cases for one dispatch";
  const bool dbl = m.spec.precision == Precision::float64;
  const std::size_t real = dbl ? sizeof(double) : sizeof(float);
  if (n > 0) std::memcpy(m.in.map, in, n * kInReals * real);
  vkResetCommandBuffer(m.cmd, 0);
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vkBeginCommandBuffer(m.cmd, &bi);
  vkCmdBindPipeline(m.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m.pipelines[ki]);
  vkCmdBindDescriptorSets(m.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m.layout, 0, 1, &m.set, 0, nullptr);
  const std::uint32_t count = static_cast<std::uint32_t>(n);
  vkCmdPushConstants(m.cmd, m.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, 4, &count);
  vkCmdDispatch(m.cmd, std::max<std::uint32_t>(1, (count + kWorkgroup - 1) / kWorkgroup), 1, 1);
  VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(m.cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0,
                       nullptr, 0, nullptr);
  if (auto r = vkEndCommandBuffer(m.cmd); r != VK_SUCCESS) return vk_error("vkEndCommandBuffer", r);
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &m.cmd;
  vkResetFences(m.device, 1, &m.fence);
  if (auto r = vkQueueSubmit(m.queue, 1, &si, m.fence); r != VK_SUCCESS) {
    m.lost = r == VK_ERROR_DEVICE_LOST;
    return vk_error("vkQueueSubmit", r);
  }
  // No timeout here: the parent process times the batch and ends this process when it hangs.
  const VkResult r = vkWaitForFences(m.device, 1, &m.fence, VK_TRUE, UINT64_MAX);
  if (r != VK_SUCCESS) {
    m.lost = true;
    return r == VK_ERROR_DEVICE_LOST ? std::string("the Vulkan device was lost during the dispatch (VK_ERROR_DEVICE_LOST)")
                                     : vk_error("vkWaitForFences", r);
  }
  if (n > 0) std::memcpy(out, m.out.map, n * kOutReals * real);
  return {};
}

}  // namespace rayproof::glsl
