// ExactMesh::closest_points: the batch (rayproof/scene/distance.h, docs/distance.md).
//
// The points are visited in Morton order of their coordinates (their answers written back in
// input order), so that consecutive queries read the same part of the tree, and each query's
// first bound starts from the previous answer's triangle (its distance to p is at most the previous
// distance plus the step between the points). The answers do not depend on the order.
//
// The side, when asked for, is contains(p)'s answer, asked point by point. (Reusing the previous
// point's exact winding number when the two points' empty balls cover the segment between them,
// and else the net crossings of that segment, were tried: neither was measurably faster than
// contains(p) in bench distance --ablation, and the crossings were slower near the surface.)

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "rayproof/scene/distance.h"
#include "scene/batch_threads.h"
#include "scene/exact_mesh_state.h"
#include "scene/distance_tree.h"

namespace rayproof {

namespace scene::detail {
namespace {

constexpr double kInfD = std::numeric_limits<double>::infinity();

/// 21 bits of x spread to every third bit.
std::uint64_t spread3(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

/// The visiting order: the indices of the points sorted by the Morton code of their position in
/// the points' bounding box (invalid points first, code 0).
std::vector<std::uint32_t> morton_order(const std::byte* base, std::size_t n, std::size_t stride) {
  auto at = [&](std::size_t i) {
    Vec3<double> p;
    std::memcpy(&p, base + i * stride, sizeof p);
    return p;
  };
  Vec3<double> lo{kInfD, kInfD, kInfD}, hi = -lo;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3<double> p = at(i);
    if (!all_finite(p)) continue;
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  }
  std::vector<std::pair<std::uint64_t, std::uint32_t>> key(n);
  double scale[3];
  for (int k = 0; k < 3; ++k) {
    const double ext = hi[k] - lo[k];  // may overflow to inf: then the scale is 0 (one cell)
    scale[k] = ext > 0 && ext < kInfD ? 2097151.0 / ext : 0.0;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3<double> p = at(i);
    std::uint64_t c = 0;
    if (all_finite(p))
      for (int k = 0; k < 3; ++k) c |= spread3(std::uint64_t(std::clamp((p[k] - lo[k]) * scale[k], 0.0, 2097151.0))) << k;
    key[i] = {c, std::uint32_t(i)};
  }
  std::sort(key.begin(), key.end());
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = distance_ablation() & kAblateOrder ? std::uint32_t(i) : key[i].second;
  return order;
}

}  // namespace
}  // namespace scene::detail

void ExactMesh::closest_points(std::span<const Vec3<double>> points, std::span<ClosestPoint> out, bool with_side,
                                int threads) const {
  if (points.size() != out.size())
    throw MeshInputError("ExactMesh::closest_points: " + std::to_string(out.size()) + " results for " +
                         std::to_string(points.size()) + " points");
  closest_points(reinterpret_cast<const double*>(points.data()), points.size(), sizeof(Vec3<double>), out.data(),
                 with_side, threads);
}

void ExactMesh::closest_points(const double* xyz, std::size_t n, std::size_t stride, ClosestPoint* out, bool with_side,
                                int threads) const {
  if (n == 0) return;
  if (!xyz || !out) throw MeshInputError("ExactMesh::closest_points: null pointer with a count of " + std::to_string(n));
  if (stride < 3 * sizeof(double) || stride % sizeof(double))
    throw MeshInputError("ExactMesh::closest_points: stride of " + std::to_string(stride) +
                         " bytes (need a multiple of 8, at least 24)");
  if (n >= (std::size_t(1) << 32)) throw MeshInputError("ExactMesh::closest_points: more than 2^32 - 1 points");
  const scene::detail::DistanceTree& t = scene::detail::distance_tree(*s_);
  const auto* base = reinterpret_cast<const std::byte*>(xyz);
  const std::vector<std::uint32_t> order = scene::detail::morton_order(base, n, stride);
  scene::detail::for_each_batch_range(n, threads, 1024, 256, [&](std::size_t b, std::size_t e) {
    std::uint32_t hint = 0xffffffffu;
    for (std::size_t j = b; j < e; ++j) {
      const std::uint32_t i = order[j];
      Vec3<double> p;
      std::memcpy(&p, base + i * stride, sizeof p);
      ClosestPoint c = scene::detail::distance_query(t, p, hint);
      if (c.triangle < t.slot_of.size()) hint = t.slot_of[c.triangle];
      if (with_side && c.distance == c.distance) c.side = c.distance == 0 ? Side::surface : contains(p);
      out[i] = c;
    }
  });
}

}  // namespace rayproof
