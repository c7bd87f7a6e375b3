// ExactMesh's generalized winding numbers (winding_tree.cpp): the value with its bound, one point
// or a batch.

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "scene/batch_threads.h"
#include "scene/exact_mesh_state.h"

namespace rayproof {

WindingValue ExactMesh::winding_value(const Vec3<double>& p, double tolerance) const {
  WindingValue v;
  if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) return v;
  if (!s_->tree) {  // closed and oriented: the exact integer
    const std::int32_t k = winding(p);
    if (k == kOnSurface) {
      v.surface = true, v.bound = 0;
    } else {
      v.w = k, v.bound = 0;
    }
    return v;
  }
  return s_->tree->value(p, tolerance);
}

void ExactMesh::winding_values(const double* xyz, std::size_t n, std::size_t stride, double* w, double* bound,
                                double tolerance, int threads) const {
  if (n == 0) return;
  if (!xyz || !w || !bound) throw MeshInputError("ExactMesh::winding_values: null pointer with a count of " + std::to_string(n));
  if (stride < 3 * sizeof(double) || stride % sizeof(double))
    throw MeshInputError("ExactMesh::winding_values: stride of " + std::to_string(stride) +
                         " bytes (need a multiple of 8, at least 24)");
  const auto* base = reinterpret_cast<const std::byte*>(xyz);
  scene::detail::for_each_batch_range(n, threads, 256, 64, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      Vec3<double> p;
      std::memcpy(&p, base + i * stride, sizeof p);
      const WindingValue v = winding_value(p, tolerance);
      w[i] = v.w;
      bound[i] = v.bound;
    }
  });
}

}  // namespace rayproof
