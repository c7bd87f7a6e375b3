#include "cli/mesh_input.h"

#include <fmt/core.h>

#include <stdexcept>
#include <utility>

namespace rayproof::cli {

std::optional<mesh::Mesh> read_mesh_file(const char* me, const std::string& path) {
  mesh::Mesh m;
  try {
    m = mesh::read_mesh(path);
  } catch (const mesh::MeshError& e) {
    fmt::print(stderr, "{}: {}\n", me, e.what());
    return std::nullopt;
  }
  if (m.triangles.empty()) {
    fmt::print(stderr, "{}: {}: the mesh has no triangles\n", me, path);
    return std::nullopt;
  }
  return m;
}

std::optional<MeshInput> read_closed_mesh(const char* me, const std::string& path, ContainsRule rule) {
  MeshInput in;
  auto read = read_mesh_file(me, path);
  if (!read) return std::nullopt;
  in.mesh = std::move(*read);
  const mesh::Mesh& m = in.mesh;
  try {
    in.closed = std::make_unique<ExactMesh>(VertexArray(&m.vertices[0].x, m.vertices.size()),
                                             IndexArray{m.triangles.front().data(), m.triangles.size()}, rule);
  } catch (const std::invalid_argument& e) {  // MeshNotClosedError, MeshInputError
    fmt::print(stderr, "{}: {}: {}\n", me, path, e.what());
    return std::nullopt;
  }
  return in;
}

}  // namespace rayproof::cli
