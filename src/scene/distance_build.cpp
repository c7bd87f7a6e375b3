// The closest-point tree: the SAH binary BVH of rayproof/bvh_build.h over the triangles (leaves of
// up to four), with exact double boxes.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "rayproof/bvh_build.h"
#include "exact/orient_exact.h"
#include "scene/distance_tree.h"

namespace rayproof::scene::detail {

namespace {
constexpr std::uint32_t kLeaf = 4;
}  // namespace

DistanceTree build_distance_tree(const std::vector<Vec3<double>>& v, const std::vector<std::array<std::uint32_t, 3>>& tris) {
  DistanceTree t;
  const auto n = std::uint32_t(tris.size());
  if (n == 0) return t;
  std::vector<std::array<Vec3<double>, 3>> tri(n);
  std::vector<BvhBox> boxes(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    tri[i] = {v[tris[i][0]], v[tris[i][1]], v[tris[i][2]]};
    for (const auto& p : tri[i]) boxes[i].extend(p);
  }
  // The topology of the SAH binary tree (float boxes, rounded outwards: only its shape is used);
  // the boxes are recomputed in double, exactly, bottom-up.
  BvhBuildOptions opt;
  opt.builder = BvhBuilder::sah;
  opt.max_leaf = kLeaf;
  opt.leaf_group = 1;
  Bvh bvh = build_bvh(boxes, {}, opt);
  const std::size_t nn = bvh.nodes.size();
  t.nodes.resize(nn);
  std::vector<std::array<double, 6>> box(nn);  // exact double bounds: lo xyz, hi xyz
  for (std::size_t i = 0; i < nn; ++i) t.nodes[i].index = bvh.nodes[i].index, t.nodes[i].count = bvh.nodes[i].count;
  std::vector<std::uint32_t> order = bvh.prim_ids;
  for (std::size_t i = nn; i-- > 0;) {  // children follow their parents
    const DistanceNode& nd = t.nodes[i];
    auto& b = box[i];
    for (int k = 0; k < 3; ++k) b[k] = std::numeric_limits<double>::infinity(), b[k + 3] = -b[k];
    if (nd.count) {
      for (std::uint32_t s = nd.index; s < nd.index + nd.count; ++s)
        for (const Vec3<double>& p : tri[order[s]])
          for (int k = 0; k < 3; ++k) b[k] = std::min(b[k], p[k]), b[k + 3] = std::max(b[k + 3], p[k]);
    } else {
      if (nd.index <= i) throw std::logic_error("distance tree: a child before its parent");
      for (std::uint32_t c : {nd.index, nd.index + 1})
        for (int k = 0; k < 3; ++k) b[k] = std::min(b[k], box[c][k]), b[k + 3] = std::max(b[k + 3], box[c][k + 3]);
    }
  }
  for (std::size_t i = 0; i < nn; ++i)
    for (int k = 0; k < 3; ++k) t.nodes[i].lo[k] = bvh_float_down(box[i][k]), t.nodes[i].hi[k] = bvh_float_up(box[i][k + 3]);
  // The wide tree of the first pass: the same leaves (slots) and float boxes (the exact double
  // boxes rounded outwards), eight or four wide.
  for (std::size_t i = 0; i < nn; ++i)
    for (int k = 0; k < 3; ++k) bvh.nodes[i].box.lo[k] = t.nodes[i].lo[k], bvh.nodes[i].box.hi[k] = t.nodes[i].hi[k];
  if (bvh_simd_path() == BvhSimd::avx2) t.wide8 = collapse_bvh8(std::move(bvh), boxes);
  else t.wide4 = collapse_bvh4(std::move(bvh), boxes);
  t.tris.resize(n);
  t.ids = std::move(order);
  t.slot_of.resize(n);
  for (std::uint32_t s = 0; s < n; ++s) t.slot_of[t.ids[s]] = s;
  t.degenerate.resize(n);
  for (std::uint32_t s = 0; s < n; ++s) {
    t.tris[s] = tri[t.ids[s]];
    const auto& [a, bb, c] = t.tris[s];
    using certified::orient2d_exact;
    t.degenerate[s] = orient2d_exact(a.x, a.y, bb.x, bb.y, c.x, c.y) == 0 && orient2d_exact(a.y, a.z, bb.y, bb.z, c.y, c.z) == 0 &&
                      orient2d_exact(a.z, a.x, bb.z, bb.x, c.z, c.x) == 0;
  }
  // A copy scaled by a power of two towards 1, when every used coordinate scales exactly.
  double big = 0;
  for (const auto& f : tris)
    for (auto i : f) big = std::max({big, std::abs(v[i].x), std::abs(v[i].y), std::abs(v[i].z)});
  const int e = big > 0 ? std::ilogb(big) : 0;
  if (std::abs(e) > 200) {
    std::vector<Vec3<double>> sv(v.size());
    bool exact = true;
    for (std::size_t i = 0; i < v.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const double c = v[i][k], d = std::ldexp(c, -e);
        if (std::ldexp(d, e) != c || (d != 0 && std::abs(d) < std::numeric_limits<double>::min())) exact = false;
        sv[i][k] = d;
      }
    if (exact) {
      t.scaled = std::make_shared<const DistanceTree>(build_distance_tree(sv, tris));
      t.scale_exp = e;
    }
  }
  return t;
}

}  // namespace rayproof::scene::detail
