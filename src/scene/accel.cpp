// Scene queries: BVH construction, the per-method kernels behind one dispatch, and TBB batches.
#include "scene/accel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <emmintrin.h>

#include <algorithm>
#include <chrono>
#include <type_traits>

#include "rayproof/bvh_packet.h"
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

/// What a query traverses: the nodes, the leaf records, the packed groups (null: none) and the
/// group kernels' path.
template <class Tree>
struct Leaves {
  const Tree& bvh;  ///< Bvh4 (SSE path) or Bvh8 (AVX2 path)
  const LeafPrim* prims;
  const detail::TriGroup* groups;
  detail::LeafSimd simd;
};

template <class Tree, class G>
Leaves<Tree> leaves_of(const Tree& bvh, const std::vector<LeafPrim>& prims, const G& groups) {
  const detail::LeafSimd simd = detail::leaf_simd();
  return {bvh, prims.data(), groups.empty() || simd == detail::LeafSimd::off ? nullptr : groups.data(), simd};
}

/// The kernels with group versions (leaf_simd.h): `float`, `robust` and `certified`.
template <class K>
constexpr bool kGroupKernel = std::is_same_v<K, detail::CompiledKernel<float, TriAlgo::moller_trumbore>> ||
                              std::is_same_v<K, detail::CompiledKernel<float, TriAlgo::robust>> ||
                              std::is_same_v<K, detail::CompiledKernel<double, TriAlgo::certified>>;

/// Lane i of group g as a float triangle.
inline Triangle<float> lane_triangle(const detail::TriGroup& g, int i) {
  auto p = [&](int v) { return Vec3<float>{g.p[v][0][i], g.p[v][1][i], g.p[v][2][i]}; };
  return {p(0), p(1), p(2)};
}

/// certified's leaves: when on (certified_screen(), off by default: it does not pay), first the
/// float screen on the group's float vertices (the roundings of the double ones); then the leaf
/// records (ids and vertex indices), the double vertices, stage 1's proven misses in lanes
/// (AVX2), the other lanes through the per-primitive kernel.
template <class K, class L_, class Emit>
bool certified_leaf(const K& k, const L_& L, std::uint32_t first, std::uint32_t count, Emit& emit) {
  using namespace detail;
  const std::uint32_t end = first + count;
  const bool screen = L.simd != LeafSimd::scalar && certified_screen();
  for (std::uint32_t g0 = first; g0 < end; g0 += kLanes) {
    unsigned in = end - g0 >= std::uint32_t(kLanes) ? (1u << kLanes) - 1 : (1u << (end - g0)) - 1;
    Crossing c[2];
    unsigned miss = 0;
    if (screen) {
      // Triangle lanes: tags without the top bit (pad and scalar lanes have it).
      const TriGroup& g = L.groups[g0 / kLanes];
      const unsigned not_tri = unsigned(_mm_movemask_ps(_mm_load_ps(reinterpret_cast<const float*>(g.tag))));
      in &= ~certified_group_float_misses(k.lane_ray, g, in & ~not_tri);
      if (!in) continue;
    }
    if (L.simd == LeafSimd::avx2) {
      alignas(32) double p[3][3][kLanes];
      unsigned tri = 0;
      for (int i = 0; i < kLanes; ++i) {
        const LeafPrim& lp = L.prims[g0 + i];
        const bool is_tri = (in >> i & 1) && lp.id < k.ntri;
        tri |= unsigned(is_tri) << i;
        for (int v = 0; v < 3; ++v) {
          const Vec3<double> x = is_tri ? k.verts[lp.v[v]] : Vec3<double>{};  // (no vertex array without triangles)
          p[v][0][i] = x.x, p[v][1][i] = x.y, p[v][2][i] = x.z;
        }
      }
      miss = certified_group_misses_avx2(k.ray_d, p, tri);
    }
    for (unsigned m = in & ~miss; m; m &= m - 1) {
      const LeafPrim& lp = L.prims[g0 + __builtin_ctz(m)];
      const int n = k.crossings(lp, c);
      if (n && emit(lp.id, c, n)) return true;
    }
  }
  return false;
}

