#pragma once
/// The `--plugin NAME=PATH.so` half of the user kernels (src/cli/user_kernels.cpp): in process
/// (methods/plugin_kernel.h), or forked as an --exec kernel running the hidden subcommand
/// `rayproof plugin-host PATH.so` (cmd_plugin_host.cpp), which serves the plugin over the line protocol.
#include <memory>
#include <string>
#include <string_view>

#include "methods/method.h"

namespace rayproof::cli {

/// The method of one `--plugin` spec, `NAME=PATH` or `PATH` (then the plugin's declared name in
/// process, the file name without its extension forked). A bad spec or plugin prints
/// "rayproof COMMAND: ..." to standard error and gives nothing.
[[nodiscard]] std::unique_ptr<Method> make_plugin_kernel(std::string_view command, const std::string& spec,
                                                         bool in_process);

}  // namespace rayproof::cli
