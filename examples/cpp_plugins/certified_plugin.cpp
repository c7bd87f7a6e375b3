/// rayproof's `certified` method (exact class on every case, T within 1 ulp: floating-point filters
/// with an exact GMP fallback) as a plugin, with CGAL, GMP and MPFR linked in. Built as
/// build/plugins/plugin_certified.so.
///     rayproof verify --methods certified --plugin build/plugins/plugin_certified.so cases.txt
#include "method_plugin.h"
#include "verify/certified_method.h"

namespace {
const rayproof::Method& certified_method() {
  static const rayproof::MethodRegistry reg = [] {
    rayproof::MethodRegistry r;
    rayproof::verify::register_certified_method(r);
    return r;
  }();
  return *reg.find("certified");
}
}  // namespace

RAYPROOF_PLUGIN_EXPORT const rayproof_plugin* rayproof_plugin_entry(void) {
  return rayproof::examples::describe<certified_method>("plugin-certified");
}
