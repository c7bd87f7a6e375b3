#pragma once
/// What `rayproof check` prints about a CheckResult: the verdict table, the reproducer lines and the
/// sentences. Kept apart from the command so that a test can build them from known tallies.
#include <string>
#include <vector>

#include "verify/check.h"

namespace rayproof::cli {

/// "NaN t" for a missing or NaN t (the maximum ulp distance), else the number.
[[nodiscard]] std::string ulp_text(std::uint64_t u);

/// One row per family and an "(all)" row: cases, false hits, false misses, wrong class, t error
/// median/p99/max, over tolerance, failures.
[[nodiscard]] std::string check_table(const verify::CheckResult& r);

/// The worst reproducers as case-file lines with a comment (family, verdict, answer, exact answer).
[[nodiscard]] std::vector<std::string> reproducer_lines(const verify::CheckResult& r);

/// The sentences about the result, each true for the counts it states: class errors, t error,
/// failures, then one per stated promise and the overall verdict.
[[nodiscard]] std::vector<std::string> check_sentences(const verify::CheckResult& r);

}  // namespace rayproof::cli

#include "verify/mesh_check.h"

namespace rayproof::cli {

/// One row per mesh and an "(all)" row: triangles, rays, candidate cases, leaks, rays without a
/// candidate, failures.
[[nodiscard]] std::string mesh_table(const std::vector<verify::MeshCheck>& r);

/// Each kept leak: a comment line with the mesh and the ray, then its candidate triangles as case
/// lines (as the kernel saw them) with the kernel's answer and the finder's class.
[[nodiscard]] std::vector<std::string> leak_lines(const std::vector<verify::MeshCheck>& r, const std::string& finder);

/// The sentences about a mesh check, true for the counts they state.
[[nodiscard]] std::vector<std::string> mesh_sentences(const std::vector<verify::MeshCheck>& r);

}  // namespace rayproof::cli
