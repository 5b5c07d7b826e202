// The tools behind toolchain.hpp: glslang and SPIRV-Tools' validator as libraries, in-process; cc
// as a subprocess in a private temporary directory (removed afterwards).
#include "toolchain.hpp"

#include <dlfcn.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <stdexcept>

#include <fmt/core.h>
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <spirv-tools/libspirv.hpp>

#ifndef SGLAB_C_COMPILER
#define SGLAB_C_COMPILER "cc"
#endif

namespace sglab::shader {
namespace {

namespace fs = std::filesystem;

// A fresh directory under the system's temporary directory, removed with this object.
struct TempDir {
  fs::path path;
  TempDir() {
    std::string t = (fs::temp_directory_path() / "sglab-export-XXXXXX").string();
    if (!mkdtemp(t.data())) throw std::runtime_error("cannot create a temporary directory for the shader tools");
    path = t;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary);
  f << text;
  if (!f) throw std::runtime_error("cannot write " + p.string());
}

// Runs argv (no shell); returns the exit status and the combined stdout and stderr.
std::pair<int, std::string> run_tool(const std::vector<std::string>& argv) {
  int fd[2];
  // Close-on-exec: a tool started meanwhile by another thread does not hold this pipe open (its
  // reader would wait for that tool too); dup2 below clears it on the child's stdout and stderr.
  // The argument vector is built before fork: other threads may be running, so the child calls
  // nothing but dup2, close, execvp and _exit (no allocation).
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  if (pipe2(fd, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    dup2(fd[1], 1);
    dup2(fd[1], 2);
    close(fd[0]);
    close(fd[1]);
    execvp(args[0], args.data());
    _exit(127);
  }
  close(fd[1]);
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = read(fd[0], buf, sizeof buf)) > 0;) out.append(buf, std::size_t(n));
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
  if (code == 127 && out.empty()) out = "cannot run " + argv[0] + " (not installed? scripts/setup.sh installs it)";
  return {code, out};
}

void run_checked(const std::vector<std::string>& argv, const char* what) {
  auto [code, out] = run_tool(argv);
  if (code != 0) throw std::runtime_error(fmt::format("{} failed ({}, status {}):\n{}", what, argv[0], code, out));
}

// Row i's arguments in the language's buffer indexing.
std::string call_row(const TracedMethod& m, const char* buffer, const char* index) {
  std::string args;
  for (std::size_t j = 0; j < m.inputs.size(); ++j)
    args += fmt::format("{}{}[{} * {}u + {}u]", j ? ", " : "", buffer, index, m.inputs.size(), j);
  return fmt::format("{}({})", m.function, args);
}

// The instructions inside the functions of a SPIR-V module (OpFunction 54 … OpFunctionEnd 56;
// the header is 5 words, each instruction's first word holds its word count in the high 16 bits).
std::size_t count_function_instructions(std::span<const std::uint32_t> w) {
  std::size_t total = 0;
  bool inside = false;
  for (std::size_t i = 5; i < w.size();) {
    const std::uint32_t count = w[i] >> 16, op = w[i] & 0xFFFF;
    if (count == 0) break;
    if (op == 54) inside = true;
    if (inside) ++total;
    if (op == 56) inside = false;
    i += count;
  }
  return total;
}

}  // namespace

std::string compute_shader_source(const std::string& exported, const TracedMethod& m, Language lang) {
  if (lang == Language::glsl)
    return "#version 450\n"
           "layout(local_size_x = 64) in;\n"
           "layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };\n"
           "layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };\n" +
           exported +
           fmt::format("\nvoid main() {{\n  uint i = gl_GlobalInvocationID.x;\n  outputs[i] = {};\n}}\n",
                       call_row(m, "inputs", "i"));
  if (lang == Language::hlsl)
    return "[[vk::binding(0, 0)]] RWStructuredBuffer<float> inputs;\n"
           "[[vk::binding(1, 0)]] RWStructuredBuffer<float> outputs;\n" +
           exported +
           fmt::format(
               "\n[numthreads(64, 1, 1)]\nvoid main(uint3 id : SV_DispatchThreadID) {{\n  uint i = id.x;\n  outputs[i] "
               "= {};\n}}\n",
               call_row(m, "inputs", "i"));
  throw std::invalid_argument("compute_shader_source: C is not a shading language");
}

