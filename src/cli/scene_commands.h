#pragma once
/// The scene commands: the subcommands that traverse a BVH over meshes and scenes (they link
/// rayproof_scene, whose traversal code is most of the tool's build). They are compiled into
/// `rayproof-scene`, the whole tool; `rayproof` holds the case-level commands (report, verify,
/// check, fuzz, spawn, classify, gen, ...) and runs these, and the --mesh modes of check, fuzz and spawn
/// (mesh_modes.h), by executing `rayproof-scene` beside itself with the same arguments, so that
/// the first build of `rayproof` (the README's first command) is the case-level code only. One list: `rayproof --help` names them from here and each command's own
/// registration takes its summary from here.
#include <array>
#include <string_view>

namespace rayproof::cli {

struct SceneCommand {
  std::string_view name;
  std::string_view summary;
};

inline constexpr std::array<SceneCommand, 5> kSceneCommands{{
    {"cast", "Cast rays into a scene or mesh: one result line per ray"},
    {"render", "Render a scene or mesh to PNG, shaded by normal and depth"},
    {"bench", "Throughput and leaks of every method next to Embree and CGAL"},
    {"advise", "What a scene needs: its geometry, its rays with every method, the cheapest error-free method"},
    {"contains", "Exact inside / outside / surface of points (or segments) against a closed mesh"},
}};

/// The scene command called `name`, or null.
inline const SceneCommand* find_scene_command(std::string_view name) {
  for (const auto& c : kSceneCommands)
    if (c.name == name) return &c;
  return nullptr;
}

/// The summary of scene command `name` as a std::string for CLI11 (name must be in the list).
std::string scene_command_summary(std::string_view name);

}  // namespace rayproof::cli
