/// rayproof-scene: the whole rayproof tool, the scene commands compiled in (scene_commands.h).
/// `rayproof` runs it for those commands; it can be run directly too.
#include <CLI/CLI.hpp>

#include "cli/tool.h"

int main(int argc, char** argv) {
  using namespace rayproof::cli;
  CLI::App app;
  setup_app(app);
  Commands commands;
  add_core_commands(app, commands);
  add_scene_commands(app, commands);
  return run_tool(app, commands, argc, argv);
}
