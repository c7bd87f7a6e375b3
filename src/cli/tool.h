#pragma once
/// The rayproof tool: every command registered on one CLI11 app, and the parse-and-run loop.
#include <utility>
#include <vector>

#include "cli/commands.h"

namespace rayproof::cli {

/// Each registered subcommand with the function that runs it; the loop runs the first parsed one.
using Commands = std::vector<std::pair<CLI::App*, Run>>;

/// Registers every command on `app` (its description and rules too; its name comes from argv[0]).
void add_commands(CLI::App& app, Commands& out);

/// `rayproof`'s main. (Here rather than in main.cpp so that CLI11's code is generated once, in this
/// library's unity batch.)
int rayproof_main(int argc, char** argv);

/// Parses argv and runs the chosen command: its exit status; 2 with "rayproof: ..." on an error.
int run_tool(CLI::App& app, Commands& commands, int argc, char** argv);

}  // namespace rayproof::cli