Spirv compile_to_spirv(const std::string& shader_source, Language lang) {
  // glslang as a library, set up as `glslangValidator -V --target-env vulkan1.1 [-D -e main -S
  // comp]` sets it up (glslang 12, StandAlone.cpp): a Vulkan 1.1 client (SPIR-V 1.3), client
  // input semantics 100, default version 100, the default resource limits, the Vulkan and SPIR-V
  // rules; HLSL read by the HLSL front end with entry point main and legalized by SPIRV-Tools'
  // optimizer, which GlslangToSpv runs for HLSL unless disableOptimizer. In-process, glslang's
  // built-in symbol tables are built once per process rather than once per shader.
  static const bool initialized = glslang::InitializeProcess();
  if (!initialized) throw std::runtime_error("glslang: InitializeProcess failed");
  const bool hlsl = lang == Language::hlsl;
  const EShLanguage stage = EShLangCompute;
  const auto messages = EShMessages(EShMsgSpvRules | EShMsgVulkanRules | (hlsl ? EShMsgReadHlsl : EShMsgDefault));
  glslang::TShader shader(stage);
  const char* text = shader_source.c_str();
  const char* name = hlsl ? "shader.hlsl" : "shader.comp";
  shader.setStringsWithLengthsAndNames(&text, nullptr, &name, 1);
  if (hlsl) shader.setEntryPoint("main");
  shader.setEnvInput(hlsl ? glslang::EShSourceHlsl : glslang::EShSourceGlsl, stage, glslang::EShClientVulkan, 100);
  shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_1);
  shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_3);
  if (!shader.parse(GetDefaultResources(), 100, false, messages))
    throw std::runtime_error(fmt::format("glslang failed ({}):\n{}{}", name, shader.getInfoLog(), shader.getInfoDebugLog()));
  glslang::TProgram program;
  program.addShader(&shader);
  if (!program.link(messages))
    throw std::runtime_error(fmt::format("glslang failed to link ({}):\n{}{}", name, program.getInfoLog(),
                                         program.getInfoDebugLog()));
  glslang::SpvOptions options;
  options.disableOptimizer = false;  // as glslangValidator: HLSL is legalized, GLSL is left as emitted
  spv::SpvBuildLogger logger;
  Spirv s;
  glslang::GlslangToSpv(*program.getIntermediate(stage), s.words, &logger, &options);
  // spirv-val's checks (SPIRV-Tools' validator) for a Vulkan 1.1 environment.
  spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_1);
  std::string diagnostics;
  tools.SetMessageConsumer([&diagnostics](spv_message_level_t, const char*, const spv_position_t& at, const char* m) {
    diagnostics += fmt::format("word {}: {}\n", at.index, m);
  });
  if (!tools.Validate(s.words))
    throw std::runtime_error(fmt::format("SPIR-V validation failed ({}):\n{}{}", name, diagnostics, logger.getAllMessages()));
  s.function_instructions = count_function_instructions(s.words);
  return s;
}

std::size_t method_instructions(const Spirv& spirv, Language lang, std::size_t arity) {
  static std::mutex mutex;
  static std::map<std::pair<int, std::size_t>, std::size_t> baselines;
  std::lock_guard<std::mutex> lock(mutex);
  auto it = baselines.find({int(lang), arity});
  if (it == baselines.end()) {
    TracedMethod identity;
    identity.function = "sglab_identity";
    std::string params;
    for (std::size_t j = 0; j < arity; ++j) {
      identity.inputs.push_back(fmt::format("a{}", j));
      params += j ? ", float a" : "float a";
      params += std::to_string(j);
    }
    const std::string src = "float sglab_identity(" + params + ") { return a0; }\n";
    const Spirv base = compile_to_spirv(compute_shader_source(src, identity, lang), lang);
    it = baselines.emplace(std::pair{int(lang), arity}, base.function_instructions).first;
  }
  return spirv.function_instructions > it->second ? spirv.function_instructions - it->second : 0;
}

std::vector<float> run_compute(VulkanCompute& gpu, const Spirv& spirv, std::span<const float> rows, std::size_t arity) {
  const std::size_t n = rows.size() / arity;
  const std::uint32_t groups = std::uint32_t((n + 63) / 64);
  // Padded to whole groups with copies of the first row (every invocation reads a valid row).
  std::vector<float> in(rows.begin(), rows.end());
  while (in.size() < std::size_t(groups) * 64 * arity) in.insert(in.end(), rows.begin(), rows.begin() + long(arity));
  std::vector<float> out = gpu.run(spirv.words, in, groups);
  out.resize(n);
  return out;
}

std::vector<float> run_c(const std::string& exported, const TracedMethod& m, std::span<const float> rows) {
  TempDir dir;
  const fs::path src = dir.path / "export.c", lib = dir.path / "export.so";
  write_text(src, exported + fmt::format("\nfloat sglab_entry(const float* inputs, unsigned i) {{ return {}; }}\n",
                                         call_row(m, "inputs", "i")));
  run_checked({SGLAB_C_COMPILER, "-std=c99", "-O2", "-ffp-contract=off", "-Wall", "-Werror", "-shared", "-fPIC", "-o",
               lib.string(), src.string(), "-lm"},
              "the C compiler");
  void* handle = dlopen(lib.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) throw std::runtime_error(fmt::format("dlopen: {}", dlerror()));
  auto entry = reinterpret_cast<float (*)(const float*, unsigned)>(dlsym(handle, "sglab_entry"));
  if (!entry) {
    dlclose(handle);
    throw std::runtime_error("dlsym: sglab_entry not found");
  }
  const std::size_t n = rows.size() / m.inputs.size();
  std::vector<float> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = entry(rows.data(), unsigned(i));
  dlclose(handle);
  return out;
}

}  // namespace sglab::shader
