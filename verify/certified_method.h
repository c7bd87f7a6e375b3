#pragma once
/// The certified method: the floating-point filters of rayproof/certified_*.h decide the class and
/// pin T, T2 to one double ulp; whatever they leave undecided falls back to certified::fallback
/// (GMP, src/exact/fallback.h), the same as rayproof::certified::intersect.
/// Its answers have the exact class on every case and T, T2 within 1 ulp of the exact ones.
#include <cstdint>
#include <optional>

#include "io/case_file.h"
#include "methods/method.h"
#include "rayproof/hit.h"

namespace rayproof::verify {

/// The filter alone: the certified answer, or nothing when it needs the exact fallback.
[[nodiscard]] std::optional<Hit<double>> certified_filter(const io::Case& c);

/// Filter, then exact fallback; counts fallbacks in `fallbacks` when given.
[[nodiscard]] io::CaseResult certified_classify(const io::Case& c, std::uint64_t* fallbacks = nullptr);

/// Fallbacks taken by the registered `certified` method on the calling thread since it started.
[[nodiscard]] std::uint64_t certified_fallbacks();

/// Registers the `certified` method.
void register_certified_method(MethodRegistry& reg);

}  // namespace rayproof::verify
