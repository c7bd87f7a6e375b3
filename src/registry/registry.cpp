#include "registry/registry.h"

#include <fmt/core.h>
#include <fmt/format.h>

#include <algorithm>

#include "verify/certified_method.h"
#include "verify/exact_method.h"

namespace rayproof::registry {

const MethodRegistry& all_methods() {
  static const MethodRegistry reg = [] {
    MethodRegistry r;
    register_fast_methods(r);
    verify::register_exact_method(r);
    register_robust_methods(r);
    verify::register_certified_method(r);
    register_tritri_methods(r);
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

bool is_user_kernel(std::string_view name, const std::vector<std::unique_ptr<Method>>& user) {
  return std::any_of(user.begin(), user.end(), [&](const auto& u) { return u->name == name; });
}

std::optional<std::vector<const Method*>> select_methods(std::string_view command, const std::vector<std::string>& names,
                                                        bool with_exact,
                                                        const std::vector<std::unique_ptr<Method>>& user) {
  const MethodRegistry& reg = all_methods();
  std::vector<const Method*> methods;
  if (names.empty()) {
    for (const auto& m : reg.all())
      if (with_exact || m.name != "exact") methods.push_back(&m);
  }
  for (const auto& name : names) {
    const Method* m = nullptr;
    for (const auto& u : user)
      if (u->name == name) m = u.get();
    if (!m) m = reg.find(name);
    if (!m) {
      std::vector<std::string> mine;
      for (const auto& u : user) mine.push_back(u->name);
      fmt::print(stderr, "rayproof {}: unknown method '{}' (known: {}{})\n", command, name, reg.names(),
                 mine.empty() ? std::string() : fmt::format("; your kernels: {}", fmt::join(mine, ", ")));
      return std::nullopt;
    }
    if (std::find(methods.begin(), methods.end(), m) == methods.end()) methods.push_back(m);
  }
  for (const auto& u : user)
    if (std::find(methods.begin(), methods.end(), u.get()) == methods.end()) methods.push_back(u.get());
  return methods;
}

}  // namespace rayproof::registry
