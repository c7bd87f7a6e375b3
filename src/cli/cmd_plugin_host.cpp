/// rayproof plugin-host PATH.so (hidden): loads a plugin (rayproof/plugin.h) and answers the line
/// protocol (docs/kernel_protocol.md) on standard input and output, so that a plugin can run in a
/// child process as an --exec kernel, where its crash is a reported kernel failure instead of
/// rayproof's own.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <system_error>

#include "cli/commands.h"
#include "cli/plugin_host.h"
#include "methods/plugin_kernel.h"
#include "methods/serve.h"

namespace rayproof::cli {

namespace {

int run_plugin_host(const std::string& path) {
  auto loaded = load_plugin_method(path);
  if (auto* why = std::get_if<std::string>(&loaded)) {
    fmt::print(stderr, "rayproof plugin-host: {}\n", *why);
    return 2;
  }
  std::ios::sync_with_stdio(false);
  return serve_kernel_protocol(std::get<Method>(loaded), std::cin, std::cout);
}

}  // namespace

std::unique_ptr<Method> make_plugin_kernel(std::string_view command, const std::string& spec, bool in_process) {
  const auto eq = spec.find('=');
  const std::string name = eq == std::string::npos ? std::string() : spec.substr(0, eq);
  const std::string path = eq == std::string::npos ? spec : spec.substr(eq + 1);
  if (eq != std::string::npos && name.empty()) {
    fmt::print(stderr, "rayproof {}: --plugin '{}': empty NAME (NAME=PATH.so or PATH.so)\n", command, spec);
    return nullptr;
  }
  if (path.empty()) {
    fmt::print(stderr, "rayproof {}: --plugin '{}': no PATH (NAME=PATH.so or PATH.so)\n", command, spec);
    return nullptr;
  }
  if (in_process) {
    auto loaded = load_plugin_method(path, name);
    if (auto* why = std::get_if<std::string>(&loaded)) {
      fmt::print(stderr, "rayproof {}: {}\n", command, *why);
      return nullptr;
    }
    return std::make_unique<Method>(std::move(std::get<Method>(loaded)));
  }
  fmt::print(stderr, "rayproof {}: --plugin '{}': forked plugins need the --exec kernels, not built yet\n", command, spec);
  return nullptr;
}

Run add_plugin_host(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  auto* sub = app.add_subcommand("plugin-host", "Serve a plugin (rayproof/plugin.h) over the line protocol on stdin/stdout");
  sub->group("");  // hidden: --plugin's forked mode runs it
  sub->add_option("plugin", *path, "The plugin's shared library")->required();
  return [path] { return run_plugin_host(*path); };
}

}  // namespace rayproof::cli
