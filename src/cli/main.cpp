/// rayproof: fast ray intersection kernels checked against exact arithmetic.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <exception>
#include <vector>

#include "cli/commands.h"
#include "cli/registry.h"

int main(int argc, char** argv) {
  using namespace rayproof::cli;
  CLI::App app{"rayproof: fast ray intersection kernels, verified against exact arithmetic"};
  app.require_subcommand(1);
  std::vector<std::pair<CLI::App*, Run>> commands;
  auto add = [&](Run run) { commands.emplace_back(app.get_subcommands({}).back(), std::move(run)); };
  add(add_classify(app));
  add(add_gen(app));
  add(add_verify(app));
  add(add_report(app));
  add(add_fuzz(app));
  add(add_cast(app));
  add(add_render(app));
  add(add_bench(app));
  {  // `bench contains` before bench itself: the loop below runs the first parsed command
    CLI::App* bench = app.get_subcommands({}).back();
    Run run = add_bench_contains(*bench);
    commands.insert(commands.begin(), {bench->get_subcommand("contains"), std::move(run)});
  }
  add(add_check(app));
  add(add_serve(app));
  add(add_plugin_host(app));
  add(add_opencl_host(app));
  add(add_glsl_host(app));
  add(add_irradiance(app));
  add(add_spawn(app));
  add(add_advise(app));
  add(add_contains(app));
  auto* methods = app.add_subcommand("methods", "List the registered methods");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (methods->parsed()) {
      for (const auto& m : all_methods().all())
        fmt::print("{:<16} {:<7} {}\n", m.name, m.precision == rayproof::Precision::float32 ? "float" : "double",
                   m.summary);
      return 0;
    }
    for (auto& [sub, run] : commands)
      if (sub->parsed()) return run();
  } catch (const std::exception& e) {
    fmt::print(stderr, "rayproof: {}\n", e.what());
    return 2;
  }
  return 2;
}
