/// Wide-tree quality: the eight-wide tree of the greedy collapse (collapse_wide)
/// beside the SAH-optimal one (collapse_wide_sah) over the same binary tree, and (with Embree) the
/// SAH collapse of Embree's binary tree (rtcBuildBVH, scene/compare/embree_build.h): nodes, children per
/// node, leaves, the collapse's cost model, and per ray the node visits, leaf visits, leaf groups
/// and triangles tested, for closest and any hit on primary and random rays. The counts come
/// from the wide traversal loop itself (the double box test, conservative as robust and certified
/// traverse) with a plain double Möller–Trumbore leaf test, so they measure the tree, not a kernel.
///
/// Memory: the leaves are aligned to groups of four as Accel lays them out (leaf_simd.h), and each
/// ray's reads are the scene BVH's: every line of each eight-wide node tested (256 bytes, four
/// lines) and every line of each leaf group tested (TriGroup, 160 bytes). `lines` counts the
/// distinct 64-byte lines a ray reads; `L1` and `L2` count those that miss in a simulated cache
/// kept warm from ray to ray in the set's order (least recently used, 32 KiB 8-way L1 and 512 KiB
/// 8-way L2 of 64-byte lines, as on a Zen core): the cache misses of one thread tracing the set,
/// modelled, since this machine's VM gives perf no counters. The trees compared are ours and
/// Embree's at quality medium, high, and high with spatial splits (duplicated triangles counted in
/// `tris`, and in the wide tree's size).
/// Run: tree_stats [mesh.off | generated[:N]] [rays] [node_cost] [max_merge]  (default: generated 2^20
/// triangles, 20000 rays per set, BvhCollapseCosts' defaults)
#include <algorithm>
#include <chrono>
#include <utility>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "rayproof/bvh_build.h"
#include "rayproof/bvh_wide.h"
#include "rayproof/bvh_wide_quantized.h"
#include "rayproof/bvh_wide_sah.h"
#include "rayproof/bvh_wide_stats.h"
#include "scene/compare/embree_build.h"
#include "scene/leaf_simd.h"
#include "scene/scene.h"
#include "scene/watertight.h"

using namespace rayproof;
using namespace rayproof::scene;

namespace {

struct Counts {
  double nodes = 0, leaves = 0, groups = 0, tris = 0, lines = 0, l1 = 0, l2 = 0;
};

/// A set-associative cache of 64-byte lines, least recently used out (way 0 the most recent).
class CacheModel {
 public:
  CacheModel(std::size_t bytes, std::size_t ways) : ways_(ways), sets_(bytes / 64 / ways), tag_(sets_ * ways, ~0ull) {}
  /// True on a miss; the line is then the set's most recent.
  bool miss(std::uint64_t line) {
    std::uint64_t* set = &tag_[(line % sets_) * ways_];
    std::size_t w = 0;
    while (w < ways_ && set[w] != line) ++w;
    const bool missed = w == ways_;
    for (std::size_t i = std::min(w, ways_ - 1); i > 0; --i) set[i] = set[i - 1];
    set[0] = line;
    return missed;
  }

