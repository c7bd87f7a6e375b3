#pragma once
/// Embree's own builder (rtcBuildBVH, embree3/rtcore_builder.h: binned SAH with callbacks that make
/// the caller's nodes) building rayproof's binary tree, so that rayproof's collapse, leaves and
/// traversal run on Embree's choice of splits (`rayproof bench --embree-tree`). Empty without Embree.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "rayproof/bvh.h"
#include "rayproof/triangle_common.h"

namespace rayproof::scene::compare {

/// Embree's build quality: medium (binned SAH, its default) or high (binned SAH with its own
/// refinements); high_splits adds spatial splits (Embree's splitPrimitive callback: a triangle may
/// then sit in several leaves, each leaf's box holding the part of it on its side).
enum class EmbreeTreeQuality { medium, high, high_splits };

[[nodiscard]] const char* to_string(EmbreeTreeQuality q);

/// The triangle of a primitive number, for high_splits' clipping.
using EmbreeTriangleOf = std::function<Triangle<double>(std::uint32_t)>;

/// BvhBuildOptions::binary for Accel: Embree's builder at `quality`, binary nodes, leaves of up to
/// `max_leaf` primitives, SAH blocks of `block` primitives (our leaf groups). high_splits needs
/// `triangle_of` (else it throws std::invalid_argument). Empty (no function) when rayproof was built
/// without Embree; `why` then says so.
[[nodiscard]] std::function<Bvh(const std::vector<BvhBox>&, const std::vector<Vec3<float>>&)> embree_binary_builder(
    unsigned max_leaf, unsigned block, std::string* why = nullptr, EmbreeTreeQuality quality = EmbreeTreeQuality::medium,
    EmbreeTriangleOf triangle_of = {});

}  // namespace rayproof::scene::compare
