#pragma once
/// check --compare-plugin: where a GPU build of a formula (a --glsl kernel) answers differently from
/// the C build of the same formula (a --plugin), on the same inputs, and why where it can tell: the
/// shader compiled with every float operation precise (NoContraction) agrees with C (contraction into
/// FMA by the device's compiler), or a value in the subnormal range is involved (the device may flush).
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "methods/method.h"

namespace rayproof::cli {

struct BuildDifference {
  io::Case input;  ///< as both kernels saw it
  io::CaseResult gpu, c;
  std::optional<io::CaseResult> precise;  ///< the precise shader's answer, where it ran
  std::string why;                        ///< "contraction", "subnormal", "unexplained"
};

struct BuildComparison {
  std::string gpu, c, precise;  ///< method names (precise empty when no precise variant ran)
  std::size_t cases = 0, differ = 0, contraction = 0, subnormal = 0, unexplained = 0;
  std::vector<BuildDifference> examples;  ///< the first `keep` differences
  double gpu_seconds = 0, c_seconds = 0;  ///< wall time of each build's one pass over the cases, side by side
};

/// The two answers are the same: same contact, same t and barycentrics (bit for bit; NaN equals NaN).
[[nodiscard]] bool same_answer(const io::CaseResult& a, const io::CaseResult& b);

/// A nonzero finite value below the smallest normal of the precision in magnitude.
[[nodiscard]] bool subnormal(double x, Precision p);

/// Runs gpu, c and (on the differing cases) precise over `cases` (already rounded for float
/// kernels) and sorts the differences by cause.
[[nodiscard]] BuildComparison compare_builds(const Method& gpu, const Method& c, const Method* precise,
                                             std::span<const io::Case> cases, std::size_t keep);

/// The text: a heading, the speed of both builds, one sentence per cause with its count, the example lines. `device_note`
/// (the device's float-controls statement) goes with the subnormal count.
[[nodiscard]] std::vector<std::string> comparison_lines(const BuildComparison& r, const std::string& device_note);

}  // namespace rayproof::cli
