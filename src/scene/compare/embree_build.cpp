// rtcBuildBVH building rayproof's binary tree (embree_build.h). The builder calls back to make
// nodes and leaves in its own thread-local memory; the finished tree is then copied into
// rayproof's layout (children of an inner node side by side after it, leaves' primitives in
// prim_ids). Every box comes from Embree's setNodeBounds, which are unions of the primitives'
// boxes given to it (ours, rounded outwards): float min and max, exact, so each node's box still
// holds its primitives and the conservative traversal's proof is unchanged. With spatial splits
// (quality high_splits) a primitive's box is cut by Embree's planes: split_primitive clips the
// triangle in double and rounds the clipped part's box outwards (with a margin for the clip's own
// rounding), so each piece's box still holds that piece of the triangle.
#include "scene/compare/embree_build.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#ifdef RAYPROOF_HAVE_EMBREE
#include <embree3/rtcore.h>
#include <embree3/rtcore_builder.h>

#include "scene/compare/embree_mesh.h"
#endif

namespace rayproof::scene::compare {

#ifdef RAYPROOF_HAVE_EMBREE
namespace {

constexpr unsigned kMaxLeaf = 16;

struct BuiltNode {
  bool leaf = false;
  unsigned count = 0;                 ///< leaf: its primitives
  std::uint32_t prims[kMaxLeaf] = {};  ///< leaf: their ids
  BuiltNode* child[2] = {nullptr, nullptr};
  BvhBox box[2];
};

void* create_node(RTCThreadLocalAllocator alloc, unsigned int count, void*) {
  if (count != 2) return nullptr;  // asked for binary nodes only
  return new (rtcThreadLocalAlloc(alloc, sizeof(BuiltNode), 16)) BuiltNode;
}
void set_children(void* node, void** children, unsigned int count, void*) {
  auto* n = static_cast<BuiltNode*>(node);
  for (unsigned i = 0; i < count && i < 2; ++i) n->child[i] = static_cast<BuiltNode*>(children[i]);
}
void set_bounds(void* node, const RTCBounds** bounds, unsigned int count, void*) {
  auto* n = static_cast<BuiltNode*>(node);
  for (unsigned i = 0; i < count && i < 2; ++i) {
    const RTCBounds& b = *bounds[i];
    n->box[i].lo[0] = b.lower_x, n->box[i].lo[1] = b.lower_y, n->box[i].lo[2] = b.lower_z;
    n->box[i].hi[0] = b.upper_x, n->box[i].hi[1] = b.upper_y, n->box[i].hi[2] = b.upper_z;
  }
}
void* create_leaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count, void*) {
  auto* n = new (rtcThreadLocalAlloc(alloc, sizeof(BuiltNode), 16)) BuiltNode;
  n->leaf = true;
  n->count = unsigned(std::min<size_t>(count, kMaxLeaf));
  for (unsigned i = 0; i < n->count; ++i) n->prims[i] = prims[i].primID;
  return n;
}

struct SplitContext {
  const EmbreeTriangleOf* triangle_of = nullptr;
};

/// A float at or below x (at or above when `up`), for outward rounding.
float outward(double x, bool up) {
  const auto f = static_cast<float>(x);
  if (up) return double(f) >= x ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
  return double(f) <= x ? f : std::nextafter(f, -std::numeric_limits<float>::infinity());
}

/// Embree's splitPrimitive: the piece of the primitive's triangle on each side of the plane
/// x[dim] = position, as boxes rounded outwards, each within the primitive's current box (itself a
/// piece's box). A side without a piece gets an empty box (lower above upper) reduced to a point on
/// the plane, inside the current box, so Embree's bookkeeping stays finite.
void split_primitive(const RTCBuildPrimitive* prim, unsigned dim, float position, RTCBounds* left, RTCBounds* right,
                     void* user) {
  const auto& ctx = *static_cast<const SplitContext*>(user);
  const Triangle<double> t = (*ctx.triangle_of)(prim->primID);
  const Vec3<double> v[3] = {t.p0, t.p1, t.p2};
  const double pos = position;
  // The clipped polygon's points on each side: vertices on it, and each edge's crossing of the
  // plane. A crossing computed in double is off by at most a few ulps of the largest coordinate:
  // `margin` covers it (8 ulps of double of the triangle's largest magnitude).
  double lo[2][3], hi[2][3];
  bool any[2] = {false, false};
  for (int s = 0; s < 2; ++s)
    for (int k = 0; k < 3; ++k) lo[s][k] = std::numeric_limits<double>::infinity(), hi[s][k] = -lo[s][k];
  double big = 0;
  for (const auto& p : v)
    for (int k = 0; k < 3; ++k) big = std::max(big, std::abs(p[k]));
  const double margin = 8 * std::numeric_limits<double>::epsilon() * big;
  auto add = [&](int side, const Vec3<double>& p, double pad) {
    any[side] = true;
    for (int k = 0; k < 3; ++k) lo[side][k] = std::min(lo[side][k], p[k] - pad), hi[side][k] = std::max(hi[side][k], p[k] + pad);
  };
  for (int i = 0; i < 3; ++i) {
    const Vec3<double>& a = v[i];
    const Vec3<double>& b = v[(i + 1) % 3];
    if (a[dim] <= pos) add(0, a, 0);
    if (a[dim] >= pos) add(1, a, 0);
    if ((a[dim] < pos && b[dim] > pos) || (a[dim] > pos && b[dim] < pos)) {
      const double s = (pos - a[dim]) / (b[dim] - a[dim]);
      const Vec3<double> c = a + (b - a) * s;
      add(0, c, margin), add(1, c, margin);
    }
  }
  const float cur_lo[3] = {prim->lower_x, prim->lower_y, prim->lower_z};
  const float cur_hi[3] = {prim->upper_x, prim->upper_y, prim->upper_z};
  for (int s = 0; s < 2; ++s) {
    float l[3], h[3];
    for (int k = 0; k < 3; ++k) {
      l[k] = std::max(cur_lo[k], outward(lo[s][k], false));
      h[k] = std::min(cur_hi[k], outward(hi[s][k], true));
    }
    if (s == 0) h[dim] = std::min(h[dim], position);
    else l[dim] = std::max(l[dim], position);
    bool empty = !any[s];
    for (int k = 0; k < 3; ++k) empty = empty || l[k] > h[k];
    if (empty)
      for (int k = 0; k < 3; ++k) l[k] = h[k] = k == int(dim) ? position : cur_lo[k];
    RTCBounds& out = s == 0 ? *left : *right;
    out.lower_x = l[0], out.lower_y = l[1], out.lower_z = l[2];
    out.upper_x = h[0], out.upper_y = h[1], out.upper_z = h[2];
  }
}

Bvh build(const std::vector<BvhBox>& boxes, unsigned max_leaf, unsigned block, EmbreeTreeQuality quality,
          const EmbreeTriangleOf& triangle_of) {
  Bvh out;
  if (boxes.empty()) return out;
  const bool splits = quality == EmbreeTreeQuality::high_splits;
  // Spatial splits add primitives; Embree uses the array's spare capacity for them.
  std::vector<RTCBuildPrimitive> prims(splits ? 2 * boxes.size() : boxes.size());
  BvhBox all;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const BvhBox& b = boxes[i];
    prims[i] = {b.lo[0], b.lo[1], b.lo[2], 0, b.hi[0], b.hi[1], b.hi[2], std::uint32_t(i)};
    all.extend(b);
  }
  RTCDevice device = new_embree_device();
  RTCBVH bvh = rtcNewBVH(device);
  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.buildQuality = quality == EmbreeTreeQuality::medium ? RTC_BUILD_QUALITY_MEDIUM : RTC_BUILD_QUALITY_HIGH;
  args.maxBranchingFactor = 2;
  args.maxDepth = 1024;
  args.sahBlockSize = block;
  args.minLeafSize = 1;
  args.maxLeafSize = std::min(max_leaf, kMaxLeaf);
  args.bvh = bvh;
  args.primitives = prims.data();
  args.primitiveCount = boxes.size();
  args.primitiveArrayCapacity = prims.size();
  SplitContext ctx{&triangle_of};
  if (splits) args.splitPrimitive = split_primitive, args.userPtr = &ctx;
  args.createNode = create_node;
  args.setNodeChildren = set_children;
  args.setNodeBounds = set_bounds;
  args.createLeaf = create_leaf;
  const auto* root = static_cast<const BuiltNode*>(rtcBuildBVH(&args));
  if (!root) {
    rtcReleaseBVH(bvh), rtcReleaseDevice(device);
    throw std::runtime_error("rtcBuildBVH returned no tree");
  }
  // Copy depth first: each inner node's two children get adjacent slots at the end.
  struct Todo {
    const BuiltNode* n;
    std::uint32_t at;
    BvhBox box;
    int depth;
  };
  out.nodes.resize(1);
  std::vector<Todo> todo{{root, 0, all, 1}};
  while (!todo.empty()) {
    const Todo t = todo.back();
    todo.pop_back();
    out.max_depth = std::max(out.max_depth, t.depth);
    out.nodes[t.at].box = t.box;
    if (t.n->leaf) {
      out.nodes[t.at].index = std::uint32_t(out.prim_ids.size());
      out.nodes[t.at].count = t.n->count;
      out.prim_ids.insert(out.prim_ids.end(), t.n->prims, t.n->prims + t.n->count);
      continue;
    }
    const auto first = std::uint32_t(out.nodes.size());
    out.nodes[t.at].index = first, out.nodes[t.at].count = 0;
    out.nodes.resize(out.nodes.size() + 2);
    for (int i = 1; i >= 0; --i) todo.push_back({t.n->child[i], first + std::uint32_t(i), t.n->box[i], t.depth + 1});
  }
  rtcReleaseBVH(bvh);
  rtcReleaseDevice(device);
  if (splits ? out.prim_ids.size() < boxes.size() : out.prim_ids.size() != boxes.size())
    throw std::runtime_error("rtcBuildBVH: " + std::to_string(out.prim_ids.size()) + " primitives in the leaves of " +
                             std::to_string(boxes.size()));
  return out;
}

}  // namespace
#endif

const char* to_string(EmbreeTreeQuality q) {
  switch (q) {
    case EmbreeTreeQuality::medium: return "medium";
    case EmbreeTreeQuality::high: return "high";
    case EmbreeTreeQuality::high_splits: return "high+splits";
  }
  return "?";
}

std::function<Bvh(const std::vector<BvhBox>&, const std::vector<Vec3<float>>&)> embree_binary_builder(
    unsigned max_leaf, unsigned block, std::string* why, EmbreeTreeQuality quality, EmbreeTriangleOf triangle_of) {
  if (quality == EmbreeTreeQuality::high_splits && !triangle_of)
    throw std::invalid_argument("embree_binary_builder: spatial splits need the triangles");
#ifdef RAYPROOF_HAVE_EMBREE
  (void)why;
  return [max_leaf, block, quality, triangle_of = std::move(triangle_of)](const std::vector<BvhBox>& boxes,
                                                                           const std::vector<Vec3<float>>&) {
    return build(boxes, max_leaf, block, quality, triangle_of);
  };
#else
  (void)max_leaf, (void)block, (void)quality, (void)triangle_of;
  if (why) *why = "rayproof was built without Embree";
  return {};
#endif
}

}  // namespace rayproof::scene::compare
