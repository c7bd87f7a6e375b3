// rtcBuildBVH building rayproof's binary tree (embree_build.h). The builder calls back to make
// nodes and leaves in its own thread-local memory; the finished tree is then copied into
// rayproof's layout (children of an inner node side by side after it, leaves' primitives in
// prim_ids). Every box comes from Embree's setNodeBounds, which are unions of the primitives'
// boxes given to it (ours, rounded outwards): float min and max, exact, so each node's box still
// holds its primitives and the conservative traversal's proof is unchanged.
#include "scene/compare/embree_build.h"

#include <algorithm>
#include <cstdint>
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

Bvh build(const std::vector<BvhBox>& boxes, unsigned max_leaf, unsigned block) {
  Bvh out;
  if (boxes.empty()) return out;
  std::vector<RTCBuildPrimitive> prims(boxes.size());
  BvhBox all;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const BvhBox& b = boxes[i];
    prims[i] = {b.lo[0], b.lo[1], b.lo[2], 0, b.hi[0], b.hi[1], b.hi[2], std::uint32_t(i)};
    all.extend(b);
  }
  RTCDevice device = new_embree_device();
  RTCBVH bvh = rtcNewBVH(device);
  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.buildQuality = RTC_BUILD_QUALITY_MEDIUM;
  args.maxBranchingFactor = 2;
  args.maxDepth = 1024;
  args.sahBlockSize = block;
  args.minLeafSize = 1;
  args.maxLeafSize = std::min(max_leaf, kMaxLeaf);
  args.bvh = bvh;
  args.primitives = prims.data();
  args.primitiveCount = prims.size();
  args.primitiveArrayCapacity = prims.size();
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
  if (out.prim_ids.size() != boxes.size())
    throw std::runtime_error("rtcBuildBVH: " + std::to_string(out.prim_ids.size()) + " primitives in the leaves of " +
                             std::to_string(boxes.size()));
  return out;
}

}  // namespace
#endif

std::function<Bvh(const std::vector<BvhBox>&, const std::vector<Vec3<float>>&)> embree_binary_builder(unsigned max_leaf,
                                                                                                      unsigned block,
                                                                                                      std::string* why) {
#ifdef RAYPROOF_HAVE_EMBREE
  (void)why;
  return [max_leaf, block](const std::vector<BvhBox>& boxes, const std::vector<Vec3<float>>&) {
    return build(boxes, max_leaf, block);
  };
#else
  (void)max_leaf, (void)block;
  if (why) *why = "rayproof was built without Embree";
  return {};
#endif
}

}  // namespace rayproof::scene::compare
