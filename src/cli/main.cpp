/// rayproof: fast ray intersection kernels checked against exact arithmetic. This executable holds
/// the case-level commands; the scene commands run in rayproof-scene beside it (scene_commands.h).
#include <CLI/CLI.hpp>

#include "cli/scene_commands.h"
#include "cli/tool.h"

int main(int argc, char** argv) {
  using namespace rayproof::cli;
  if (argc > 1 && find_scene_command(argv[1])) return forward_to_scene(argc, argv);
  CLI::App app;
  setup_app(app);
  Commands commands;
  add_core_commands(app, commands);
  add_scene_forwarders(app, commands, argc, argv);
  return run_tool(app, commands, argc, argv);
}
