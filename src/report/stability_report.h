#pragma once
/// The report's stability part (docs/stability.md): stability.svg (one panel per knob: class error
/// rate and median / max t error of every method against the knob), stability.csv (one row per
/// knob x method x step) and the "where each method breaks" section of the markdown.
#include <string>

#include "verify/stability.h"

namespace rayproof::report {

[[nodiscard]] std::string stability_csv(const verify::StabilityRun& run);
[[nodiscard]] std::string stability_svg(const verify::StabilityRun& run);
/// The markdown section: the chart, the table of breaks, and the prediction sentences.
[[nodiscard]] std::string stability_markdown(const verify::StabilityRun& run);

/// Writes stability.md, stability.csv and stability.svg into `dir` (created if needed); returns an
/// error message or "".
[[nodiscard]] std::string write_stability(const verify::StabilityRun& run, const std::string& dir);

}  // namespace rayproof::report
