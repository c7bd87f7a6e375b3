#pragma once
/// The words for a t error of u ulps (verify::ulp_distance, Stats::ulps), one wording for every
/// table and sentence that prints one: `report`, `check` (the command and rayproof.check in Python)
/// and `verify`'s mismatch lines.
#include <cstdint>
#include <string>

#include "methods/method.h"

namespace rayproof::verify {

/// The ulp distance that stands for a NaN t, or a t present on one side only.
inline constexpr std::uint64_t kNaNUlps = UINT64_MAX;

/// A t error of `u` ulps in precision p: the number below 10^6; above, the number in exponent form
/// with what it means: "(rel. <= 2e-07)" (an upper bound on the relative error: u ulps of a normal t
/// are at most u 2^-52 of it in double, u 2^-23 in float), or "(leading bits wrong)" once u reaches
/// 2^52 (2^23): t off by about a factor of 2 or more, or on the other side of zero. "NaN t" for
/// kNaNUlps.
[[nodiscard]] std::string ulp_text(std::uint64_t u, Precision p);

/// The number alone: "NaN t", the integer below 10^6, else "4.5e+18".
[[nodiscard]] std::string ulp_number(std::uint64_t u);

/// The reading alone: "leading bits wrong" or "rel. <= 2e-07" beyond 10^6 ulps; "" below, and for NaN.
[[nodiscard]] std::string ulp_note(std::uint64_t u, Precision p);

}  // namespace rayproof::verify
