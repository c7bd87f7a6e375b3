/// rayproof serve --method NAME: a built-in method as an external kernel, answering case lines on
/// standard input over the line protocol (docs/kernel_protocol.md), so that it can be put under
/// test through --exec exactly as a user's program is.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "registry/registry.h"
#include "methods/serve.h"

namespace rayproof::cli {

namespace {
struct ServeOptions {
  std::string method;
  bool no_header = false;
};

int run_serve(const ServeOptions& opt) {
  const MethodRegistry& reg = registry::all_methods();
  const Method* m = reg.find(opt.method);
  if (!m) {
    fmt::print(stderr, "rayproof serve: unknown method '{}' (known: {})\n", opt.method, reg.names());
    return 2;
  }
  std::ios::sync_with_stdio(false);
  return serve_kernel_protocol(*m, std::cin, std::cout, !opt.no_header);
}
}  // namespace

Run add_serve(CLI::App& app) {
  auto opt = std::make_shared<ServeOptions>();
  auto* sub = app.add_subcommand(
      "serve", "Answer case lines on standard input with a built-in method, as an --exec kernel (docs/kernel_protocol.md)");
  sub->add_option("--method", opt->method, "The method that answers")->required();
  sub->add_flag("--no-header", opt->no_header, "Do not print the declaration line (declare it in the --exec spec)");
  return [opt] { return run_serve(*opt); };
}

}  // namespace rayproof::cli
