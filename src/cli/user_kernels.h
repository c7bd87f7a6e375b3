#pragma once
/// The user's own kernels on the command line: `--exec NAME=COMMAND` (a child process speaking the
/// line protocol of docs/kernel_protocol.md) and `--plugin NAME=PATH.so` (a shared library exporting
/// the entry point of rayproof/plugin.h). verify, report, fuzz and check take both.
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "methods/method.h"

namespace CLI { class App; }

namespace rayproof::cli {

struct UserKernelOptions {
  std::vector<std::string> exec;    ///< NAME=COMMAND
  std::vector<std::string> plugin;  ///< NAME=PATH.so
  bool plugin_in_process = true;    ///< false: each plugin runs in a forked child (check's default)
  double exec_timeout = 5;          ///< --exec-timeout: seconds without an answer before a kernel counts as hung
  std::vector<std::string> glsl;    ///< NAME=FILE, NAME:float=FILE, NAME:double=FILE (docs/shaders.md)
  int device = 0;                   ///< --device N: the GPU device of --glsl (Vulkan's device index)
  bool glsl_precise = false;        ///< --glsl-precise: every float operation of the shader precise (NoContraction)
};

/// Adds --exec, --plugin, --glsl and --device to a subcommand.
void add_user_kernel_options(CLI::App& sub, UserKernelOptions& opt);

/// The methods the options name, owned by the caller for the command's run. A bad spec prints
/// "rayproof COMMAND: ..." to standard error and gives nothing.
[[nodiscard]] std::optional<std::vector<std::unique_ptr<Method>>> make_user_kernels(std::string_view command,
                                                                                   const UserKernelOptions& opt);

/// A --glsl kernel (its summary names the file, the precision, the device and its driver).
[[nodiscard]] bool is_glsl_kernel(const Method& m);

}  // namespace rayproof::cli
