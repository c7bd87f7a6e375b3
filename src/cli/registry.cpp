#include "cli/registry.h"

#include <fmt/core.h>

#include "verify/certified.h"
#include "verify/exact.h"

namespace rayproof::cli {

const MethodRegistry& all_methods() {
  static const MethodRegistry reg = [] {
    MethodRegistry r;
    register_fast_methods(r);
    verify::register_exact_method(r);
    register_robust_methods(r);
    verify::register_certified_method(r);
    return r;
  }();
  return reg;
}

std::optional<std::vector<const Method*>> select_methods(std::string_view command, const std::vector<std::string>& names,
                                                        bool with_exact) {
  const MethodRegistry& reg = all_methods();
  std::vector<const Method*> methods;
  if (names.empty()) {
    for (const auto& m : reg.all())
      if (with_exact || m.name != "exact") methods.push_back(&m);
    return methods;
  }
  for (const auto& name : names) {
    const Method* m = reg.find(name);
    if (!m) {
      fmt::print(stderr, "rayproof {}: unknown method '{}' (known: {})\n", command, name, reg.names());
      return std::nullopt;
    }
    methods.push_back(m);
  }
  return methods;
}

}  // namespace rayproof::cli
