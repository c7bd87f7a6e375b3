// The parse-and-run loop and the table of commands.
#include "cli/tool.h"

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <exception>

#include "registry/registry.h"

namespace rayproof::cli {

void add_commands(CLI::App& app, Commands& out) {
  app.description("rayproof: fast ray intersection kernels, verified against exact arithmetic");
  app.require_subcommand(1);
  auto add = [&](Run run) { out.emplace_back(app.get_subcommands({}).back(), std::move(run)); };
  add(add_classify(app));
  add(add_gen(app));
  add(add_verify(app));
  add(add_report(app));
  add(add_fuzz(app));
  add(add_check(app));
  add(add_spawn(app));
  add(add_serve(app));
  add(add_plugin_host(app));
  add(add_opencl_host(app));
  add(add_glsl_host(app));
  add(add_irradiance(app));
  app.add_subcommand("methods", "List the registered methods");
  add([] {
    for (const auto& m : registry::all_methods().all())
      fmt::print("{:<16} {:<7} {}\n", m.name, m.precision == rayproof::Precision::float32 ? "float" : "double",
                 m.summary);
    return 0;
  });
  add(add_cast(app));
  add(add_render(app));
  add(add_bench(app));
  {  // the bench subcommands before bench itself: the loop runs the first parsed command
    using AddSub = Run (*)(CLI::App&);
    CLI::App* bench = app.get_subcommand("bench");
    for (const auto& [name, add_sub] : {std::pair<const char*, AddSub>{"contains", &add_bench_contains},
                                        {"crossings", &add_bench_crossings}, {"distance", &add_bench_distance},
                                        {"intersect", &add_bench_intersect}}) {
      Run run = add_sub(*bench);
      out.insert(out.begin(), {bench->get_subcommand(name), std::move(run)});
    }
  }
  add(add_advise(app));
  add(add_contains(app));
  add(add_distance(app));
  add(add_intersect(app));
}

int rayproof_main(int argc, char** argv) {
  CLI::App app;
  Commands commands;
  add_commands(app, commands);
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
