/// rayproof glsl-host (hidden): the child process of a --glsl kernel (src/methods/glsl_kernel.h):
/// compiles the shader, opens the Vulkan device and answers batches in binary frames on stdin/stdout.
#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "cli/commands.h"
#include "methods/glsl_kernel.h"

namespace rayproof::cli {

namespace {
struct GlslHostOptions {
  std::string file, precision = "float";
  int device = 0;
  bool no_contraction = false;
};
}  // namespace

Run add_glsl_host(CLI::App& app) {
  auto o = std::make_shared<GlslHostOptions>();
  auto* sub = app.add_subcommand("glsl-host", "Run a --glsl shader for a parent rayproof (binary frames on stdin/stdout)");
  sub->group("");  // hidden: --glsl runs it
  sub->add_option("--file", o->file, "The GLSL file")->required();
  sub->add_option("--precision", o->precision)->check(CLI::IsMember({"float", "double"}));
  sub->add_option("--device", o->device);
  sub->add_flag("--no-contraction", o->no_contraction);
  return [o] {
    return run_glsl_host(o->file, o->precision == "double" ? Precision::float64 : Precision::float32, o->device,
                         o->no_contraction);
  };
}

}  // namespace rayproof::cli
