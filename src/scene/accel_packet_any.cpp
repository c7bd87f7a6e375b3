// Accel::any_packets: packets of eight rays through the eight-wide trees (accel_packet.h), the
// any-hit leaf code per lane (apart from closest_packets, accel_packet.cpp: each is a large
// compile, and apart they build side by side).
#include "scene/accel_packet.h"

namespace rayproof::scene {
using namespace detail;
namespace {

template <class Tree, class K>
void any_packet(const Leaves<Tree>& L, K* ks, const Ray<double>* rays, int n, std::span<const QueryRange> ranges,
                std::size_t first, BvhTraversal mode, std::uint8_t* out) {
  PacketLanes<K> P(ks, rays, n, ranges, first);
  for (int i = 0; i < n; ++i) out[i] = 0;
  bvh8_packet_traverse_leaves<BvhQuery::any>(L.bvh, P.ray, P.tmin, P.tmax, P.live, mode,
                              [&](int lane, std::uint32_t f, std::uint32_t count) {
                                const QueryRange q = P.q[lane];
                                // any_with's emit, for this lane.
                                auto emit = [&](std::uint32_t, const Crossing* c, int nc) {
                                  for (int i = 0; i < nc; ++i)
                                    if (c[i].t >= q.tmin && c[i].t <= q.tmax) {
                                      out[lane] = 1;
                                      return true;
                                    }
                                  return false;
                                };
                                return leaf_for_ray(L, P.kernel(lane), f, count, emit);
                              });
}

}  // namespace

void Accel::any_packets(std::span<const Ray<double>> rays, std::span<const QueryRange> ranges, std::span<std::uint8_t> out,
                        const SceneMethod& m, int threads) const {
  over_packets(
      rays.size(), m, threads,
      [&](const auto& L, auto* ks, std::size_t first, int n) {
        any_packet(L, ks, &rays[first], n, ranges, first, m.traversal, &out[first]);
      },
      [&](std::size_t b, std::size_t e) { any_range(rays.data(), b, e, ranges, out.data(), m); });
}

}  // namespace rayproof::scene
