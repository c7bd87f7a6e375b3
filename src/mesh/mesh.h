#pragma once
/// Triangle meshes read from OFF, OBJ, PLY (ASCII, binary little and big endian) and STL (ASCII
/// and binary). Polygons are fan-triangulated. Bad input is a MeshError whose message names the
/// file and the line (text formats) or byte offset (binary formats); no reader trusts a count from
/// a header to size an allocation before the file has shown it holds that much data.
#include <array>
#include <cstdint>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

#include "rayproof/vec3.h"

namespace rayproof::mesh {

struct Mesh {
  std::vector<Vec3<double>> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< indices into vertices
};

/// Malformed input: "FILE:LINE: what" or "FILE: byte N: what".
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class MeshFormat { off, obj, ply, stl };

/// The format named by a file's extension (case-insensitive); throws MeshError when unknown.
[[nodiscard]] MeshFormat format_of(const std::string& path);
[[nodiscard]] bool is_mesh_path(const std::string& path);

/// Reads a mesh file; throws MeshError on any problem (missing file included).
[[nodiscard]] Mesh read_mesh(const std::string& path);
/// Reads from a stream; `name` is the file name used in messages. The stream must be binary-safe.
[[nodiscard]] Mesh read_mesh(std::istream& in, MeshFormat f, const std::string& name);

[[nodiscard]] Mesh read_off(std::istream& in, const std::string& name);
[[nodiscard]] Mesh read_obj(std::istream& in, const std::string& name);
[[nodiscard]] Mesh read_ply(std::istream& in, const std::string& name);
[[nodiscard]] Mesh read_stl(std::istream& in, const std::string& name);

/// Writers for tests and generated data (OFF text; binary STL).
void write_off(std::ostream& out, const Mesh& m);
void write_stl_binary(std::ostream& out, const Mesh& m);

}  // namespace rayproof::mesh
