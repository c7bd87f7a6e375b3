#pragma once
/// Triangle meshes read from OFF, OBJ, PLY (ASCII, binary little and big endian) and STL (ASCII
/// and binary) by rayproof's own readers, and glTF 2.0 (.gltf, .glb) through Debian's tinygltf.
/// Polygons are fan-triangulated. Bad input is a MeshError whose message names the file and the
/// line (text formats), the byte offset (binary formats) or, for glTF, the object ("FILE:
/// meshes[0].primitives[1]: ..."); no reader trusts a count from a header to size an allocation
/// before the file has shown it holds that much data.
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

/// Axis-aligned bounds of a mesh's vertices: all of them, or (`used_only`) those the triangles
/// index. Needs at least one such vertex (the caller checks the mesh is not empty).
struct VertexBounds {
  Vec3<double> lo, hi;
  [[nodiscard]] Vec3<double> extent() const { return hi - lo; }
};
[[nodiscard]] VertexBounds vertex_bounds(const Mesh& m, bool used_only);

/// Malformed input: "FILE:LINE: what", "FILE: byte N: what", or for glTF "FILE: WHERE: what"
/// (WHERE a glTF object such as accessors[3]) and "FILE: glTF (tinygltf): what" (tinygltf's message).
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class MeshFormat { off, obj, ply, stl, gltf };  ///< gltf: .gltf and .glb

/// The format named by a file's extension (case-insensitive); throws MeshError when unknown.
[[nodiscard]] MeshFormat format_of(const std::string& path);
[[nodiscard]] bool is_mesh_path(const std::string& path);

/// Which reader answers a format: "rayproof's OFF reader", ..., "tinygltf 2.7.0" (or, built
/// without it, a sentence saying so). The commands print it in their load messages.
[[nodiscard]] std::string reader_name(MeshFormat f);

/// Reads a mesh file; throws MeshError on any problem (missing file included).
[[nodiscard]] Mesh read_mesh(const std::string& path);
/// Reads from a stream; `name` is the file name used in messages. The stream must be binary-safe.
[[nodiscard]] Mesh read_mesh(std::istream& in, MeshFormat f, const std::string& name);

[[nodiscard]] Mesh read_off(std::istream& in, const std::string& name);
[[nodiscard]] Mesh read_obj(std::istream& in, const std::string& name);
[[nodiscard]] Mesh read_ply(std::istream& in, const std::string& name);
[[nodiscard]] Mesh read_stl(std::istream& in, const std::string& name);
/// glTF 2.0, text (.gltf; buffers in data: URIs or in files beside `name`) or binary (.glb; the
/// magic decides): the triangle primitives (mode 4) of the default scene's nodes, in world space
/// (node matrices or TRS applied); with no scene, every mesh untransformed. Other primitive modes,
/// sparse accessors and geometry extensions (Draco, meshopt, quantization) are refused.
[[nodiscard]] Mesh read_gltf(std::istream& in, const std::string& name);

/// Writers for tests and generated data (OFF text; binary STL).
void write_off(std::ostream& out, const Mesh& m);
void write_stl_binary(std::ostream& out, const Mesh& m);

}  // namespace rayproof::mesh
