#pragma once
/// The OpenCL side of `--opencl NAME=FILE` (docs/opencl.md): the devices of every platform, the
/// wrapper that turns a user's OpenCL C functions into one __kernel per kind (one work-item per
/// case), its build and its runs. Only the device process (`rayproof opencl-host`,
/// src/cli/cmd_opencl_host.cpp) links OpenCL; rayproof itself talks to it over pipes
/// (methods/opencl_kernel.h), so that a kernel that never returns can be killed.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "io/case_file.h"
#include "methods/method.h"
#include "methods/opencl_wrapper.h"

namespace rayproof::opencl {

/// One device of one platform, numbered across platforms in the ICD loader's order (`--device N`).
struct DeviceInfo {
  std::string platform, platform_version;
  std::string name, version, driver_version, type;  ///< type: cpu, gpu, accelerator, other
  bool fp64 = false;              ///< cl_khr_fp64 (or a double FP config)
  bool float_denorms = false;     ///< CL_DEVICE_SINGLE_FP_CONFIG has CL_FP_DENORM
  bool float_fma = false;         ///< CL_DEVICE_SINGLE_FP_CONFIG has CL_FP_FMA
  /// "pthread-skylake (platform Portable Computing Language, OpenCL 3.0 PoCL 3.1, driver 3.1)".
  [[nodiscard]] std::string describe() const;
};

/// Every device, or a message when there is none (no ICD loader, no platform, no device), naming
/// the Debian packages of a CPU device.
[[nodiscard]] std::variant<std::vector<DeviceInfo>, std::string> list_devices();

/// "  0: NAME (...)\n  1: ...": the devices for a message.
[[nodiscard]] std::string device_list_text(const std::vector<DeviceInfo>& devices);

/// A built program on one device, ready to run batches.
class Program {
 public:
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  /// Builds `source` on device `index` with `options` (empty: the device's defaults) and runs each
  /// kernel once on no case, so that a compiler working at the first launch (pocl) is done here.
  /// A message on failure: no device, the build log, ...
  [[nodiscard]] static std::variant<std::unique_ptr<Program>, std::string> build(
      int index, const std::string& source, const std::string& options, const std::vector<io::Kind>& kinds,
      Precision precision);

  [[nodiscard]] const DeviceInfo& device() const;
  /// Runs the kind's kernel on `n` cases: `in` holds fields(kind) reals (float or double, the
  /// program's precision) per case; the return codes go to `codes`, t, b1, b2 per case to `out`.
  /// Gives a message on an OpenCL error.
  [[nodiscard]] std::optional<std::string> run(io::Kind kind, const void* in, std::size_t n, std::int32_t* codes,
                                               void* out);

 private:
  struct Impl;
  explicit Program(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace rayproof::opencl
