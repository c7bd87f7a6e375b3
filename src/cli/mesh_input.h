#pragma once
/// A mesh file read and its ExactMesh built, for the commands that query a mesh (contains,
/// distance, cast --query crossings, bench distance, intersect), with one clear error per failure.
#include <memory>
#include <optional>
#include <string>

#include "mesh/mesh.h"
#include "rayproof/scene/exact_mesh.h"

namespace rayproof::cli {

struct MeshInput {
  mesh::Mesh mesh;
  std::unique_ptr<ExactMesh> closed;
};

/// Reads `path` (any mesh: open, a soup). On failure prints `ME: ...` to stderr (the reader's
/// message, or `PATH: the mesh has no triangles`) and returns nothing.
[[nodiscard]] std::optional<mesh::Mesh> read_mesh_file(const char* me, const std::string& path);

/// Reads `path` and builds its ExactMesh under `rule`. On failure prints `ME: ...` to stderr (the
/// reader's message, `PATH: the mesh has no triangles`, or why ExactMesh refused the arrays) and
/// returns nothing.
[[nodiscard]] std::optional<MeshInput> read_closed_mesh(const char* me, const std::string& path,
                                                        ContainsRule rule = ContainsRule::automatic);

}  // namespace rayproof::cli