 private:
  std::size_t ways_, sets_;
  std::vector<std::uint64_t> tag_;
};

/// An eight-wide tree with its leaves aligned to groups of four, as Accel lays them out:
/// old_of[slot] is the prim_ids entry a leaf slot holds (kPadLane for padding).
struct Aligned {
  Bvh8 w;
  std::vector<std::uint32_t> old_of;
};

Aligned align(Bvh8 w) {
  Aligned a{std::move(w), {}};
  a.old_of = scene::detail::align_leaf_slots(std::span(a.w.nodes), scene::detail::kLanes);
  return a;
}

/// Double Möller–Trumbore: t of a crossing in (tmin, tmax), or -1.
double mt(const Triangle<double>& tr, const Ray<double>& r) {
  const Vec3<double> e1 = tr.p1 - tr.p0, e2 = tr.p2 - tr.p0, p = cross(r.d, e2);
  const double det = dot(e1, p);
  if (det == 0) return -1;
  const double inv = 1 / det;
  const Vec3<double> s = r.o - tr.p0;
  const double u = dot(s, p) * inv;
  if (u < 0 || u > 1) return -1;
  const Vec3<double> q = cross(s, e1);
  const double v = dot(r.d, q) * inv;
  if (v < 0 || u + v > 1) return -1;
  return dot(e2, q) * inv;
}

/// Per ray on an eight-wide tree, full (Bvh8) or compressed (Bvh8Q: 128-byte nodes, two lines),
/// whose leaf slots old_of maps to prim_ids entries.
template <BvhQuery Q, class Tree>
Counts count(const Tree& w, const std::vector<std::uint32_t>& old_of, const Scene& s, const std::vector<Ray<double>>& rays) {
  using Node = typename Tree::Node;
  Counts c;
  CacheModel l1(32 << 10, 8), l2(512 << 10, 8);
  constexpr std::uint64_t kGroupBase = std::uint64_t(1) << 40;  // the groups' array, apart from the nodes'
  std::vector<std::uint64_t> lines;
  for (const Ray<double>& ray : rays) {
    const BvhRay<double> br(ray, BvhTraversal::conservative);
    double tmax = std::numeric_limits<double>::infinity();
    lines.clear();
    auto test = [&](const Node& n, double tm, double* t) {
      c.nodes += 1;
      const auto at = std::uint64_t(&n - w.nodes.data()) * sizeof(Node);
      for (std::uint64_t b = 0; b < sizeof(Node); b += 64) lines.push_back((at + b) / 64);
      return rayproof::detail::wide_test_double<true>(n, br, 0.0, tm, t);
    };
    auto leaf = [&](std::uint32_t first, std::uint32_t n) {
      c.leaves += 1, c.groups += double((n + 3) / 4);
      for (std::uint32_t g = first / 4; g <= (first + n - 1) / 4; ++g) {
        const std::uint64_t at = kGroupBase + std::uint64_t(g) * sizeof(scene::detail::TriGroup);
        for (std::uint64_t l = at / 64; l <= (at + sizeof(scene::detail::TriGroup) - 1) / 64; ++l) lines.push_back(l);
      }
      bool hit = false;
      for (std::uint32_t j = first; j < first + n; ++j) {
        if (old_of[j] == scene::detail::kPadLane) continue;
        c.tris += 1;
        const double t = mt(s.triangle(w.prim_ids[old_of[j]]), ray);
        if (t >= 0 && t <= tmax) hit = true, tmax = Q == BvhQuery::closest ? t : tmax;
      }
      return hit;
    };
    rayproof::detail::wide_traverse_loop<Tree, double, Q>(w, test, [&] { return tmax; }, leaf);
    // The cache sees the reads in order (a line read twice by one ray hits the second time).
    for (const std::uint64_t l : lines)
      if (l1.miss(l)) c.l1 += 1, c.l2 += l2.miss(l);
    std::sort(lines.begin(), lines.end());
    c.lines += double(std::unique(lines.begin(), lines.end()) - lines.begin());
  }
  const double n = double(std::max<std::size_t>(1, rays.size()));
  return {c.nodes / n, c.leaves / n, c.groups / n, c.tris / n, c.lines / n, c.l1 / n, c.l2 / n};
}

/// Per ray on the binary tree, in the order of bvh_traverse_impl (rayproof/bvh_traverse.h: both
/// children's boxes tested, the nearer first, entries beyond tmax dropped when popped), which has
/// no hook for its node reads. `nodes` counts inner nodes visited (two box tests each); the lines
/// are those of the two children's 32-byte nodes and of each triangle tested, taken as a 40-byte
/// record in leaf order (a leaf group's share per triangle); `groups` is zero (the binary tree has
/// none).
template <BvhQuery Q>
Counts count_binary(const Bvh& bin, const Scene& s, const std::vector<Ray<double>>& rays) {
  Counts c;
  CacheModel l1(32 << 10, 8), l2(512 << 10, 8);
  constexpr std::uint64_t kRecordBase = std::uint64_t(1) << 40;
  std::vector<std::uint64_t> lines;
  const double inf = std::numeric_limits<double>::infinity();
  for (const Ray<double>& ray : rays) {
    const BvhRay<double> br(ray, BvhTraversal::conservative);
    double tmax = inf;
    lines.clear();
    struct Entry {
      std::uint32_t node;
      double t;
    };
    std::vector<Entry> stack;
    std::uint32_t n = 0;
    bool done = br.enter<true>(bin.nodes[0].box, 0.0, tmax) == inf;
    while (!done) {
      const BvhNode& node = bin.nodes[n];
      bool next = false;
      if (node.is_leaf()) {
        c.leaves += 1;
        bool hit = false;
        for (std::uint32_t i = node.index; i < node.index + node.count; ++i) {
          c.tris += 1;
          const std::uint64_t at = kRecordBase + std::uint64_t(i) * 40;
          for (std::uint64_t l = at / 64; l <= (at + 39) / 64; ++l) lines.push_back(l);
          const double t = mt(s.triangle(bin.prim_ids[i]), ray);
          if (t >= 0 && t <= tmax) hit = true, tmax = Q == BvhQuery::closest ? t : tmax;
        }
        if (hit && Q == BvhQuery::any) break;
      } else {
        c.nodes += 1;
        const std::uint32_t a = node.index, b = a + 1;
        for (std::uint64_t l = std::uint64_t(a) * 32 / 64; l <= (std::uint64_t(b) * 32 + 31) / 64; ++l) lines.push_back(l);
        const double ta = br.enter<true>(bin.nodes[a].box, 0.0, tmax), tb = br.enter<true>(bin.nodes[b].box, 0.0, tmax);
        if (ta != inf && tb != inf) {
          stack.push_back(ta <= tb ? Entry{b, tb} : Entry{a, ta});
          n = ta <= tb ? a : b, next = true;
        } else if (ta != inf || tb != inf) {
          n = ta != inf ? a : b, next = true;
        }
      }
      while (!next) {
        if (stack.empty()) {
          done = true;
          break;
        }
        const Entry e = stack.back();
        stack.pop_back();
        if (Q != BvhQuery::closest || e.t <= tmax) n = e.node, next = true;
      }
    }
    for (const std::uint64_t l : lines)
      if (l1.miss(l)) c.l1 += 1, c.l2 += l2.miss(l);
    std::sort(lines.begin(), lines.end());
    c.lines += double(std::unique(lines.begin(), lines.end()) - lines.begin());
  }
  const double k = double(std::max<std::size_t>(1, rays.size()));
  return {c.nodes / k, c.leaves / k, 0, c.tris / k, c.lines / k, c.l1 / k, c.l2 / k};
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mesh = argc > 1 ? argv[1] : "generated";
  const std::size_t nrays = argc > 2 ? std::size_t(std::max(1, std::atoi(argv[2]))) : 20000;
  Scene s;
  if (mesh.rfind("generated", 0) == 0) add_mesh(s, bumpy_sphere(mesh.size() > 10 ? std::size_t(std::atoll(mesh.c_str() + 10)) : std::size_t(1) << 20));
  else s = load_scene(mesh);
  std::vector<BvhBox> boxes(s.size());
  std::vector<Vec3<float>> centers(s.size());
  BvhBox all;
  for (std::uint32_t i = 0; i < s.size(); ++i) triangle_bounds(s.triangle(i), boxes[i], centers[i]), all.extend(boxes[i]);
  const BvhBuildOptions opt{BvhBuilder::sah, 4};
  const Bvh bin = build_bvh(boxes, centers, opt);
  BvhCollapseCosts k;
  k.leaf_group = opt.leaf_group, k.group_cost = bvh_group_cost(opt.leaf_group, opt.group_cost);
  if (argc > 3) k.node_cost = float(std::atof(argv[3]));
  if (argc > 4) k.max_merge = std::uint32_t(std::atoi(argv[4]));
  // The collapses' times (one thread, fastest of 3; the copy of the binary tree not counted).
  auto timed = [&](auto&& collapse) {
    double best = 1e30;
    Bvh8 out;
    for (int r = 0; r < 3; ++r) {
      Bvh copy(bin);
      const auto t0 = std::chrono::steady_clock::now();
      out = collapse(std::move(copy));
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return std::pair{std::move(out), best};
  };
  const auto [greedy, greedy_s] = timed([&](Bvh&& b) { return collapse_wide<8>(std::move(b), boxes); });
  const auto [sah, sah_s] = timed([&](Bvh&& b) { return collapse_wide_sah<8>(std::move(b), boxes, k); });
  std::printf("collapse time: greedy %.1f ms, sah %.1f ms\n", 1e3 * greedy_s, 1e3 * sah_s);
  // Embree's binary trees (binned SAH at quality medium and high, and high with spatial splits;
  // blocks of four, leaves of up to eight), collapsed as ours.
  std::vector<std::pair<std::string, Aligned>> trees;
  Bvh embree_bin;  // Embree's binary tree at quality medium, before the collapse
  trees.emplace_back("greedy", align(greedy));
  trees.emplace_back("sah", align(sah));
  for (const auto q : {compare::EmbreeTreeQuality::medium, compare::EmbreeTreeQuality::high,
                       compare::EmbreeTreeQuality::high_splits}) {
    std::string why;
    const auto embree_binary = compare::embree_binary_builder(2 * opt.max_leaf, opt.leaf_group, &why, q,
                                                              [&s](std::uint32_t i) { return s.triangle(i); });
    if (!embree_binary) {
      std::printf("no Embree tree: %s\n", why.c_str());
      break;
    }
    const auto t0 = std::chrono::steady_clock::now();
    Bvh bin_e = embree_binary(boxes, centers);
    const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::size_t refs = bin_e.prim_ids.size();
    if (q == compare::EmbreeTreeQuality::medium) embree_bin = bin_e;
    trees.emplace_back(std::string("embree-") + compare::to_string(q), align(collapse_wide_sah<8>(std::move(bin_e), boxes, k)));
    std::printf("embree %s: binary build %.1f ms, %zu triangle references for %zu triangles\n", compare::to_string(q),
                1e3 * build_s, refs, s.size());
  }
  // Primary rays: a pinhole camera on the +z side of the box looking at its centre (a square grid);
  // random rays: origins uniform in the box, directions uniform on the sphere.
  const Vec3<double> lo{all.lo[0], all.lo[1], all.lo[2]}, hi{all.hi[0], all.hi[1], all.hi[2]};
  const Vec3<double> mid = (lo + hi) * 0.5, ext = hi - lo;
  const double r = std::max({ext.x, ext.y, ext.z});
  std::vector<Ray<double>> primary, random;
  const int side = int(std::sqrt(double(nrays)));
  const Vec3<double> eye = mid + Vec3<double>{0.1 * r, 0.2 * r, 1.6 * r};
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const Vec3<double> at = mid + Vec3<double>{(x + 0.5) / side - 0.5, (y + 0.5) / side - 0.5, 0} * (0.8 * r);
      primary.push_back({eye, at - eye});
    }
  std::mt19937_64 rng(20);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> nd;
  for (std::size_t i = 0; i < nrays; ++i)
    random.push_back({lo + Vec3<double>{u(rng) * ext.x, u(rng) * ext.y, u(rng) * ext.z}, Vec3<double>{nd(rng), nd(rng), nd(rng)}});
  std::printf("%s: %zu triangles; %zu primary, %zu random rays; costs: node %.1f, group %.1f (of %u), merge up to %u\n", mesh.c_str(), s.size(),
              primary.size(), random.size(), k.node_cost, k.group_cost, k.leaf_group, k.max_merge);
  std::printf("%-18s %8s %9s %8s %8s\n", "tree", "nodes", "children", "leaves", "cost");
  std::printf("  per ray: %-20s %-7s %6s %6s %6s %6s %6s %6s %6s\n", "", "rays", "nodes", "leaves", "groups", "tris", "lines",
              "L1", "L2");
  for (const auto& [name, a] : trees) {
    const Bvh8& w = a.w;
    std::size_t leaves = 0;
    for (const auto& n : w.nodes)
      for (int i = 0; i < 8; ++i) leaves += (n.valid >> i & 1) && n.count[i];
    std::printf("%-18s %8zu %9.2f %8zu %8.2f\n", name.c_str(), w.nodes.size(), wide_fullness(w), leaves, wide_sah_cost(w, k));
    auto row = [&](const char* what, const char* set, const Counts& x) {
      std::printf("  %-18s %-9s %-7s %6.2f %6.2f %6.2f %6.2f %6.2f %6.2f %6.2f\n", name.c_str(), what, set, x.nodes, x.leaves,
                  x.groups, x.tris, x.lines, x.l1, x.l2);
    };
    row("closest", "primary", count<BvhQuery::closest>(w, a.old_of, s, primary));
    row("closest", "random", count<BvhQuery::closest>(w, a.old_of, s, random));
    row("any", "primary", count<BvhQuery::any>(w, a.old_of, s, primary));
    row("any", "random", count<BvhQuery::any>(w, a.old_of, s, random));
    // The same tree with compressed nodes (as Accel quantizes it above 8 MiB of full nodes).
    if (name != "sah" && name != "embree-medium") continue;
    if (const auto qt = quantize_wide(w)) {
      const std::string qn = name + " compressed";
      std::printf("%-18s %8zu\n", qn.c_str(), qt->nodes.size());
      auto qrow = [&](const char* what, const char* set, const Counts& x) {
        std::printf("  %-18s %-9s %-7s %6.2f %6.2f %6.2f %6.2f %6.2f %6.2f %6.2f\n", qn.c_str(), what, set, x.nodes, x.leaves,
                    x.groups, x.tris, x.lines, x.l1, x.l2);
      };
      qrow("closest", "primary", count<BvhQuery::closest>(*qt, a.old_of, s, primary));
      qrow("closest", "random", count<BvhQuery::closest>(*qt, a.old_of, s, random));
    }
  }
  // The binary trees before the collapse (ours and Embree's at quality medium).
  for (const auto* b : {&bin, static_cast<const Bvh*>(&embree_bin)}) {
    if (b->nodes.empty()) continue;
    const char* bn = b == &bin ? "ours binary" : "embree binary";
    std::printf("%-18s %8zu\n", bn, b->nodes.size());
    for (const auto& [set, rays] : {std::pair<const char*, const std::vector<Ray<double>>*>{"primary", &primary}, {"random", &random}}) {
      const Counts x = count_binary<BvhQuery::closest>(*b, s, *rays);
      std::printf("  %-18s %-9s %-7s %6.2f %6.2f %6.2f %6.2f %6.2f %6.2f %6.2f\n", bn, "closest", set, x.nodes, x.leaves, x.groups,
                  x.tris, x.lines, x.l1, x.l2);
    }
  }
  return 0;
}
