#pragma once
/// What `rayproof check` prints: about a CheckResult, verify/check_text.h (shared with the Python
/// module); about a mesh check, the table, the leak lines and the sentences below. Kept apart from the
/// command so that a test can build them from known tallies.
#include <string>
#include <vector>

#include "verify/check_text.h"

namespace rayproof::cli {

using verify::check_sentences;
using verify::check_table;
using verify::reproducer_lines;

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
