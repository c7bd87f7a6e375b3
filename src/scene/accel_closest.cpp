// Accel's closest hit for single rays and batches (closest(), closest_batch(), the packets' SSE
// path): closest_with expanded over the four trees x nine kernels. Any hit and all hits have their
// own files (accel_any.cpp, accel_all.cpp): each expansion is a large compile, and apart they build
// side by side.
#include "scene/accel.h"
#include "scene/accel_query.h"

namespace rayproof::scene {
using namespace detail;

void Accel::closest_range(const Ray<double>* rays, std::size_t b, std::size_t e, std::span<const QueryRange> ranges,
                          HitSink sink, void* context, const SceneMethod& m) const {
  with_tree([&](const auto& tree) {
    return with_kernel(scene_, verts_, ntri_, m, [&](auto& k) {
      for (std::size_t i = b; i < e; ++i)
        sink(context, i, closest_with(leaves_of(tree, leaf_prims_, groups_), k, rays[i], m.traversal, range_of(ranges, i)));
      return 0;
    });
  });
}

}  // namespace rayproof::scene
