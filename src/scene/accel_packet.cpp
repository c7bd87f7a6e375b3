// Accel::closest_packets: packets of eight rays through the eight-wide trees (accel_packet.h),
// the closest-hit leaf code per lane.
#include "scene/accel_packet.h"

namespace rayproof::scene {
using namespace detail;
namespace {

template <class Tree, class K>
void closest_packet(const Leaves<Tree>& L, K* ks, const Ray<double>* rays, int n, std::span<const QueryRange> ranges,
                    std::size_t first, BvhTraversal mode, PrimHit* out) {
  PacketLanes<K> P(ks, rays, n, ranges, first);
  for (int i = 0; i < n; ++i) out[i] = P.live >> i & 1 ? PrimHit{} : PrimHit{Contact::invalid};
  bvh8_packet_traverse_leaves<BvhQuery::closest>(L.bvh, P.ray, P.tmin, P.tmax, P.live, mode,
                              [&](int lane, std::uint32_t f, std::uint32_t count) {
                                PrimHit& best = out[lane];
                                double& tmax = P.tmax[lane];
                                const double tmin = P.q[lane].tmin;
                                // closest_with's emit, for this lane.
                                auto emit = [&](std::uint32_t id, const Crossing* c, int nc) {
                                  for (int i = 0; i < nc; ++i)
                                    if (c[i].t >= tmin && (c[i].t < tmax || (c[i].t == tmax && id < best.prim))) {
                                      tmax = c[i].t;
                                      best = {c[i].contact, c[i].t, id, c[i].b1, c[i].b2};
                                    }
                                  return false;
                                };
                                return leaf_for_ray(L, P.kernel(lane), f, count, emit);
                              });
}

}  // namespace

void Accel::closest_packets(std::span<const Ray<double>> rays, std::span<const QueryRange> ranges, std::span<PrimHit> out,
                            const SceneMethod& m, int threads) const {
  over_packets(
      rays.size(), m, threads,
      [&](const auto& L, auto* ks, std::size_t first, int n) {
        closest_packet(L, ks, &rays[first], n, ranges, first, m.traversal, &out[first]);
      },
      [&](std::size_t b, std::size_t e) { closest_range(rays.data(), b, e, ranges, store_hit, out.data(), m); });
}

}  // namespace rayproof::scene
