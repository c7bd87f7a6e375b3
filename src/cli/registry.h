#pragma once
/// Every method the command-line tool knows, fast and exact, in one registry.
#include "methods/method.h"

namespace rayproof::cli {

/// The registry of all methods (built once).
[[nodiscard]] const MethodRegistry& all_methods();

}  // namespace rayproof::cli
