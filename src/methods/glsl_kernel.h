#pragma once
/// A user's GLSL intersection functions (docs/shaders.md) as a Method: `--glsl NAME=FILE`. The
/// shader is compiled and run on a Vulkan device in a child process (`rayproof glsl-host`), batches
/// of cases (one invocation each) going through pipes, so that a shader that never finishes is a
/// reported failure of its batch's cases, ended by killing the child, and the run goes on with a
/// new child (and a new device: how a lost device is recreated).
#include <string>
#include <variant>

#include "methods/method.h"

namespace rayproof {

struct GlslOptions {
  int device = 0;               ///< --device N: the Vulkan device's index (vkEnumeratePhysicalDevices)
  double timeout_seconds = 5;   ///< a dispatch (at most 65536 cases) without an answer this long has hung
  std::string host;             ///< the rayproof executable that runs `glsl-host`
  bool no_contraction = false;  ///< compile with every float operation `precise` (NoContraction)
};

/// SPEC: `NAME=FILE`, `NAME:float=FILE`, `NAME:double=FILE` or `FILE` (named after the file's stem;
/// float unless said). Compiles the shader and opens the device once to check them: gives the method
/// or the message (the compiler's errors with FILE's lines, no device, no shaderFloat64, ...).
/// The method's summary names the file, the precision, the device and its driver:
/// "GLSL shader FILE (float) on DEVICE (TYPE; driver DRIVER; Vulkan API)".
[[nodiscard]] std::variant<Method, std::string> make_glsl_method(const std::string& spec, const GlslOptions& opt);

/// `rayproof glsl-host`: the child's side. Compiles FILE, opens the device, answers batches on
/// standard input and output (binary frames, glsl_kernel.cpp) until asked to stop. Returns the exit status.
int run_glsl_host(const std::string& file, Precision precision, int device, bool no_contraction);

}  // namespace rayproof