/// One leaf's slots [first, first + count) through the group kernels (float, robust): emit(id, crossings, n) for
/// every primitive with crossings, in slot order within each group; true when emit asks to stop.
template <class K, class L_, class Emit>
bool group_leaf(const K& k, const L_& L, std::uint32_t first, std::uint32_t count, Emit& emit) {
  using namespace detail;
  constexpr bool kRobust = std::is_same_v<K, CompiledKernel<float, TriAlgo::robust>>;
  const std::uint32_t end = first + count;
  for (std::uint32_t g0 = first; g0 < end; g0 += kLanes) {
    const unsigned in = end - g0 >= std::uint32_t(kLanes) ? (1u << kLanes) - 1 : (1u << (end - g0)) - 1;
    Crossing c[2];
    const TriGroup& g = L.groups[g0 / kLanes];
    // The lanes' kinds from the tags' two top bits (padding lies past `in`: leaves end before it).
    static_assert(kLanes == 4 && kScalarLane == 0x80000000u && kDeadLane == 0x40000000u);
    const __m128i tags = _mm_load_si128(reinterpret_cast<const __m128i*>(g.tag));
    const unsigned bit31 = unsigned(_mm_movemask_ps(_mm_castsi128_ps(tags)));
    const unsigned bit30 = unsigned(_mm_movemask_ps(_mm_castsi128_ps(_mm_slli_epi32(tags, 1))));
    const unsigned scalar = in & bit31;
    const unsigned dead = in & ~bit31 & bit30, tri = in & ~bit31 & ~bit30;
    // Lanes that the per-primitive kernel finishes (in slot order with the lane results).
    unsigned finish;
    RobustLanes lanes;
    lanes.hit = 0;
    if constexpr (kRobust) {
      if (!k.ray_ok) {
        finish = 0;  // the scalar kernel's `invalid`: no triangle crossing
      } else if (L.simd == LeafSimd::avx2) {
        robust_group_avx2(k.lane_ray, g, robust_screen_avx2() ? tri & ~robust_group_float_misses(k.lane_ray, g, tri) : tri,
                          lanes);
        finish = lanes.special;
      } else if (L.simd == LeafSimd::sse) {
        finish = tri & ~robust_group_float_misses(k.lane_ray, g, tri);  // the float screen's misses need no kernel
      } else {
        finish = tri;  // dead lanes: the scalar kernel reports nothing for them either
      }
    } else {
      finish = L.simd == LeafSimd::scalar ? tri | dead : mt_group_survivors(k.ray, g, tri | dead);
    }
    for (unsigned m = finish | lanes.hit | scalar; m; m &= m - 1) {
      const int i = __builtin_ctz(m);
      const std::uint32_t id = g.tag[i] & kLaneIdMask;
      int n;
      if (scalar >> i & 1) {
        n = k.crossings(L.prims[g0 + i], c);
      } else if (lanes.hit >> i & 1) {
        c[0] = {static_cast<Contact>(lanes.contact[i]), double(lanes.t[i]), double(lanes.b1[i]), double(lanes.b2[i])};
        n = 1;
      } else {
        n = k.triangle_crossings(lane_triangle(g, i), c);
      }
      if (n && emit(id, c, n)) return true;
    }
  }
  return false;
}

/// Runs the traversal with the leaf groups when the kernel has group versions and the groups
/// exist, else slot by slot: emit(id, crossings, n) as in group_leaf.
template <class K, class L_, class Emit>
void traverse_with(const L_& L, const K& k, QueryRange q, const double& tmax, BvhTraversal mode, BvhQuery query,
                   Emit&& emit) {
  if constexpr (kGroupKernel<K>) {
    if (L.groups) {
      wide_traverse_leaves(L.bvh, k.traversal_ray(), q.tmin, tmax, mode, query,
                           [&](std::uint32_t first, std::uint32_t count) {
                             if constexpr (std::is_same_v<K, detail::CompiledKernel<double, TriAlgo::certified>>) {
                               return certified_leaf(k, L, first, count, emit);
                             } else {
                               return group_leaf(k, L, first, count, emit);
                             }
                           });
      return;
    }
  }
  wide_traverse_leaves(L.bvh, k.traversal_ray(), q.tmin, tmax, mode, query, [&](std::uint32_t first, std::uint32_t count) {
    for (std::uint32_t j = first; j < first + count; ++j) {
      Crossing c[2];
      const int n = k.crossings(L.prims[j], c);
      if (n && emit(L.prims[j].id, c, n)) return true;
    }
    return false;
  });
}

template <class L_, class K>
PrimHit closest_with(const L_& L, K& k, const Ray<double>& r, BvhTraversal mode, QueryRange q) {
  if (!r.valid()) return {Contact::invalid};
  k.prepare(r);
  PrimHit best;
  double tmax = q.tmax;
  traverse_with(L, k, q, tmax, mode, BvhQuery::closest, [&](std::uint32_t id, const Crossing* c, int n) {
    for (int i = 0; i < n; ++i)
      if (c[i].t >= q.tmin && (c[i].t < tmax || (c[i].t == tmax && id < best.prim))) {
        tmax = c[i].t;
        best = {c[i].contact, c[i].t, id, c[i].b1, c[i].b2};
      }
    return false;
  });
  return best;
}

