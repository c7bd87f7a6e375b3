#pragma once
/// A scene: triangle meshes (flattened into one indexed world-space mesh), analytic primitives,
/// a camera and disk area lights. Each primitive kind is a vector, so a scene holds only the
/// kinds it uses. Primitives are numbered globally: triangles first, then spheres, ellipsoids,
/// disks and boxes; that number is the PRIM of `rayproof cast`.
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "mesh/mesh.h"
#include "rayproof/box.h"
#include "rayproof/bvh.h"
#include "rayproof/camera.h"
#include "rayproof/disk.h"
#include "rayproof/ellipsoid.h"
#include "rayproof/sphere.h"
#include "rayproof/triangle_common.h"

namespace rayproof::scene {

/// Bad scene description: "FILE: what" (JSON errors carry the byte offset).
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class PrimKind { triangle, sphere, ellipsoid, disk, box };

struct Camera {
  std::variant<PerspectiveCamera<double>, OrthographicCamera<double>> cam;
  [[nodiscard]] int width() const;
  [[nodiscard]] int height() const;
  [[nodiscard]] Ray<double> generate(int i, int j) const;
};

struct DiskLight {
  Disk<double> disk;
  Vec3<double> emission{1, 1, 1};
};

struct Scene {
  mesh::Mesh mesh;  ///< every mesh, in world space
  std::vector<Sphere<double>> spheres;
  std::vector<Ellipsoid<double>> ellipsoids;
  std::vector<Disk<double>> disks;
  std::vector<Box<double>> boxes;
  std::optional<Camera> camera;
  std::vector<DiskLight> lights;

  [[nodiscard]] std::size_t size() const {
    return mesh.triangles.size() + spheres.size() + ellipsoids.size() + disks.size() + boxes.size();
  }
  /// The kind of global primitive `id` and its index among that kind.
  [[nodiscard]] PrimKind kind_of(std::uint32_t id, std::uint32_t& local) const;
  [[nodiscard]] Triangle<double> triangle(std::uint32_t i) const {
    const auto& t = mesh.triangles[i];
    return {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
  }
  /// Bounds (float, rounded outward) and split centers of every primitive, in global order.
  void primitive_bounds(std::vector<BvhBox>& boxes_out, std::vector<Vec3<float>>& centers_out) const;
  [[nodiscard]] BvhBox bounds() const;
  /// Bytes held by the triangle data (vertices and indices).
  [[nodiscard]] std::size_t triangle_bytes() const;
};

/// A triangle's bounds (float, rounded outward) and split center, as primitive_bounds gives them.
void triangle_bounds(const Triangle<double>& t, BvhBox& box, Vec3<float>& center);

/// Adds a mesh, transformed by world_from_object, to the scene's mesh.
void add_mesh(Scene& s, const mesh::Mesh& m, const Transform<double>& world_from_object = {});

/// A scene file: a mesh file (.off .obj .ply .stl .gltf .glb) or a JSON scene description (see scene_json.cpp).
[[nodiscard]] Scene load_scene(const std::string& path);
/// A JSON scene from text; `base_dir` resolves relative mesh paths, `name` is used in messages.
[[nodiscard]] Scene parse_scene_json(const std::string& text, const std::string& base_dir, const std::string& name);

/// The built-in scene: an icosphere (subdivided `subdivisions` times), a box and a ground disk
/// under a perspective camera and one disk light.
[[nodiscard]] Scene default_scene(int subdivisions = 3, int width = 320, int height = 240);
/// A closed icosphere of radius r at c: 20 * 4^subdivisions triangles, vertices shared.
[[nodiscard]] mesh::Mesh icosphere(int subdivisions, Vec3<double> c = {0, 0, 0}, double r = 1);

/// A camera framing the scene's bounds from the +z/+y side (for meshes without a camera).
[[nodiscard]] Camera default_camera(const Scene& s, int width, int height);

}  // namespace rayproof::scene
