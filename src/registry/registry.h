#pragma once
/// Every method the command-line tool knows, fast and exact, in one registry.
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "methods/method.h"

namespace rayproof::registry {

/// The registry of all methods (built once).
[[nodiscard]] const MethodRegistry& all_methods();

/// The methods a command's --methods option names, in that order; with no names, every registered
/// method (but `exact` unless with_exact). An unknown name prints "rayproof COMMAND: unknown method
/// 'NAME' (known: ...)" to standard error and gives nothing.
[[nodiscard]] std::optional<std::vector<const Method*>> select_methods(std::string_view command,
                                                                       const std::vector<std::string>& names,
                                                                       bool with_exact);

/// The same with the user's kernels (--exec, --plugin, ...: cli/user_kernels.h) as methods like the
/// others: a name in --methods is looked up among them first, then in the registry, and lands at its
/// place in the order. A user's kernel runs whether the list names it or not (giving it is asking for
/// it); those the list leaves out follow the named ones. With no names: every registered method (but
/// `exact` unless with_exact), then every user kernel. An unknown name prints "rayproof COMMAND:
/// unknown method 'NAME' (known: ..., your kernels: ...)" and gives nothing.
[[nodiscard]] std::optional<std::vector<const Method*>> select_methods(std::string_view command,
                                                                       const std::vector<std::string>& names,
                                                                       bool with_exact,
                                                                       const std::vector<std::unique_ptr<Method>>& user);

/// True when `name` is one of the user's kernels.
[[nodiscard]] bool is_user_kernel(std::string_view name, const std::vector<std::unique_ptr<Method>>& user);

}  // namespace rayproof::registry
