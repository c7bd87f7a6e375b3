#pragma once
/// What both executables share: the case-level commands, the scene commands' forwarding and the
/// parse-and-run loop (main.cpp: `rayproof`; main_scene.cpp: `rayproof-scene`).
#include <string_view>
#include <utility>
#include <vector>

#include "cli/commands.h"

namespace rayproof::cli {

/// Each registered subcommand with the function that runs it; the loop runs the first parsed one.
using Commands = std::vector<std::pair<CLI::App*, Run>>;

/// The top-level app's description and rules (its name comes from argv[0] at parse time).
void setup_app(CLI::App& app);

/// classify, gen, verify, report, check, fuzz, spawn, serve, the three hosts, irradiance and methods;
/// the --mesh modes of check, fuzz and spawn through `modes` (empty: handed to rayproof-scene).
void add_core_commands(CLI::App& app, Commands& out, const MeshModes& modes);

/// The scene commands (scene_commands.h), compiled in: only in rayproof-scene (rayproof_cli_lib).
void add_scene_commands(CLI::App& app, Commands& out);

/// The scene commands as entries that `rayproof --help` lists; running one forwards.
void add_scene_forwarders(CLI::App& app, Commands& out);

/// Replaces this process with `rayproof-scene` beside the running executable, with the same
/// arguments (argv[0] included, so its messages and help read as this tool's): those of
/// rayproof_main's call. Returns only on failure, with status 2 after saying that `what` (a
/// command, or a command's mode) is in rayproof-scene and how to build it.
int forward_to_scene(std::string_view what);

/// `rayproof`'s main: the case-level commands, the scene commands forwarded. (Here rather than in
/// main.cpp so that CLI11's code is generated once, in this library's unity batch.)
int rayproof_main(int argc, char** argv);

/// `rayproof-scene`'s main: every command compiled in (scene_commands.cpp).
int rayproof_scene_main(int argc, char** argv);

/// Parses argv and runs the chosen command: its exit status; 2 with "rayproof: ..." on an error.
int run_tool(CLI::App& app, Commands& commands, int argc, char** argv);

}  // namespace rayproof::cli
