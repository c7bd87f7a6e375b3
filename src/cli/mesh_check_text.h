#pragma once
/// What `rayproof check --mesh` and `fuzz --mesh` print about mesh checks: the
/// table, the leak lines and the sentences. Kept apart from the commands so that a test can build
/// them from known tallies.
#include <string>
#include <vector>

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
