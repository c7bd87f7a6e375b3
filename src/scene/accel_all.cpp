// Accel::all, every crossing of a ray sorted by t then primitive: the all-hits traversal expanded over
// the four trees x nine kernels (apart from closest and any hit: accel_closest.cpp).
#include <algorithm>

#include "scene/accel.h"
#include "scene/accel_query.h"

namespace rayproof::scene {
using namespace detail;

std::vector<PrimHit> Accel::all(const Ray<double>& r, const SceneMethod& m, QueryRange q) const {
  std::vector<PrimHit> out;
  if (!r.valid()) return out;
  with_tree([&](const auto& tree) {
    return with_kernel(scene_, verts_, ntri_, m, [&](auto& k) {
      k.prepare(r);
      traverse_with<BvhQuery::all>(leaves_of(tree, leaf_prims_, groups_), k, q, q.tmax, m.traversal,
                    [&](std::uint32_t id, const Crossing* c, int n) {
                      for (int i = 0; i < n; ++i)
                        if (c[i].t >= q.tmin && c[i].t <= q.tmax) out.push_back({c[i].contact, c[i].t, id, c[i].b1, c[i].b2});
                      return false;
                    });
      return 0;
    });
  });
  std::sort(out.begin(), out.end(), [](const PrimHit& a, const PrimHit& b) { return a.t < b.t || (a.t == b.t && a.prim < b.prim); });
  return out;
}

}  // namespace rayproof::scene
