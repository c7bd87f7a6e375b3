#pragma once
/// A user's OpenCL C functions as a method (`--opencl NAME=FILE`, docs/opencl.md). FILE defines
/// `rayproof_triangle`, `rayproof_sphere`, ... with the signatures of docs/opencl.md; rayproof wraps
/// them in one __kernel per kind (one work-item per case), builds the program on an OpenCL device
/// and runs batches there. The device work runs in a child process (`HOST opencl-host`, the same
/// rayproof), because OpenCL cannot stop a kernel that never returns: a batch that runs over the
/// timeout is reported with its cases (each answered Contact::error, a KernelFailure), the child is
/// killed and a new one built for the next batch, and the run goes on. After `max_timeouts` timed-out
/// or crashed batches the kernel is dropped from the run (its remaining cases answer Contact::error).
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "methods/method.h"

namespace rayproof {

struct OpenclOptions {
  int device = 0;                          ///< --device N: the Nth device over every platform
  std::optional<std::string> cl_options;   ///< --cl-options; none: the device's default build options
  bool contract_off = false;               ///< prepend `#pragma OPENCL FP_CONTRACT OFF` to the user's text
  double timeout_seconds = 5;              ///< a batch without answers for this long has hung
  double build_timeout_seconds = 300;      ///< the build (and the first launch) may take this long
  std::size_t max_batch = std::size_t{1} << 16;  ///< cases per device launch
  std::size_t max_timeouts = 3;            ///< timed-out or crashed batches before the kernel is dropped
};

/// What the device process said when it was ready.
struct OpenclDeviceReport {
  std::string device;        ///< "NAME (cpu; platform P, OpenCL 3.0 ...; driver D)"
  bool float_denorms = true; ///< CL_DEVICE_SINGLE_FP_CONFIG has CL_FP_DENORM
  bool float_fma = false;    ///< CL_DEVICE_SINGLE_FP_CONFIG has CL_FP_FMA
  double build_seconds = 0;  ///< build and first launch, in the device process
};

/// The method of one spec: `FILE`, `NAME=FILE`, `NAME:PRECISION=FILE` or
/// `NAME:PRECISION:KIND[,KIND...]=FILE` (PRECISION float or double; without KINDs, every kind whose
/// function FILE defines). Builds the program once here, so that a build error (shown with FILE's
/// own line numbers), a missing device or a bad FILE is a message now, not a failure per case.
/// `host` is a rayproof executable (it runs `host opencl-host ...`). `report`, when not null,
/// receives the device process's report. The method is safe to call from several threads (its
/// batches take turns on the one device process).
[[nodiscard]] std::variant<Method, std::string> make_opencl_method(std::string_view spec, const std::string& host,
                                                                   const OpenclOptions& opt = {},
                                                                   OpenclDeviceReport* report = nullptr);

}  // namespace rayproof
