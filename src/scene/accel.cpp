// Scene queries: BVH construction, the method names, single rays and TBB batches (the query
// machinery in accel_query.h, expanded once per query in accel_closest.cpp, accel_any.cpp and
// accel_all.cpp; packets of eight in accel_packet.cpp).
#include "scene/accel.h"

#include <algorithm>
#include <chrono>

#include "scene/accel_query.h"

namespace rayproof::scene {
using namespace detail;
namespace {

const Scene& empty_scene() {
  static const Scene s;
  return s;
}

}  // namespace

SceneMethod find_scene_method(const std::string& name, const MethodRegistry& reg) {
  const Method* m = reg.find(name);
  if (!m) throw SceneError("unknown method '" + name + "' (known: " + reg.names() + ")");
  const FastKernel k = m->scene.kernel;
  const BvhTraversal traversal = m->scene.conservative_boxes ? BvhTraversal::conservative : BvhTraversal::standard;
  // robust and certified reach the method for other kinds (and certified for its fallback).
  const bool reaches_method = k == FastKernel::none || k == FastKernel::robust || k == FastKernel::certified;
  return {name, k, reaches_method ? m : nullptr, traversal};
}

std::vector<std::string> compiled_scene_method_names(const MethodRegistry& reg) {
  std::vector<std::string> out;
  for (const Method& m : reg.all())
    if (m.scene.kernel != FastKernel::none) out.push_back(m.name);
  return out;
}

Accel::Accel(const Scene& s, const BvhBuildOptions& opt, BvhSimd simd, BvhNodes nodes)
    : scene_(s), verts_(s.mesh.vertices.data()), ntri_(std::uint32_t(s.mesh.triangles.size())),
      triangle_bytes_(s.triangle_bytes()), simd_(bvh_simd_path(simd)) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<BvhBox> boxes;
  std::vector<Vec3<float>> centers;
  if (s.size() == s.mesh.triangles.size()) {  // triangles only: their bounds over TBB's threads
    boxes.resize(s.size()), centers.resize(s.size());
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, ntri_, 4096), [&](const auto& r) {
      for (std::uint32_t i = r.begin(); i < r.end(); ++i) triangle_bounds(s.triangle(i), boxes[i], centers[i]);
    });
  } else {
    s.primitive_bounds(boxes, centers);
  }
  build(boxes, centers, opt, nodes);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaf_prims_.size(), 4096), [&](const auto& r) {
    for (std::size_t j = r.begin(); j < r.end(); ++j)
      for (LeafPrim& p = leaf_prims_[j]; int k : {0, 1, 2}) p.v[k] = p.id < ntri_ ? s.mesh.triangles[p.id][k] : 0;
  });
  build_groups();
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Accel::Accel(const MeshRef& m, const BvhBuildOptions& opt, BvhSimd simd, BvhNodes nodes)
    : scene_(empty_scene()), verts_(m.vertices), ntri_(std::uint32_t(m.triangle_count)),
      triangle_bytes_(m.vertex_count * sizeof(Vec3<double>)), simd_(bvh_simd_path(simd)) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<BvhBox> boxes(m.triangle_count);
  std::vector<Vec3<float>> centers(m.triangle_count);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m.triangle_count, 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      const auto t = m.triangle(i);
      triangle_bounds({verts_[t[0]], verts_[t[1]], verts_[t[2]]}, boxes[i], centers[i]);
    }
  });
  build(boxes, centers, opt, nodes);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaf_prims_.size(), 4096), [&](const auto& r) {
    for (std::size_t j = r.begin(); j < r.end(); ++j) {
      LeafPrim& p = leaf_prims_[j];
      if (p.id == PrimHit::kNoPrim) continue;  // padding
      const auto t = m.triangle(p.id);
      for (int k = 0; k < 3; ++k) p.v[k] = t[k];
    }
  });
  build_groups();
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void Accel::build(const std::vector<BvhBox>& boxes, const std::vector<Vec3<float>>& centers, const BvhBuildOptions& opt,
                  BvhNodes nodes) {
  // Throws on a bad RAYPROOF_BVH_NODES before any work; automatic is decided by the tree's size.
  const BvhNodes asked = nodes == BvhNodes::automatic ? bvh_nodes_from_env() : nodes;
  const BvhCollapse collapse = bvh_collapse_choice(opt.collapse);
  // Subtrees in parallel on TBB's threads (the arena of the caller).
  Bvh bin = opt.binary ? opt.binary(boxes, centers) : build_bvh(boxes, centers, opt, [](std::size_t n, const auto& f) {
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) { f(i); });
  });
  // The wide tree of the path (eight-wide for AVX2, four-wide for SSE). Every leaf on a group
  // boundary, then prim_ids folded into leaf-order records (padding slots: kNoPrim; the
  // constructors add the triangles' vertex indices).
  auto fold = [&](auto& tree) {
    primitive_count_ = tree.prim_ids.size();
    const std::vector<std::uint32_t> old_of = detail::align_leaf_slots(std::span(tree.nodes), detail::kLanes);
    leaf_prims_.resize(old_of.size());
    for (std::size_t j = 0; j < leaf_prims_.size(); ++j)
      leaf_prims_[j] = {{0, 0, 0}, old_of[j] == detail::kPadLane ? PrimHit::kNoPrim : tree.prim_ids[old_of[j]]};
    std::vector<std::uint32_t>().swap(tree.prim_ids);
  };
  // Compressed nodes: a pass after the collapse and the leaf alignment (it copies the final leaf
  // references); the full tree is dropped when every node quantized, else kept (nodes_ full).
  auto compress = [&](auto& full, auto& q) {
    if (bvh_nodes_choice(asked, full.nodes.size() * sizeof(full.nodes[0])) != BvhNodes::compressed) return;
    auto c = quantize_wide(full, [](std::size_t n, const auto& f) {
      tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) { f(i); });
    });
    if (c) q = std::move(*c), full = {}, nodes_ = BvhNodes::compressed;
  };
  // The collapse weighs leaves as the builder does (groups of leaf_group at group_cost each).
  BvhCollapseCosts costs;
  costs.leaf_group = std::max<std::uint32_t>(1, opt.leaf_group);
  costs.group_cost = bvh_group_cost(opt.leaf_group, opt.group_cost);
  if (simd_ == BvhSimd::avx2) {
    bvh8_ = collapse_wide_as<8>(std::move(bin), boxes, collapse, costs);
    fold(bvh8_);
    compress(bvh8_, bvh8q_);
  } else {
    bvh_ = collapse_wide_as<4>(std::move(bin), boxes, collapse, costs);
    fold(bvh_);
    compress(bvh_, bvh4q_);
  }
}

