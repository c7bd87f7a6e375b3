#pragma once
/// Every sentence and cell of the stability part (docs/stability.md), built from the tallies of a
/// run so that a test can build each one from known numbers: where each method breaks, what theory
/// predicts for it, and whether the measurement agrees.
#include <optional>
#include <string>
#include <vector>

#include "verify/stability.h"

namespace rayproof::report {

/// "2^-24", "2^0", "2^40".
[[nodiscard]] std::string pow2_text(int exponent);

/// Mantissa bits of the arithmetic `method` computes `kind` in: 24 or 53. The precision of its
/// inputs, except for the built-in methods that compute in double on float inputs (`mt-double`;
/// `robust` on triangles: its watertight test runs in double).
[[nodiscard]] int arithmetic_bits(const std::string& method, Precision inputs, io::Kind kind);

/// What theory predicts for the first step with class errors of one method on one knob: between
/// 2^mild and 2^stiff (mild: the end met first in the sweep), or never within the swept range.
struct Prediction {
  bool never = false;
  int mild = 0, stiff = 0;
  std::string why;  ///< the derivation, one sentence
};

/// The prediction for a method on a knob, or nothing where this theory predicts nothing (sliver,
/// far_small, ellipsoid; the derivations are in stability_text.cpp and docs/stability.md).
/// `promise`: a method promising the exact class is predicted never to break.
[[nodiscard]] std::optional<Prediction> predict(const gen::Knob& knob, const std::string& method, Precision inputs,
                                                const Promise& promise);

/// How a measured break compares with a prediction. The break lies between the last step without
/// class errors above the threshold and the first with them; `as_predicted` when that interval
/// meets the predicted window (or when neither breaks in range), else `earlier` or `later`.
enum class Agreement { as_predicted, earlier, later };
[[nodiscard]] Agreement agreement(const gen::Knob& knob, const verify::StabilityCurve& c, const verify::Break& b,
                                  const Prediction& p);

/// The table cell of a break: "2^-17", or "never up to 2^-59" (the last step of the knob).
[[nodiscard]] std::string break_cell(const gen::Knob& knob, std::optional<int> exponent);
/// The prediction cell: "2^-16 .. 2^-24", "2^-24", "never in range", or "" (no prediction).
[[nodiscard]] std::string prediction_cell(const std::optional<Prediction>& p);

/// The markdown table "where each method breaks": one row per knob x method.
[[nodiscard]] std::string breaks_table(const verify::StabilityRun& run);

/// Per knob with a derivation (not only the exact-class promise), one sentence: the prediction and its derivation, then each method's
/// measured break, "as predicted" or "earlier" / "later" with the reason when one is known.
[[nodiscard]] std::vector<std::string> prediction_sentences(const verify::StabilityRun& run);

}  // namespace rayproof::report
