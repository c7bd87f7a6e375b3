#pragma once
/// Every method the command-line tool knows, fast and exact, in one registry.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "methods/method.h"

namespace rayproof::cli {

/// The registry of all methods (built once).
[[nodiscard]] const MethodRegistry& all_methods();

/// The methods a command's --methods option names, in that order; with no names, every registered
/// method (but `exact` unless with_exact). An unknown name prints "rayproof COMMAND: unknown method
/// 'NAME' (known: ...)" to standard error and gives nothing.
[[nodiscard]] std::optional<std::vector<const Method*>> select_methods(std::string_view command,
                                                                       const std::vector<std::string>& names,
                                                                       bool with_exact);

}  // namespace rayproof::cli
