#pragma once
/// Embree's own builder (rtcBuildBVH, embree3/rtcore_builder.h: binned SAH with callbacks that make
/// the caller's nodes) building rayproof's binary tree, so that rayproof's collapse, leaves and
/// traversal run on Embree's choice of splits (`rayproof bench --embree-tree`). Empty without Embree.
#include <functional>
#include <string>
#include <vector>

#include "rayproof/bvh.h"

namespace rayproof::scene::compare {

/// BvhBuildOptions::binary for Accel: Embree's binned SAH (quality medium), binary nodes, leaves of
/// up to `max_leaf` primitives, SAH blocks of `block` primitives (our leaf groups). Empty (no
/// function) when rayproof was built without Embree; `why` then says so.
[[nodiscard]] std::function<Bvh(const std::vector<BvhBox>&, const std::vector<Vec3<float>>&)> embree_binary_builder(
    unsigned max_leaf, unsigned block, std::string* why = nullptr);

}  // namespace rayproof::scene::compare
