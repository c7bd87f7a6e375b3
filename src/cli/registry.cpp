#include "cli/registry.h"

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

}  // namespace rayproof::cli
