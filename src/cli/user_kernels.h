#pragma once
/// The user's own kernels on the command line: `--exec NAME=COMMAND` (a child process speaking the
/// line protocol of docs/kernel_protocol.md) and `--plugin NAME=PATH.so` (a shared library exporting
/// the entry point of rayproof/plugin.h) and `--opencl NAME=FILE` (OpenCL C functions run on an
/// OpenCL device, docs/opencl.md). verify, report, fuzz and check take them all.
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "methods/method.h"
#include "methods/opencl_kernel.h"

namespace CLI { class App; }

namespace rayproof::cli {

struct UserKernelOptions {
  std::vector<std::string> exec;    ///< NAME=COMMAND
  std::vector<std::string> plugin;  ///< NAME=PATH.so
  bool plugin_in_process = true;    ///< false: each plugin runs in a forked child (check's default)
  double exec_timeout = 5;          ///< --exec-timeout: seconds without an answer before a kernel counts as hung
  std::vector<std::string> opencl;  ///< NAME=FILE: OpenCL C functions (docs/opencl.md)
  std::string cl_options;           ///< --cl-options: OpenCL build options (unset: the device's defaults)
  bool cl_options_given = false;
  bool cl_contract_off = false;     ///< --cl-contract-off: `#pragma OPENCL FP_CONTRACT OFF` before FILE
  std::vector<std::string> glsl;    ///< NAME=FILE, NAME:float=FILE, NAME:double=FILE (docs/shaders.md)
  bool glsl_precise = false;        ///< --glsl-precise: every float operation of the shader precise (NoContraction)
  int device = 0;                   ///< --device N: Vulkan's device index (--glsl); the Nth over every platform (--opencl)
};

/// Adds --exec, --plugin, --glsl, --opencl (with --cl-options) and --device to a subcommand.
void add_user_kernel_options(CLI::App& sub, UserKernelOptions& opt);

/// One `--opencl` spec's method, built with the options' --device, --cl-options and timeout, and
/// without FMA contraction when `contract_off` (or --cl-contract-off). `report` receives the device
/// process's report. A bad spec, FILE or build prints "rayproof COMMAND: ..." and gives nothing.
[[nodiscard]] std::unique_ptr<Method> make_opencl_kernel(std::string_view command, const std::string& spec,
                                                         const UserKernelOptions& opt, bool contract_off,
                                                         OpenclDeviceReport* report = nullptr);

/// The methods the options name, owned by the caller for the command's run. A bad spec prints
/// "rayproof COMMAND: ..." to standard error and gives nothing.
[[nodiscard]] std::optional<std::vector<std::unique_ptr<Method>>> make_user_kernels(std::string_view command,
                                                                                   const UserKernelOptions& opt);

/// A --glsl kernel (its summary names the file, the precision, the device and its driver).
[[nodiscard]] bool is_glsl_kernel(const Method& m);

}  // namespace rayproof::cli
