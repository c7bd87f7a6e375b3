// The closest-point tree: a binary BVH over the triangles with exact double boxes, split at the
// median of the centroids along the longest axis, leaves of up to four triangles.
#include <algorithm>
#include <numeric>

#include "scene/contains_exact.h"
#include "scene/distance_tree.h"

namespace rayproof::detail {

namespace {

constexpr std::uint32_t kLeaf = 4;

struct Builder {
  const std::vector<std::array<Vec3<double>, 3>>& tri;
  std::vector<Vec3<double>> centroid;
  std::vector<std::uint32_t> order;
  std::vector<DistanceNode>& nodes;

  void bounds(DistanceNode& n, std::uint32_t b, std::uint32_t e) const {
    for (int k = 0; k < 3; ++k) n.lo[k] = std::numeric_limits<double>::infinity(), n.hi[k] = -n.lo[k];
    for (std::uint32_t i = b; i < e; ++i)
      for (const Vec3<double>& v : tri[order[i]])
        for (int k = 0; k < 3; ++k) n.lo[k] = std::min(n.lo[k], v[k]), n.hi[k] = std::max(n.hi[k], v[k]);
  }
  void build(std::uint32_t node, std::uint32_t b, std::uint32_t e) {
    bounds(nodes[node], b, e);
    if (e - b <= kLeaf) {
      nodes[node].index = b, nodes[node].count = e - b;
      return;
    }
    double clo[3], chi[3];
    for (int k = 0; k < 3; ++k) clo[k] = std::numeric_limits<double>::infinity(), chi[k] = -clo[k];
    for (std::uint32_t i = b; i < e; ++i)
      for (int k = 0; k < 3; ++k) clo[k] = std::min(clo[k], centroid[order[i]][k]), chi[k] = std::max(chi[k], centroid[order[i]][k]);
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
    const std::uint32_t mid = b + (e - b) / 2;
    std::nth_element(order.begin() + b, order.begin() + mid, order.begin() + e,
                     [&](std::uint32_t x, std::uint32_t y) { return centroid[x][axis] < centroid[y][axis]; });
    const auto first = std::uint32_t(nodes.size());
    nodes.emplace_back();
    nodes.emplace_back();
    nodes[node].index = first, nodes[node].count = 0;
    build(first, b, mid);
    build(first + 1, mid, e);
  }
};

}  // namespace

DistanceTree build_distance_tree(const std::vector<Vec3<double>>& v, const std::vector<std::array<std::uint32_t, 3>>& tris) {
  DistanceTree t;
  const auto n = std::uint32_t(tris.size());
  if (n == 0) return t;
  std::vector<std::array<Vec3<double>, 3>> tri(n);
  std::vector<Vec3<double>> centroid(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    tri[i] = {v[tris[i][0]], v[tris[i][1]], v[tris[i][2]]};
    // The centroid only orders the split; a third of each coordinate avoids overflow.
    centroid[i] = tri[i][0] / 3.0 + tri[i][1] / 3.0 + tri[i][2] / 3.0;
  }
  Builder b{tri, std::move(centroid), std::vector<std::uint32_t>(n), t.nodes};
  std::iota(b.order.begin(), b.order.end(), 0u);
  t.nodes.reserve(2 * (n / kLeaf + 1));
  t.nodes.emplace_back();
  b.build(0, 0, n);
  t.tris.resize(n);
  t.ids = b.order;
  t.degenerate.resize(n);
  for (std::uint32_t s = 0; s < n; ++s) {
    t.tris[s] = tri[t.ids[s]];
    const auto& [a, bb, c] = t.tris[s];
    using scene::detail::orient2d_exact;
    t.degenerate[s] = orient2d_exact(a.x, a.y, bb.x, bb.y, c.x, c.y) == 0 && orient2d_exact(a.y, a.z, bb.y, bb.z, c.y, c.z) == 0 &&
                      orient2d_exact(a.z, a.x, bb.z, bb.x, c.z, c.x) == 0;
  }
  return t;
}

}  // namespace rayproof::detail
