/// rayproof's `robust` method (watertight triangles, stable quadrics, conservative slabs; float
/// inputs) as a plugin. Built as build/plugins/plugin_robust.so.
///     rayproof verify --methods robust --plugin build/plugins/plugin_robust.so cases.txt
#include "method_plugin.h"

namespace {
const rayproof::Method& robust_method() {
  static const rayproof::MethodRegistry reg = [] {
    rayproof::MethodRegistry r;
    rayproof::register_robust_methods(r);
    return r;
  }();
  return *reg.find("robust");
}
}  // namespace

RAYPROOF_PLUGIN_EXPORT const rayproof_plugin* rayproof_plugin_entry(void) {
  return rayproof::examples::describe<robust_method>("plugin-robust");
}
