#pragma once
/// Stability curves: every method judged against exact at every step of every stiffness knob
/// (gen/knobs.h), and where each one breaks (docs/stability.md).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "gen/knobs.h"
#include "methods/method.h"
#include "verify/differential.h"

namespace rayproof::verify {

/// One step of a knob for one method: the knob value is 2^exponent.
struct StepTally {
  int exponent = 0;
  Stats stats;
};

/// One method along one knob, steps in sweep order (increasing stiffness).
struct StabilityCurve {
  std::string knob;
  std::string method;
  Precision precision = Precision::float64;  ///< of the method's inputs (ulps are counted in it)
  Promise promise;                           ///< what the method promises on the knob's kind
  std::vector<StepTally> steps;
};

struct StabilityRun {
  std::size_t count = 0;  ///< cases per step
  std::uint64_t seed = 0;
  std::vector<std::string> knobs;  ///< in gen::knobs() order, those swept
  std::vector<StabilityCurve> curves;  ///< knob-major, methods in the given order
};

/// Generates `count` cases per step of each knob, computes the exact answers once, and judges every
/// method that supports the knob's kind at every step (verify::compare, so float methods are judged
/// on their float-rounded inputs, as everywhere). `progress` gets a line now and then.
[[nodiscard]] StabilityRun run_stability(const std::vector<const gen::Knob*>& knobs,
                                         const std::vector<const Method*>& methods, std::size_t count,
                                         std::uint64_t seed, const std::function<void(const std::string&)>& progress);

/// Where a curve breaks: the first step (in sweep order) whose class error rate is above
/// `class_rate`, and the first whose median t error is above `ulps`; nothing when no step is.
struct Break {
  std::optional<int> class_errors;
  std::optional<int> t_error;
};
[[nodiscard]] Break find_break(const StabilityCurve& c, double class_rate = 0.001, std::uint64_t ulps = 1);

}  // namespace rayproof::verify
