// Scene queries: BVH construction, the per-method kernels behind one dispatch, and TBB batches.
#include "scene/accel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>

#include "scene/kernels.h"

namespace rayproof::scene {
namespace {

using detail::Crossing;
using detail::TriAlgo;

struct FastName {
  const char* name;
  FastKernel kernel;
  BvhTraversal traversal;
};
// Möller–Trumbore and Cramer are the worked problems' kernels with the textbook slab test;
// watertight (Woop et al.) keeps its guarantee only with conservative traversal (Ize).
constexpr FastName kFast[] = {
    {"float", FastKernel::mt_float, BvhTraversal::standard},
    {"double", FastKernel::mt_double, BvhTraversal::standard},
    {"cramer-float", FastKernel::cramer_float, BvhTraversal::standard},
    {"cramer-double", FastKernel::cramer_double, BvhTraversal::standard},
    {"watertight-float", FastKernel::watertight_float, BvhTraversal::conservative},
    {"watertight", FastKernel::watertight_double, BvhTraversal::conservative},
    {"robust", FastKernel::robust, BvhTraversal::conservative},
    {"certified", FastKernel::certified, BvhTraversal::conservative},
};

/// Runs `f(kernel)` with the kernel type the method names.
template <class F>
decltype(auto) with_kernel(const Scene& s, const Vec3<double>* v, std::uint32_t n, const SceneMethod& m, F&& f) {
  using detail::CompiledKernel;
  const Method* g = m.generic;
  switch (m.fast) {
    case FastKernel::mt_float: { CompiledKernel<float, TriAlgo::moller_trumbore> k{s, v, n}; return f(k); }
    case FastKernel::mt_double: { CompiledKernel<double, TriAlgo::moller_trumbore> k{s, v, n}; return f(k); }
    case FastKernel::cramer_float: { CompiledKernel<float, TriAlgo::cramer> k{s, v, n}; return f(k); }
    case FastKernel::cramer_double: { CompiledKernel<double, TriAlgo::cramer> k{s, v, n}; return f(k); }
    case FastKernel::watertight_float: { CompiledKernel<float, TriAlgo::watertight> k{s, v, n}; return f(k); }
    case FastKernel::watertight_double: { CompiledKernel<double, TriAlgo::watertight> k{s, v, n}; return f(k); }
    case FastKernel::robust: { CompiledKernel<float, TriAlgo::robust> k{s, v, n, g}; return f(k); }
    case FastKernel::certified: {
      CompiledKernel<double, TriAlgo::certified> k{s, v, n, g, m.triangle_fallback};
      return f(k);
    }
    case FastKernel::none: break;
  }
  detail::GenericKernel k{s, *m.generic};
  return f(k);
}

const Scene& empty_scene() {
  static const Scene s;
  return s;
}

template <class K>
PrimHit closest_with(const Bvh4& bvh, const LeafPrim* prims, K& k, const Ray<double>& r, BvhTraversal mode, QueryRange q) {
  if (!r.valid()) return {Contact::invalid};
  k.prepare(r);
  PrimHit best;
  double tmax = q.tmax;
  bvh4_traverse_slots(bvh, k.traversal_ray(), q.tmin, tmax, mode, BvhQuery::closest, [&](std::uint32_t j) {
    const LeafPrim& p = prims[j];
    const std::uint32_t id = p.id;
    Crossing c[2];
    const int n = k.crossings(p, c);
    for (int i = 0; i < n; ++i)
      if (c[i].t >= q.tmin && (c[i].t < tmax || (c[i].t == tmax && id < best.prim))) {
        tmax = c[i].t;
        best = {c[i].contact, c[i].t, id, c[i].b1, c[i].b2};
      }
    return false;
  });
  return best;
}

template <class K>
bool any_with(const Bvh4& bvh, const LeafPrim* prims, K& k, const Ray<double>& r, BvhTraversal mode, QueryRange q) {
  if (!r.valid()) return false;
  k.prepare(r);
  bool hit = false;
  bvh4_traverse_slots(bvh, k.traversal_ray(), q.tmin, q.tmax, mode, BvhQuery::any, [&](std::uint32_t j) {
    Crossing c[2];
    const int n = k.crossings(prims[j], c);
    for (int i = 0; i < n; ++i)
      if (c[i].t >= q.tmin && c[i].t <= q.tmax) return hit = true;
    return false;
  });
  return hit;
}

}  // namespace

SceneMethod find_scene_method(const std::string& name, const MethodRegistry& reg) {
  for (const auto& f : kFast) {
    if (name != f.name) continue;
    const bool needs_registry = f.kernel == FastKernel::robust || f.kernel == FastKernel::certified;
    const Method* m = needs_registry ? reg.find(name) : nullptr;
    if (needs_registry && !m) break;
    return {name, f.kernel, m, f.traversal};
  }
  if (const Method* m = reg.find(name)) return {name, FastKernel::none, m, BvhTraversal::conservative};
  std::string known;
  for (const auto& f : kFast) known += std::string(known.empty() ? "" : ", ") + f.name;
  throw SceneError("unknown method '" + name + "' (compiled: " + known + "; or any of: " + reg.names() + ")");
}

std::vector<std::string> fast_scene_method_names() {
  std::vector<std::string> out;
  for (const auto& f : kFast) out.emplace_back(f.name);
  return out;
}

Accel::Accel(const Scene& s, const BvhBuildOptions& opt)
    : scene_(s), verts_(s.mesh.vertices.data()), ntri_(std::uint32_t(s.mesh.triangles.size())),
      triangle_bytes_(s.triangle_bytes()) {
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
  build(boxes, centers, opt);
  for (LeafPrim& p : leaf_prims_)
    for (int k = 0; k < 3; ++k) p.v[k] = p.id < ntri_ ? s.mesh.triangles[p.id][k] : 0;
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Accel::Accel(const MeshRef& m, const BvhBuildOptions& opt)
    : scene_(empty_scene()), verts_(m.vertices), ntri_(std::uint32_t(m.triangle_count)),
      triangle_bytes_(m.vertex_count * sizeof(Vec3<double>)) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<BvhBox> boxes(m.triangle_count);
  std::vector<Vec3<float>> centers(m.triangle_count);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m.triangle_count, 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      const auto t = m.triangle(i);
      triangle_bounds({verts_[t[0]], verts_[t[1]], verts_[t[2]]}, boxes[i], centers[i]);
    }
  });
  build(boxes, centers, opt);
  for (LeafPrim& p : leaf_prims_) {
    const auto t = m.triangle(p.id);
    for (int k = 0; k < 3; ++k) p.v[k] = t[k];
  }
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void Accel::build(const std::vector<BvhBox>& boxes, const std::vector<Vec3<float>>& centers, const BvhBuildOptions& opt) {
  // Subtrees in parallel on TBB's threads (the arena of the caller).
  Bvh bin = build_bvh(boxes, centers, opt, [](std::size_t n, const auto& f) {
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) { f(i); });
  });
  bvh_ = collapse_bvh4(std::move(bin), boxes);
  // prim_ids folded into leaf-order records (the constructors add the triangles' vertex indices).
  leaf_prims_.resize(bvh_.prim_ids.size());
  for (std::size_t j = 0; j < leaf_prims_.size(); ++j) leaf_prims_[j] = {{0, 0, 0}, bvh_.prim_ids[j]};
  std::vector<std::uint32_t>().swap(bvh_.prim_ids);
}

