#pragma once
// Packets of eight rays (the traversal in rayproof/bvh_packet.h), shared by accel_packet.cpp
// (closest_packets) and accel_packet_any.cpp (any_packets): the leaf code of accel_query.h's
// traverse_with called per lane, the lanes' kernels, and the loop over a batch's packets.
// Internal to rayproof_scene.
#include <algorithm>
#include <type_traits>

#include "rayproof/bvh_packet.h"
#include "scene/accel.h"
#include "scene/accel_query.h"

namespace rayproof::scene {
namespace detail {

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

/// Runs `one(kernels, first ray, n)` for each packet of a batch: eight copies of the method's kernel.
template <class K, class One>
void packets_over(std::size_t b, std::size_t e, std::size_t nrays, const K& k, One&& one) {
  K ks[kPacketWidth] = {k, k, k, k, k, k, k, k};
  for (std::size_t p = b; p < e; ++p) {
    const std::size_t first = p * kPacketWidth;
    one(ks, first, int(std::min<std::size_t>(kPacketWidth, nrays - first)));
  }
}

}  // namespace detail

template <class Packet, class Rays>
void Accel::over_packets(std::size_t nrays, const SceneMethod& m, int threads, Packet&& packet, Rays&& rays) const {
  using namespace detail;
  const std::size_t packets = (nrays + kPacketWidth - 1) / kPacketWidth;
  parallel_rays(packets, threads, [&](std::size_t b, std::size_t e) {
    if (simd_ != BvhSimd::avx2) return rays(b * kPacketWidth, std::min(e * kPacketWidth, nrays));  // ray by ray
    auto on = [&](const auto& tree) {
      with_kernel(scene_, verts_, ntri_, m, [&](auto& k) {
        const auto L = leaves_of(tree, leaf_prims_, groups_);
        packets_over(b, e, nrays, k, [&](auto* ks, std::size_t first, int n) { packet(L, ks, first, n); });
        return 0;
      });
    };
    if (nodes_ == BvhNodes::compressed) on(bvh8q_);
    else on(bvh8_);
  });
}

}  // namespace rayproof::scene
