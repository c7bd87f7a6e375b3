#pragma once
/// The GPU side of --glsl: a user's GLSL functions compiled with glslang into one compute pipeline
/// per kind, run on a Vulkan device in batches (one invocation per case), answers read back. Used
/// only inside the child process of methods/glsl_kernel.h, so that a shader that never finishes is
/// ended by killing that process.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "io/case_file.h"
#include "methods/method.h"

namespace rayproof::glsl {

/// What a run says about its device (VkPhysicalDeviceProperties, driver and float-controls properties).
struct DeviceInfo {
  std::string name;    ///< deviceName
  std::string type;    ///< "cpu", "integrated GPU", "discrete GPU", "virtual GPU", "other"
  std::string driver;  ///< driverName driverInfo (Vulkan 1.2), else the driver version number
  std::string api;     ///< "1.3.230"
  bool float64 = false;              ///< shaderFloat64
  bool float_controls = false;       ///< the float-controls properties below were read
  bool denorm_preserve32 = false, denorm_flush32 = false, denorm_preserve64 = false, denorm_flush64 = false;
  /// "llvmpipe (LLVM 15.0.6, 256 bits) (cpu; driver llvmpipe Mesa 22.3.6; Vulkan 1.3.230)"
  [[nodiscard]] std::string describe() const;
  /// "subnormal floats: may be flushed (the device promises neither preserving nor flushing them)", ...
  [[nodiscard]] std::string subnormals(Precision p) const;
};

struct RunnerSpec {
  std::string file;     ///< the user's GLSL file
  Precision precision = Precision::float32;
  int device = 0;       ///< index into vkEnumeratePhysicalDevices
  bool no_contraction = false;  ///< every float operation decorated NoContraction (decorate_no_contraction)
};

/// The Vulkan devices here, one line each ("0: NAME (...)"), or a message saying why there are none.
[[nodiscard]] std::variant<std::vector<std::string>, std::string> list_devices();

class Runner {
 public:
  /// Reads and compiles the file, opens the device. A one-line-or-more message on failure: the
  /// compiler's errors with the user's file name and lines; no Vulkan device (naming the Debian
  /// packages); a device index out of range (listing the devices); no shaderFloat64 for double.
  [[nodiscard]] static std::variant<std::unique_ptr<Runner>, std::string> create(const RunnerSpec& spec);
  ~Runner();
  Runner(const Runner&) = delete;
  Runner& operator=(const Runner&) = delete;

  [[nodiscard]] const DeviceInfo& info() const;
  [[nodiscard]] const std::vector<io::Kind>& kinds() const;
  /// Most cases per run call.
  [[nodiscard]] std::size_t max_cases() const;
  /// Answers n <= max_cases() cases of kind k: in = n * kInReals inputs, out = n * kOutReals reals
  /// (code, t, b1, b2), reals of the shader's precision (float or double). Empty on success, else
  /// why not (device lost, ...): the runner is unusable then.
  [[nodiscard]] std::string run(io::Kind k, const void* in, std::size_t n, void* out);

  struct Impl;

 private:
  explicit Runner(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace rayproof::glsl
