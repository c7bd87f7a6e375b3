#pragma once
/// Loading a scene, its BVH and the method for the scene commands (cast, render, bench), with one
/// clear message on failure.
#include <fmt/core.h>

#include <memory>
#include <optional>
#include <string>

#include "registry/registry.h"
#include "mesh/mesh.h"
#include "scene/scene_caster.h"
#include "scene/accel.h"

namespace rayproof::cli {

using scene::CastHit;
using scene::SceneCaster;
using scene::to_cast_hit;

/// " (read by tinygltf 2.7.0)", " (read by rayproof's OFF reader)", ... for a mesh file; "" else.
inline std::string reader_note(const std::string& path) {
  if (!mesh::is_mesh_path(path)) return "";
  return " (read by " + mesh::reader_name(mesh::format_of(path)) + ")";
}

struct LoadedScene {
  std::unique_ptr<scene::Scene> scene;
  std::unique_ptr<SceneCaster> caster;  ///< the public MeshCaster for meshes, else the scene BVH
  scene::SceneMethod method;
};

/// `path` is a mesh file, a scene JSON, or "default" (the built-in scene). Prints
/// "rayproof CMD: message" and returns nothing on failure. `verbose`: says on standard error what
/// was loaded and which reader read it.
inline std::optional<LoadedScene> load_scene_for_cli(const char* cmd, const std::string& path, const std::string& method,
                                                     const std::string& builder, bool verbose = false) {
  try {
    LoadedScene l;
    l.method = scene::find_scene_method(method, registry::all_methods());
    l.scene = std::make_unique<scene::Scene>(path == "default" ? scene::default_scene() : scene::load_scene(path));
    BvhBuildOptions opt;
    opt.builder = builder == "median" ? BvhBuilder::median : BvhBuilder::sah;
    if (verbose)
      fmt::print(stderr, "rayproof {}: {}: {} triangles, {} primitives{}\n", cmd, path, l.scene->mesh.triangles.size(),
                 l.scene->size(), reader_note(path));
    l.caster = std::make_unique<SceneCaster>(*l.scene, l.method, opt);
    return l;
  } catch (const std::exception& e) {
    fmt::print(stderr, "rayproof {}: {}\n", cmd, e.what());
    return std::nullopt;
  }
}

}  // namespace rayproof::cli
