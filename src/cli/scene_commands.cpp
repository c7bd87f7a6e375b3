// The scene commands registered for real (rayproof-scene and the libraries' users).
#include <CLI/CLI.hpp>

#include "cli/mesh_modes.h"
#include "cli/tool.h"

namespace rayproof::cli {

void add_scene_commands(CLI::App& app, Commands& out) {
  auto add = [&](Run run) { out.emplace_back(app.get_subcommands({}).back(), std::move(run)); };
  add(add_cast(app));
  add(add_render(app));
  add(add_bench(app));
  {  // `bench contains` before bench itself: the loop runs the first parsed command
    CLI::App* bench = app.get_subcommands({}).back();
    Run run = add_bench_contains(*bench);
    out.insert(out.begin(), {bench->get_subcommand("contains"), std::move(run)});
  }
  add(add_advise(app));
  add(add_contains(app));
}

int rayproof_scene_main(int argc, char** argv) {
  CLI::App app;
  setup_app(app);
  Commands commands;
  add_core_commands(app, commands, scene_mesh_modes());
  add_scene_commands(app, commands);
  return run_tool(app, commands, argc, argv);
}

}  // namespace rayproof::cli