template <class L_, class K>
bool any_with(const L_& L, K& k, const Ray<double>& r, BvhTraversal mode, QueryRange q) {
  if (!r.valid()) return false;
  k.prepare(r);
  bool hit = false;
  traverse_with(L, k, q, q.tmax, mode, BvhQuery::any, [&](std::uint32_t, const Crossing* c, int n) {
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
  // Subtrees in parallel on TBB's threads (the arena of the caller).
  Bvh bin = build_bvh(boxes, centers, opt, [](std::size_t n, const auto& f) {
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
  if (simd_ == BvhSimd::avx2) {
    bvh8_ = collapse_bvh8(std::move(bin), boxes);
    fold(bvh8_);
    compress(bvh8_, bvh8q_);
  } else {
    bvh_ = collapse_bvh4(std::move(bin), boxes);
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
  return with_tree([&](const auto& tree) {
    return with_kernel(scene_, verts_, ntri_, m,
                       [&](auto& k) { return closest_with(leaves_of(tree, leaf_prims_, groups_), k, r, m.traversal, q); });
  });
}

bool Accel::any(const Ray<double>& r, const SceneMethod& m, QueryRange q) const {
  return with_tree([&](const auto& tree) {
    return with_kernel(scene_, verts_, ntri_, m,
                       [&](auto& k) { return any_with(leaves_of(tree, leaf_prims_, groups_), k, r, m.traversal, q); });
  });
}

std::vector<PrimHit> Accel::all(const Ray<double>& r, const SceneMethod& m, QueryRange q) const {
  std::vector<PrimHit> out;
  if (!r.valid()) return out;
  with_tree([&](const auto& tree) {
    return with_kernel(scene_, verts_, ntri_, m, [&](auto& k) {
      k.prepare(r);
      traverse_with(leaves_of(tree, leaf_prims_, groups_), k, q, q.tmax, m.traversal, BvhQuery::all,
                    [&](std::uint32_t id, const Crossing* c, int n) {
                      for (int i = 0; i < n; ++i)
                        if (c[i].t >= q.tmin && c[i].t <= q.tmax) out.push_back({c[i].contact, c[i].t, id, c[i].b1, c[i].b2});
                      return false;
                    });
      return 0;
    });
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
    with_tree([&](const auto& tree) {
      return with_kernel(scene_, verts_, ntri_, m, [&](auto& k) {
        for (std::size_t i = b; i < e; ++i) out[i] = closest_with(leaves_of(tree, leaf_prims_, groups_), k, rays[i], m.traversal, q);
        return 0;
      });
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
    with_tree([&](const auto& tree) {
      return with_kernel(scene_, verts_, ntri_, m, [&](auto& k) {
        for (std::size_t i = b; i < e; ++i)
          sink(context, i, closest_with(leaves_of(tree, leaf_prims_, groups_), k, rays[i], m.traversal, range_of(ranges, i)));
        return 0;
      });
    });
  });
}

void Accel::any_batch(std::span<const Ray<double>> rays, std::span<const QueryRange> ranges,
                      std::span<std::uint8_t> out, const SceneMethod& m, int threads) const {
  parallel_rays(rays.size(), threads, [&](std::size_t b, std::size_t e) {
    with_tree([&](const auto& tree) {
      return with_kernel(scene_, verts_, ntri_, m, [&](auto& k) {
        for (std::size_t i = b; i < e; ++i)
          out[i] = any_with(leaves_of(tree, leaf_prims_, groups_), k, rays[i], m.traversal, range_of(ranges, i));
        return 0;
      });
    });
  });
}

}  // namespace rayproof::scene

// Packets of eight rays (issue 15; the traversal in rayproof/bvh_packet.h): the leaf code of
// traverse_with, called per lane.
namespace rayproof::scene {
namespace {

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

template <class Tree, class K>
void closest_packet(const Leaves<Tree>& L, K* ks, const Ray<double>* rays, int n, std::span<const QueryRange> ranges,
                    std::size_t first, BvhTraversal mode, PrimHit* out) {
  PacketLanes<K> P(ks, rays, n, ranges, first);
  for (int i = 0; i < n; ++i) out[i] = P.live >> i & 1 ? PrimHit{} : PrimHit{Contact::invalid};
  bvh8_packet_traverse_leaves(L.bvh, P.ray, P.tmin, P.tmax, P.live, mode, BvhQuery::closest,
                              [&](int lane, std::uint32_t f, std::uint32_t count) {
                                PrimHit& best = out[lane];
                                double& tmax = P.tmax[lane];
                                const double tmin = P.q[lane].tmin;
                                // closest_with's emit, for this lane.
                                auto emit = [&](std::uint32_t id, const Crossing* c, int nc) {
                                  for (int i = 0; i < nc; ++i)
                                    if (c[i].t >= tmin && (c[i].t < tmax || (c[i].t == tmax && id < best.prim))) {
                                      tmax = c[i].t;
                                      best = {c[i].contact, c[i].t, id, c[i].b1, c[i].b2};
                                    }
                                  return false;
                                };
                                return leaf_for_ray(L, P.kernel(lane), f, count, emit);
                              });
}

template <class Tree, class K>
void any_packet(const Leaves<Tree>& L, K* ks, const Ray<double>* rays, int n, std::span<const QueryRange> ranges,
                std::size_t first, BvhTraversal mode, std::uint8_t* out) {
  PacketLanes<K> P(ks, rays, n, ranges, first);
  for (int i = 0; i < n; ++i) out[i] = 0;
  bvh8_packet_traverse_leaves(L.bvh, P.ray, P.tmin, P.tmax, P.live, mode, BvhQuery::any,
                              [&](int lane, std::uint32_t f, std::uint32_t count) {
                                const QueryRange q = P.q[lane];
                                // any_with's emit, for this lane.
                                auto emit = [&](std::uint32_t, const Crossing* c, int nc) {
                                  for (int i = 0; i < nc; ++i)
                                    if (c[i].t >= q.tmin && c[i].t <= q.tmax) {
                                      out[lane] = 1;
                                      return true;
                                    }
                                  return false;
                                };
                                return leaf_for_ray(L, P.kernel(lane), f, count, emit);
                              });
}

/// The trees the packet traversal runs on (the AVX2 path's); the SSE path's answer ray by ray.
template <class Tree>
constexpr bool is_eight_wide = std::is_same_v<Tree, Bvh8> || std::is_same_v<Tree, Bvh8Q>;

/// Runs `one(kernels, first ray, n)` for each packet of a batch: eight copies of the method's kernel.
template <class K, class One>
void packets_over(std::size_t b, std::size_t e, std::size_t nrays, const K& k, One&& one) {
  K ks[kPacketWidth] = {k, k, k, k, k, k, k, k};
  for (std::size_t p = b; p < e; ++p) {
    const std::size_t first = p * kPacketWidth;
    one(ks, first, int(std::min<std::size_t>(kPacketWidth, nrays - first)));
  }
}

}  // namespace

template <class Packet, class Single>
void Accel::over_packets(std::size_t nrays, const SceneMethod& m, int threads, Packet&& packet, Single&& single) const {
  const std::size_t packets = (nrays + kPacketWidth - 1) / kPacketWidth;
  parallel_rays(packets, threads, [&](std::size_t b, std::size_t e) {
    with_tree([&](const auto& tree) {
      return with_kernel(scene_, verts_, ntri_, m, [&](auto& k) {
        const auto L = leaves_of(tree, leaf_prims_, groups_);
        if constexpr (is_eight_wide<std::decay_t<decltype(tree)>>) {
          packets_over(b, e, nrays, k, [&](auto* ks, std::size_t first, int n) { packet(L, ks, first, n); });
        } else {  // the SSE path: ray by ray
          for (std::size_t i = b * kPacketWidth; i < std::min(e * kPacketWidth, nrays); ++i) single(L, k, i);
        }
        return 0;
      });
    });
  });
}

void Accel::closest_packets(std::span<const Ray<double>> rays, std::span<const QueryRange> ranges, std::span<PrimHit> out,
                            const SceneMethod& m, int threads) const {
  over_packets(
      rays.size(), m, threads,
      [&](const auto& L, auto* ks, std::size_t first, int n) {
        closest_packet(L, ks, &rays[first], n, ranges, first, m.traversal, &out[first]);
      },
      [&](const auto& L, auto& k, std::size_t i) { out[i] = closest_with(L, k, rays[i], m.traversal, range_of(ranges, i)); });
}

void Accel::any_packets(std::span<const Ray<double>> rays, std::span<const QueryRange> ranges, std::span<std::uint8_t> out,
                        const SceneMethod& m, int threads) const {
  over_packets(
      rays.size(), m, threads,
      [&](const auto& L, auto* ks, std::size_t first, int n) {
        any_packet(L, ks, &rays[first], n, ranges, first, m.traversal, &out[first]);
      },
      [&](const auto& L, auto& k, std::size_t i) { out[i] = any_with(L, k, rays[i], m.traversal, range_of(ranges, i)); });
}

}  // namespace rayproof::scene
