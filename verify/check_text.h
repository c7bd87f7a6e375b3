#pragma once
/// What a check of one kernel says about its CheckResult (verify/check.h): the verdict table, the
/// reproducer lines and the sentences. `rayproof check` prints them, and rayproof.check in Python
/// returns the same table; t errors are worded by verify/ulp_text.h, as in `report`. Kept apart from
/// the commands so that a test can build them from known tallies.
#include <string>
#include <vector>

#include "verify/check.h"

namespace rayproof::verify {

/// n and the noun in its number: "1 case", "2 cases" (every sentence that counts something).
std::string plural(std::size_t n, const char* one, const char* many);

/// One row per family and an "(all)" row: cases, false hits, false misses, wrong class, t error
/// median/p99/max (ulp_text), over tolerance, failures. Columns widen to their widest cell.
[[nodiscard]] std::string check_table(const CheckResult& r);

/// The worst reproducers as case-file lines with a comment (family, verdict, answer, exact answer).
[[nodiscard]] std::vector<std::string> reproducer_lines(const CheckResult& r);

/// The sentences about the result, each true for the counts it states: class errors, t error,
/// failures, then one per stated promise and the overall verdict.
[[nodiscard]] std::vector<std::string> check_sentences(const CheckResult& r);

}  // namespace rayproof::verify
