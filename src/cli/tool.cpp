// The parse-and-run loop and the case-level commands of both executables; the scene commands'
// forwarding from `rayproof` to `rayproof-scene` (scene_commands.h says why there are two).
#include "cli/tool.h"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>
#include <filesystem>
#include <string>

#include "cli/mesh_modes.h"
#include "cli/registry.h"
#include "cli/scene_commands.h"

namespace rayproof::cli {

std::string scene_command_summary(std::string_view name) {
  const SceneCommand* c = find_scene_command(name);
  return c ? std::string(c->summary) : std::string();
}

void setup_app(CLI::App& app) {
  app.description("rayproof: fast ray intersection kernels, verified against exact arithmetic");
  app.require_subcommand(1);
}

void add_core_commands(CLI::App& app, Commands& out, const MeshModes& modes) {
  auto add = [&](Run run) { out.emplace_back(app.get_subcommands({}).back(), std::move(run)); };
  add(add_classify(app));
  add(add_gen(app));
  add(add_verify(app));
  add(add_report(app));
  add(add_fuzz(app, modes));
  add(add_check(app, modes));
  add(add_spawn(app, modes));
  add(add_serve(app));
  add(add_plugin_host(app));
  add(add_opencl_host(app));
  add(add_glsl_host(app));
  add(add_irradiance(app));
  app.add_subcommand("methods", "List the registered methods");
  add([] {
    for (const auto& m : all_methods().all())
      fmt::print("{:<16} {:<7} {}\n", m.name, m.precision == rayproof::Precision::float32 ? "float" : "double",
                 m.summary);
    return 0;
  });
}

namespace {
int g_argc = 0;  // rayproof_main's arguments, for forward_to_scene
char** g_argv = nullptr;
}  // namespace

int forward_to_scene(std::string_view what) {
  const int argc = g_argc;
  char** argv = g_argv;
  if (!argv) {
    fmt::print(stderr, "rayproof: {} is in rayproof-scene, which this program does not run\n", what);
    return 2;
  }
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) self = fs::absolute(argv[0], ec);
  const fs::path scene = self.parent_path() / "rayproof-scene";
  std::vector<char*> args(argv, argv + argc);
  args.push_back(nullptr);
  ::execv(scene.c_str(), args.data());
  const int err = errno;
  if (err == ENOENT)
    fmt::print(stderr,
               "rayproof: '{}' is in {}, which this build has not built yet: the commands that traverse BVHs over "
               "meshes ({}, and the --mesh modes of check, fuzz and spawn) are compiled there, and the README's first command builds only "
               "`rayproof`. Build it with: cmake --build <build dir> --target rayproof-scene\n",
               what, scene.string(), [] {
                 std::string names;
                 for (const auto& c : kSceneCommands) names += (names.empty() ? "" : ", ") + std::string(c.name);
                 return names;
               }());
  else
    fmt::print(stderr, "rayproof: cannot run {} for '{}': {}\n", scene.string(), what, std::strerror(err));
  return 2;
}

void add_scene_forwarders(CLI::App& app, Commands& out) {
  for (const auto& c : kSceneCommands) {
    auto* sub = app.add_subcommand(std::string(c.name), std::string(c.summary));
    sub->set_help_flag();  // its --help goes to rayproof-scene with the rest
    sub->allow_extras();
    sub->prefix_command();
    out.emplace_back(sub, [name = std::string(c.name)] { return forward_to_scene(name); });
  }
}

int rayproof_main(int argc, char** argv) {
  g_argc = argc, g_argv = argv;
  if (argc > 1 && find_scene_command(argv[1])) return forward_to_scene(argv[1]);
  CLI::App app;
  setup_app(app);
  Commands commands;
  add_core_commands(app, commands, MeshModes{});
  add_scene_forwarders(app, commands);
  return run_tool(app, commands, argc, argv);
}

int run_tool(CLI::App& app, Commands& commands, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    for (auto& [sub, run] : commands)
      if (sub->parsed()) return run();
  } catch (const std::exception& e) {
    fmt::print(stderr, "rayproof: {}\n", e.what());
    return 2;
  }
  return 2;
}

}  // namespace rayproof::cli