double Accel::bytes_per_primitive() const {
  const std::size_t n = std::max<std::size_t>({1, scene_.size(), ntri_});
  return double(bvh_bytes() + triangle_bytes_) / double(n);
}

PrimHit Accel::closest(const Ray<double>& r, const SceneMethod& m, QueryRange q) const {
  return with_kernel(scene_, verts_, ntri_, m,
                     [&](auto& k) { return closest_with(bvh_, leaf_prims_.data(), k, r, m.traversal, q); });
}

bool Accel::any(const Ray<double>& r, const SceneMethod& m, QueryRange q) const {
  return with_kernel(scene_, verts_, ntri_, m,
                     [&](auto& k) { return any_with(bvh_, leaf_prims_.data(), k, r, m.traversal, q); });
}

std::vector<PrimHit> Accel::all(const Ray<double>& r, const SceneMethod& m, QueryRange q) const {
  std::vector<PrimHit> out;
  if (!r.valid()) return out;
  with_kernel(scene_, verts_, ntri_, m, [&](auto& k) {
    k.prepare(r);
    bvh4_traverse_slots(bvh_, k.traversal_ray(), q.tmin, q.tmax, m.traversal, BvhQuery::all, [&](std::uint32_t j) {
      const std::uint32_t id = leaf_prims_[j].id;
      Crossing c[2];
      const int n = k.crossings(leaf_prims_[j], c);
      for (int i = 0; i < n; ++i)
        if (c[i].t >= q.tmin && c[i].t <= q.tmax) out.push_back({c[i].contact, c[i].t, id, c[i].b1, c[i].b2});
      return false;
    });
    return 0;
  });
  std::sort(out.begin(), out.end(), [](const PrimHit& a, const PrimHit& b) { return a.t < b.t || (a.t == b.t && a.prim < b.prim); });
  return out;
}

