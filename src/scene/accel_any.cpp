// Accel's any hit for single rays and batches (any(), any_batch(), the packets' SSE path): any_with
// expanded over the four trees x nine kernels (apart from closest and all hits: accel_closest.cpp).
#include "scene/accel.h"
#include "scene/accel_query.h"

namespace rayproof::scene {
using namespace detail;

void Accel::any_range(const Ray<double>* rays, std::size_t b, std::size_t e, std::span<const QueryRange> ranges,
                      std::uint8_t* out, const SceneMethod& m) const {
  with_tree([&](const auto& tree) {
    return with_kernel(scene_, verts_, ntri_, m, [&](auto& k) {
      for (std::size_t i = b; i < e; ++i)
        out[i] = any_with(leaves_of(tree, leaf_prims_, groups_), k, rays[i], m.traversal, range_of(ranges, i));
      return 0;
    });
  });
}

}  // namespace rayproof::scene
