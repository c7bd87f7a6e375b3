#pragma once
/// `check --glsl ... --compare-plugin` and `check --opencl ... --compare-plugin`: where the device
/// build of a formula (a GLSL shader or an OpenCL C kernel) answers differently from the C build of
/// the same formula (a --plugin), on the same inputs, and why where rayproof can tell:
///  - contraction: the device build without contraction (GLSL: every float operation precise,
///    SPIR-V NoContraction; OpenCL: `#pragma OPENCL FP_CONTRACT OFF`) agrees with the C build, so the
///    device's compiler contracted multiply-adds into FMA (or made another rewrite that forbids);
///  - subnormal: a value in the subnormal range is involved (an input, or either build's answer),
///    which a device may flush to zero;
///  - unexplained: neither.
/// One tally and one text for both languages; a test builds the text from known tallies.
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "io/case_file.h"
#include "methods/method.h"

namespace rayproof::verify {

/// The device build's language: it names the build without contraction in the text.
enum class DeviceLanguage { glsl, opencl };

struct BuildDifference {
  io::Case input;  ///< as both builds saw it
  io::CaseResult device, c;
  std::optional<io::CaseResult> uncontracted;  ///< the build without contraction, where it ran
  std::string why;                             ///< "contraction", "subnormal", "unexplained"
};

struct BuildComparison {
  DeviceLanguage language = DeviceLanguage::glsl;
  std::string device, c, uncontracted;  ///< method names (uncontracted empty when no such build ran)
  std::size_t cases = 0;                ///< answered by both (a failure on either side leaves a case out)
  std::size_t failed = 0;               ///< left out: a failure of either build
  std::size_t differ = 0;               ///< not identical (class, t, t2 or barycentrics, bit for bit)
  std::size_t differ_hit = 0;           ///< of `differ`: one says miss, the other a contact
  std::size_t contraction = 0;          ///< of `differ`: the build without contraction agrees with C
  std::size_t uncontracted_differ = 0;  ///< of `cases`: the build without contraction differs from C
  std::size_t subnormal = 0;            ///< of `differ` but not contraction: a subnormal value is involved
  std::size_t unexplained = 0;          ///< the rest of `differ`
  std::string device_note;              ///< the device's own statement on subnormals ("" when unknown)
  std::vector<BuildDifference> examples;    ///< the first `keep` differences
  double device_seconds = 0, c_seconds = 0;  ///< wall time of each build's one pass, side by side
};

/// The two answers are the same: same contact, same t, t2 and barycentrics (bit for bit; NaN equals NaN).
[[nodiscard]] bool same_answer(const io::CaseResult& a, const io::CaseResult& b);

/// A nonzero finite value below the smallest normal of the precision in magnitude.
[[nodiscard]] bool subnormal(double x, Precision p);

/// Runs `device`, `c` and, when given, `uncontracted` over the cases both builds answer (already
/// rounded for float kernels), and sorts the differences by cause. Failures the builds recorded are
/// taken (the check reported them).
[[nodiscard]] BuildComparison compare_builds(DeviceLanguage language, const Method& device, const Method& c,
                                             const Method* uncontracted, std::span<const io::Case> cases,
                                             std::size_t keep);

/// The text: a heading, the speed of both builds, one sentence per cause with its count; then the
/// example lines (case line, both answers, the cause) after a line starting "# the first".
[[nodiscard]] std::vector<std::string> comparison_lines(const BuildComparison& r);

}  // namespace rayproof::verify