void Accel::build_groups() {
  using namespace detail;
  groups_.clear();
  if (leaf_prims_.empty()) return;
  for (const LeafPrim& p : leaf_prims_)
    if (p.id != PrimHit::kNoPrim && p.id > kMaxGroupPrims) return;  // too many for the lane tags
  groups_.resize(leaf_prims_.size() / kLanes);
  tbb::parallel_for(std::size_t(0), groups_.size(), [&](std::size_t gi) {
    TriGroup& g = groups_[gi];
    for (int i = 0; i < kLanes; ++i) {
      const LeafPrim& p = leaf_prims_[gi * kLanes + i];
      for (int v = 0; v < 3; ++v)
        for (int a = 0; a < 3; ++a) g.p[v][a][i] = 0.0f;
      if (p.id == PrimHit::kNoPrim) {
        g.tag[i] = kPadLane;
      } else if (p.id >= ntri_) {
        g.tag[i] = kScalarLane | p.id;
      } else {
        const Triangle<float> t{verts_[p.v[0]].cast<float>(), verts_[p.v[1]].cast<float>(), verts_[p.v[2]].cast<float>()};
        const Vec3<float> q[3] = {t.p0, t.p1, t.p2};
        for (int v = 0; v < 3; ++v)
          for (int a = 0; a < 3; ++a) g.p[v][a][i] = q[v][a];
        g.tag[i] = triangle_lane_tag(t, p.id);
      }
    }
  });
}

double Accel::group_bytes_per_primitive() const {
  const std::size_t n = std::max<std::size_t>({1, scene_.size(), ntri_});
  return double(tree_bytes() + groups_.size() * sizeof(detail::TriGroup)) / double(n);
}

double Accel::bytes_read_per_primitive(const SceneMethod& m) const {
  const bool groups = !groups_.empty() && detail::leaf_simd() != detail::LeafSimd::off &&
                      (m.fast == FastKernel::mt_float || m.fast == FastKernel::robust);
  // Triangles only (a MeshRef's accel has an empty scene): the queries never read the records.
  const bool triangles_only = scene_.size() == 0 || scene_.size() == std::size_t(ntri_);
  if (groups && triangles_only) return group_bytes_per_primitive();
  return bytes_per_primitive();
}

double Accel::bytes_per_primitive() const {
  const std::size_t n = std::max<std::size_t>({1, scene_.size(), ntri_});
  return double(bvh_bytes() + triangle_bytes_) / double(n);
}

PrimHit Accel::closest(const Ray<double>& r, const SceneMethod& m, QueryRange q) const {
  PrimHit h;
  closest_range(&r, 0, 1, std::span<const QueryRange>(&q, 1),
                [](void* c, std::size_t, const PrimHit& x) { *static_cast<PrimHit*>(c) = x; }, &h, m);
  return h;
}

bool Accel::any(const Ray<double>& r, const SceneMethod& m, QueryRange q) const {
  std::uint8_t hit = 0;
  any_range(&r, 0, 1, std::span<const QueryRange>(&q, 1), &hit, m);
  return hit != 0;
}

void Accel::closest_batch(std::span<const Ray<double>> rays, std::span<PrimHit> out, const SceneMethod& m, int threads,
                          QueryRange q) const {
  closest_batch(rays, std::span<const QueryRange>(&q, 1), store_hit, out.data(), m, threads);
}

void Accel::any_batch(std::span<const Ray<double>> rays, std::span<std::uint8_t> out, const SceneMethod& m,
                      int threads, QueryRange q) const {
  any_batch(rays, std::span<const QueryRange>(&q, 1), out, m, threads);
}

void Accel::closest_batch(std::span<const Ray<double>> rays, std::span<const QueryRange> ranges, HitSink sink,
                          void* context, const SceneMethod& m, int threads) const {
  parallel_rays(rays.size(), threads,
                [&](std::size_t b, std::size_t e) { closest_range(rays.data(), b, e, ranges, sink, context, m); });
}

void Accel::any_batch(std::span<const Ray<double>> rays, std::span<const QueryRange> ranges,
                      std::span<std::uint8_t> out, const SceneMethod& m, int threads) const {
  parallel_rays(rays.size(), threads, [&](std::size_t b, std::size_t e) { any_range(rays.data(), b, e, ranges, out.data(), m); });
}

}  // namespace rayproof::scene
