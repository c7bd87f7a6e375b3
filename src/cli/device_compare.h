#pragma once
/// `check --opencl ... --compare-plugin PATH.so` (docs/opencl.md): where the device build of a
/// formula answers differently from the C build of the same formula, and why where rayproof can
/// tell: a build without FMA contraction (`#pragma OPENCL FP_CONTRACT OFF`) that agrees, or inputs
/// that a device without CL_FP_DENORM flushes to zero.
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "io/case_file.h"
#include "methods/method.h"

namespace rayproof::cli {

// same_answer (bit for bit) is cli/build_compare.h's, shared with the --glsl comparison.

/// The tallies of one comparison, from which the sentences are built.
struct DeviceComparison {
  std::string device_name, c_name;         ///< the two methods
  std::size_t cases = 0;                   ///< cases both answered (no failure on either side)
  std::size_t differ = 0;                  ///< answers not identical (class, t or barycentrics, bit for bit)
  std::size_t differ_hit = 0;              ///< of those: one says hit, the other miss
  std::optional<std::size_t> agree_uncontracted;  ///< of `differ`: the FP_CONTRACT OFF build agrees with C
  std::optional<std::size_t> uncontracted_differ; ///< cases where the FP_CONTRACT OFF build differs from C
  bool device_flushes = false;             ///< no CL_FP_DENORM on the device (float)
  std::size_t differ_subnormal = 0;        ///< of `differ`: a float input or difference is subnormal
  std::vector<std::string> examples;       ///< up to 3: the case line and both answers
};

/// Compares `device` with `c_build` on `cases` (already rounded for float methods); `uncontracted`,
/// when not null, is the device build without contraction.
[[nodiscard]] DeviceComparison compare_device_builds(const Method& device, const Method& c_build, const Method* uncontracted,
                                             bool device_flushes, std::span<const io::Case> cases);

/// The report's sentences for the tallies.
[[nodiscard]] std::vector<std::string> device_comparison_sentences(const DeviceComparison& c);

}  // namespace rayproof::cli
