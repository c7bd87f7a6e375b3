/// rayproof's `float` method (the worked problems' formulas in float) as a plugin: the same answers
/// in process, through --plugin and through plugin-host. Built as build/plugins/plugin_float.so.
///     rayproof verify --methods float --plugin build/plugins/plugin_float.so cases.txt
#include "method_plugin.h"

namespace {
const rayproof::Method& float_method() {
  static const rayproof::MethodRegistry reg = [] {
    rayproof::MethodRegistry r;
    rayproof::register_fast_methods(r);
    return r;
  }();
  return *reg.find("float");
}
}  // namespace

RAYPROOF_PLUGIN_EXPORT const rayproof_plugin* rayproof_plugin_entry(void) {
  return rayproof::examples::describe<float_method>("plugin-float");
}
