#pragma once
/// Exact answers: the class of exact arithmetic on the parsed doubles and T/T2 rounded to nearest
/// double (docs/cases.md). CGAL's exact number types decide every class by signs of rational
/// quantities; square roots (quadric roots) are rounded correctly by MPFR and checked exactly.
#include <array>
#include <optional>

#include "io/case_file.h"
#include "methods/method.h"

namespace rayproof::verify {

/// Ground truth for one case. Never throws on well-formed cases (NaN and infinities are `invalid`).
[[nodiscard]] io::CaseResult exact_classify(const io::Case& c);

/// The barycentrics of p1 and p2 of the point where a triangle case's line meets the closed
/// triangle at one point (exact classes interior, edge, vertex, behind), exact and rounded to
/// nearest double; nothing for other kinds and other classes.
[[nodiscard]] std::optional<std::array<double, 2>> exact_barycentrics(const io::Case& c);

/// Registers the `exact` method.
void register_exact_method(MethodRegistry& reg);

}  // namespace rayproof::verify
