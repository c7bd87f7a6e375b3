#include "cli/user_kernels.h"

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <filesystem>
#include <system_error>

#include "cli/plugin_host.h"
#include "registry/registry.h"
#include "methods/exec_kernel.h"
#include "methods/glsl_kernel.h"
#include "methods/opencl_kernel.h"

namespace rayproof::cli {

namespace {
/// This rayproof's own executable, which hosts a --glsl shader as `rayproof glsl-host` and an
/// --opencl kernel as `rayproof opencl-host`.
std::string self_executable() {
  std::error_code ec;
  const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : p.string();
}

/// Appends m unless its name is a registered method's or an earlier kernel's (then says so and
/// returns false); `option` and `hint` (how NAME is written) go into the message.
bool add_unique(std::string_view command, std::string_view option, const std::string& spec, std::string_view hint,
                std::unique_ptr<Method> m, std::vector<std::unique_ptr<Method>>& out) {
  bool taken = registry::all_methods().find(m->name) != nullptr;
  for (const auto& other : out) taken = taken || other->name == m->name;
  if (taken) {
    fmt::print(stderr, "rayproof {}: {} {}: the name '{}' is taken; choose another {}\n", command, option, spec, m->name,
               hint);
    return false;
  }
  out.push_back(std::move(m));
  return true;
}
}  // namespace

void add_user_kernel_options(CLI::App& sub, UserKernelOptions& opt) {
  sub.add_option("--exec", opt.exec,
                 "NAME=COMMAND: a kernel of yours answering case lines on stdin (docs/kernel_protocol.md); repeatable")
      ->allow_extra_args(false);  // one command per --exec: the case files that follow stay positional
  sub.add_option("--exec-timeout", opt.exec_timeout,
                 "Seconds an --exec kernel may take without answering before it counts as hung")
      ->check(CLI::Range(0.001, 86400.0))
      ->capture_default_str();
  sub.add_option("--plugin", opt.plugin,
                 "NAME=PATH.so or PATH.so: a kernel of yours as a shared library (rayproof/plugin.h); repeatable")
      ->allow_extra_args(false);  // one library per --plugin: the case files that follow stay positional
  sub.add_option("--glsl", opt.glsl,
                 "NAME=FILE (or NAME:double=FILE): your GLSL intersection functions (docs/shaders.md), run on a "
                 "Vulkan device; repeatable")
      ->allow_extra_args(false);
  sub.add_flag("--glsl-precise", opt.glsl_precise,
               "Compile --glsl shaders with every float operation precise (SPIR-V NoContraction): no FMA contraction");
  sub.add_option("--opencl", opt.opencl,
                 "NAME=FILE or NAME:double=FILE: OpenCL C functions of yours run on an OpenCL device "
                 "(docs/opencl.md); repeatable")
      ->allow_extra_args(false);
  sub.add_option("--cl-options", opt.cl_options, "OpenCL build options for --opencl (default: the device's defaults)")
      ->each([&opt](const std::string&) { opt.cl_options_given = true; });
  sub.add_flag("--cl-contract-off", opt.cl_contract_off,
               "Build --opencl kernels with `#pragma OPENCL FP_CONTRACT OFF` before their text (no FMA contraction)");
  sub.add_option("--device", opt.device,
                 "The GPU device: for --glsl its index in the Vulkan device list, for --opencl N over every "
                 "platform (a bad N's message lists them)")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
}

static OpenclOptions opencl_options(const UserKernelOptions& opt) {
  OpenclOptions oo;
  oo.device = opt.device;
  if (opt.cl_options_given) oo.cl_options = opt.cl_options;
  oo.contract_off = opt.cl_contract_off;
  oo.timeout_seconds = opt.exec_timeout;
  return oo;
}
std::unique_ptr<Method> make_opencl_kernel(std::string_view command, const std::string& spec,
                                           const UserKernelOptions& opt, bool contract_off, OpenclDeviceReport* report) {
  OpenclOptions oo = opencl_options(opt);
  oo.contract_off = oo.contract_off || contract_off;
  fmt::print(stderr, "[opencl] building {} on OpenCL device {}{}\n", spec, opt.device,
             oo.contract_off ? " with #pragma OPENCL FP_CONTRACT OFF" : "");
  OpenclDeviceReport rep;
  auto made = make_opencl_method(spec, self_executable(), oo, &rep);
  if (auto* err = std::get_if<std::string>(&made)) {
    fmt::print(stderr, "rayproof {}: {}\n", command, *err);
    return nullptr;
  }
  if (report) *report = rep;
  auto m = std::make_unique<Method>(std::move(std::get<Method>(made)));
  fmt::print(stderr, "[opencl] {}: {}: built in {:.2f} s\n", m->name, m->summary, rep.build_seconds);
  return m;
}

bool is_glsl_kernel(const Method& m) { return m.summary.rfind("GLSL shader ", 0) == 0; }

std::optional<std::vector<std::unique_ptr<Method>>> make_user_kernels(std::string_view command,
                                                                     const UserKernelOptions& opt) {
  std::vector<std::unique_ptr<Method>> out;
  // Filled in by the exec (src/methods/exec_kernel.h) and plugin (src/methods/plugin_kernel.h) loaders.

  // --exec: child processes over the line protocol (src/methods/exec_kernel.h).
  {
    ExecOptions eo;
    eo.timeout_seconds = opt.exec_timeout;
    for (const std::string& spec : opt.exec) {
      auto made = make_exec_method(spec, eo);
      if (auto* err = std::get_if<std::string>(&made)) {
        fmt::print(stderr, "rayproof {}: {}\n", command, *err);
        return std::nullopt;
      }
      if (!add_unique(command, "--exec", spec, "NAME", std::make_unique<Method>(std::move(std::get<Method>(made))), out))
        return std::nullopt;
    }
  }

  // --plugin: in process, or forked through `rayproof plugin-host` (src/cli/plugin_host.h).
  for (const std::string& spec : opt.plugin) {
    auto m = make_plugin_kernel(command, spec, opt.plugin_in_process, opt.exec_timeout);
    if (!m || !add_unique(command, "--plugin", spec, "(NAME=PATH.so)", std::move(m), out)) return std::nullopt;
  }
  // --glsl: compiled and run on a Vulkan device in a child process (src/methods/glsl_kernel.h).
  for (const std::string& spec : opt.glsl) {
    GlslOptions go;
    go.device = opt.device;
    go.timeout_seconds = opt.exec_timeout;
    go.host = self_executable();
    go.no_contraction = opt.glsl_precise;
    auto made = make_glsl_method(spec, go);
    if (auto* err = std::get_if<std::string>(&made)) {
      fmt::print(stderr, "rayproof {}: {}\n", command, *err);
      return std::nullopt;
    }
    Method& m = std::get<Method>(made);
    fmt::print(stderr, "rayproof {}: --glsl {}: {}\n", command, m.name, m.summary);
    if (!add_unique(command, "--glsl", spec, "(NAME=FILE)", std::make_unique<Method>(std::move(m)), out)) return std::nullopt;
  }

  // --opencl: OpenCL C on a device, in a device process (src/methods/opencl_kernel.h).
  for (const std::string& spec : opt.opencl) {
    auto m = make_opencl_kernel(command, spec, opt, false);
    if (!m || !add_unique(command, "--opencl", spec, "(NAME=FILE)", std::move(m), out)) return std::nullopt;
  }
  return out;
}

}  // namespace rayproof::cli
