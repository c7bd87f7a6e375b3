#pragma once
/// Every sentence the report writes about results, built from tallies (Row, Point) in one place so
/// that a test can build each one from known numbers. report.cpp only lays them out.
#include <cstdint>
#include <string>
#include <vector>

#include "methods/method.h"
#include "report/report.h"
#include "verify/differential.h"

namespace rayproof::report {

/// A t error of `u` ulps in precision p as a table cell: verify::ulp_text (verify/ulp_text.h), the
/// one wording of report, check and Python's rayproof.check.
[[nodiscard]] std::string ulp_text(std::uint64_t u, Precision p);

/// The t tolerance a row is judged under: what the method promises on the kind (Promise::t_ulps),
/// else `report_tolerance`.
[[nodiscard]] std::uint64_t tolerance(const Promise& promised, std::uint64_t report_tolerance);

/// Error-free: cases, no class error, no kernel failure, and every class-correct t within `tol` ulps.
[[nodiscard]] bool error_free(const verify::Stats& s, std::uint64_t tol);

/// The paragraph under the legend: what "error-free" means in this report.
[[nodiscard]] std::string error_free_definition(std::uint64_t report_tolerance);

/// The sentences under one kind's tables (rows of that kind only, one per method x family): the
/// cheapest method error-free on every family; family by family the cheapest error-free method; the
/// families where the cheapest method without class error has its t beyond tolerance.
[[nodiscard]] std::vector<std::string> kind_sentences(io::Kind kind, const std::vector<Row>& rows,
                                                      std::uint64_t report_tolerance);

/// One sentence per method and promise (the kinds it covers listed): what, and whether this run
/// kept it ("kept on all N cases", "broken on B of N cases").
[[nodiscard]] std::vector<std::string> promise_sentences(const std::vector<Row>& rows);

/// One sentence per row with a NaN t (class right, t NaN): how many, and the worst case as a
/// reproducer line; then one per row whose worst t error is 10^9 ulps or more: the case, the t it
/// gave and the exact t, and what the error is (relative, or wrong in the leading bits).
[[nodiscard]] std::vector<std::string> t_error_sentences(const std::vector<Row>& rows);

/// The "promise" cell of the summary and kind tables: verify::promise_status over the tally.
[[nodiscard]] std::string promise_cell(const verify::Stats& s);

}  // namespace rayproof::report
