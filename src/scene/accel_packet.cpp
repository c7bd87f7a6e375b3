// Packets of eight rays (the traversal in rayproof/bvh_packet.h): Accel::closest_packets
// and any_packets, the leaf code of accel_query.h's traverse_with called per lane.
#include <algorithm>
#include <type_traits>

#include "rayproof/bvh_packet.h"
#include "scene/accel.h"
#include "scene/accel_query.h"

namespace rayproof::scene {
using namespace accel_detail;
namespace {

/// One leaf for one ray: the group kernels where traverse_with uses them, else slot by slot
/// (the same choice as traverse_with).
template <class K, class L_, class Emit>
bool leaf_for_ray(const L_& L, const K& k, std::uint32_t first, std::uint32_t count, Emit& emit) {
  if constexpr (kGroupKernel<K>) {
    if (L.groups) {
      if constexpr (std::is_same_v<K, detail::CompiledKernel<double, TriAlgo::certified>>) {
        return certified_leaf(k, L, first, count, emit);
      } else {
        return group_leaf(k, L, first, count, emit);
      }
    }
  }
  for (std::uint32_t j = first; j < first + count; ++j) {
    Crossing c[2];
    const int n = k.crossings(L.prims[j], c);
    if (n && emit(L.prims[j].id, c, n)) return true;
  }
  return false;
}

template <class K>
struct IsCompiledKernel : std::false_type {};
template <class T, TriAlgo A>
struct IsCompiledKernel<detail::CompiledKernel<T, A>> : std::true_type {};

/// The packet's lanes: the traversal rays and ranges, and the kernels, each prepared for its ray
/// when that ray first reaches a leaf (most primary rays of a scene miss: they never pay for it).
/// A compiled kernel's traversal ray is its ray rounded to its type and back, computed here without
/// preparing it (CompiledKernel::traversal_ray); other kernels are prepared at once. Invalid rays
/// are answered at once (`invalid`, no hit) and left out of `live`.
template <class K>
struct PacketLanes {
  K* ks;
  const Ray<double>* rays;
  Ray<double> ray[kPacketWidth];
  double tmin[kPacketWidth], tmax[kPacketWidth];
  QueryRange q[kPacketWidth];
  unsigned live = 0, prepared = 0;
  PacketLanes(K* k, const Ray<double>* r, int n, std::span<const QueryRange> ranges, std::size_t first) : ks(k), rays(r) {
    for (int i = 0; i < kPacketWidth; ++i) {
      q[i] = i < n ? range_of(ranges, first + std::size_t(i)) : QueryRange{};
      tmin[i] = q[i].tmin, tmax[i] = q[i].tmax;
      if (i >= n || !rays[i].valid()) continue;
      if constexpr (IsCompiledKernel<K>::value) {
        using T = decltype(ks[i].ray.o.x);
        ray[i] = {rays[i].o.template cast<T>().template cast<double>(), rays[i].d.template cast<T>().template cast<double>()};
      } else {
        ks[i].prepare(rays[i]);
        ray[i] = ks[i].traversal_ray();
        prepared |= 1u << i;
      }
      live |= 1u << i;
    }
  }
  /// Lane i's kernel, prepared for its ray.
  const K& kernel(int i) {
    if (!(prepared >> i & 1)) ks[i].prepare(rays[i]), prepared |= 1u << i;
    return ks[i];
  }
};

template <class Tree, class K>
void closest_packet(const Leaves<Tree>& L, K* ks, const Ray<double>* rays, int n, std::span<const QueryRange> ranges,
                    std::size_t first, BvhTraversal mode, PrimHit* out) {
  PacketLanes<K> P(ks, rays, n, ranges, first);
  for (int i = 0; i < n; ++i) out[i] = P.live >> i & 1 ? PrimHit{} : PrimHit{Contact::invalid};
  bvh8_packet_traverse_leaves(L.bvh, P.ray, P.tmin, P.tmax, P.live, mode, BvhQuery::closest,
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

template <class Tree, class K>
void any_packet(const Leaves<Tree>& L, K* ks, const Ray<double>* rays, int n, std::span<const QueryRange> ranges,
                std::size_t first, BvhTraversal mode, std::uint8_t* out) {
  PacketLanes<K> P(ks, rays, n, ranges, first);
  for (int i = 0; i < n; ++i) out[i] = 0;
  bvh8_packet_traverse_leaves(L.bvh, P.ray, P.tmin, P.tmax, P.live, mode, BvhQuery::any,
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

/// The trees the packet traversal runs on (the AVX2 path's); the SSE path's answer ray by ray.
template <class Tree>
constexpr bool is_eight_wide = std::is_same_v<Tree, Bvh8> || std::is_same_v<Tree, Bvh8Q>;

/// Runs `one(kernels, first ray, n)` for each packet of a batch: eight copies of the method's kernel.
template <class K, class One>
void packets_over(std::size_t b, std::size_t e, std::size_t nrays, const K& k, One&& one) {
  K ks[kPacketWidth] = {k, k, k, k, k, k, k, k};
  for (std::size_t p = b; p < e; ++p) {
    const std::size_t first = p * kPacketWidth;
    one(ks, first, int(std::min<std::size_t>(kPacketWidth, nrays - first)));
  }
}

}  // namespace

template <class Packet, class Single>
void Accel::over_packets(std::size_t nrays, const SceneMethod& m, int threads, Packet&& packet, Single&& single) const {
  const std::size_t packets = (nrays + kPacketWidth - 1) / kPacketWidth;
  parallel_rays(packets, threads, [&](std::size_t b, std::size_t e) {
    with_tree([&](const auto& tree) {
      return with_kernel(scene_, verts_, ntri_, m, [&](auto& k) {
        const auto L = leaves_of(tree, leaf_prims_, groups_);
        if constexpr (is_eight_wide<std::decay_t<decltype(tree)>>) {
          packets_over(b, e, nrays, k, [&](auto* ks, std::size_t first, int n) { packet(L, ks, first, n); });
        } else {  // the SSE path: ray by ray
          for (std::size_t i = b * kPacketWidth; i < std::min(e * kPacketWidth, nrays); ++i) single(L, k, i);
        }
        return 0;
      });
    });
  });
}

void Accel::closest_packets(std::span<const Ray<double>> rays, std::span<const QueryRange> ranges, std::span<PrimHit> out,
                            const SceneMethod& m, int threads) const {
  over_packets(
      rays.size(), m, threads,
      [&](const auto& L, auto* ks, std::size_t first, int n) {
        closest_packet(L, ks, &rays[first], n, ranges, first, m.traversal, &out[first]);
      },
      [&](const auto& L, auto& k, std::size_t i) { out[i] = closest_with(L, k, rays[i], m.traversal, range_of(ranges, i)); });
}

void Accel::any_packets(std::span<const Ray<double>> rays, std::span<const QueryRange> ranges, std::span<std::uint8_t> out,
                        const SceneMethod& m, int threads) const {
  over_packets(
      rays.size(), m, threads,
      [&](const auto& L, auto* ks, std::size_t first, int n) {
        any_packet(L, ks, &rays[first], n, ranges, first, m.traversal, &out[first]);
      },
      [&](const auto& L, auto& k, std::size_t i) { out[i] = any_with(L, k, rays[i], m.traversal, range_of(ranges, i)); });
}

}  // namespace rayproof::scene