namespace {
template <class Body>
void parallel_rays(std::size_t n, int threads, Body&& body) {
  const int t = threads > 0 ? threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(t);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& r) {
      body(r.begin(), r.end());
    });
  });
}
}  // namespace

void Accel::closest_batch(std::span<const Ray<double>> rays, std::span<PrimHit> out, const SceneMethod& m, int threads,
                          QueryRange q) const {
  parallel_rays(rays.size(), threads, [&](std::size_t b, std::size_t e) {
    with_kernel(scene_, verts_, ntri_, m, [&](auto& k) {
      for (std::size_t i = b; i < e; ++i) out[i] = closest_with(bvh_, leaf_prims_.data(), k, rays[i], m.traversal, q);
      return 0;
    });
  });
}

void Accel::any_batch(std::span<const Ray<double>> rays, std::span<std::uint8_t> out, const SceneMethod& m,
                      int threads, QueryRange q) const {
  any_batch(rays, std::span<const QueryRange>(&q, 1), out, m, threads);
}

namespace {
/// Ray i's range: one per ray, one for all, or the default.
QueryRange range_of(std::span<const QueryRange> ranges, std::size_t i) {
  return ranges.size() > 1 ? ranges[i] : ranges.empty() ? QueryRange{} : ranges[0];
}
}  // namespace

void Accel::closest_batch(std::span<const Ray<double>> rays, std::span<const QueryRange> ranges, HitSink sink,
                          void* context, const SceneMethod& m, int threads) const {
  parallel_rays(rays.size(), threads, [&](std::size_t b, std::size_t e) {
    with_kernel(scene_, verts_, ntri_, m, [&](auto& k) {
      for (std::size_t i = b; i < e; ++i)
        sink(context, i, closest_with(bvh_, leaf_prims_.data(), k, rays[i], m.traversal, range_of(ranges, i)));
      return 0;
    });
  });
}

void Accel::any_batch(std::span<const Ray<double>> rays, std::span<const QueryRange> ranges,
                      std::span<std::uint8_t> out, const SceneMethod& m, int threads) const {
  parallel_rays(rays.size(), threads, [&](std::size_t b, std::size_t e) {
    with_kernel(scene_, verts_, ntri_, m, [&](auto& k) {
      for (std::size_t i = b; i < e; ++i)
        out[i] = any_with(bvh_, leaf_prims_.data(), k, rays[i], m.traversal, range_of(ranges, i));
      return 0;
    });
  });
}

}  // namespace rayproof::scene
