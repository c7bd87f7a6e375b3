/// Wide-tree quality: the eight-wide tree of the greedy collapse (collapse_wide)
/// beside the SAH-optimal one (collapse_wide_sah) over the same binary tree, and (with Embree) the
/// SAH collapse of Embree's binary tree (rtcBuildBVH, scene/compare/embree_build.h): nodes, children per
/// node, leaves, the collapse's cost model, and per ray the node visits, leaf visits, leaf groups
/// and triangles tested, for closest and any hit on primary and random rays. The counts come
/// from the wide traversal loop itself (the double box test, conservative as robust and certified
/// traverse) with a plain double Möller–Trumbore leaf test, so they measure the tree, not a kernel.
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
#include "rayproof/bvh_wide_sah.h"
#include "rayproof/bvh_wide_stats.h"
#include "scene/compare/embree_build.h"
#include "scene/scene.h"
#include "scene/watertight.h"

using namespace rayproof;
using namespace rayproof::scene;

namespace {

struct Counts {
  double nodes = 0, leaves = 0, groups = 0, tris = 0;
};

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

template <BvhQuery Q>
Counts count(const Bvh8& w, const Scene& s, const std::vector<Ray<double>>& rays) {
  Counts c;
  for (const Ray<double>& ray : rays) {
    const BvhRay<double> br(ray, BvhTraversal::conservative);
    double tmax = std::numeric_limits<double>::infinity();
    auto test = [&](const Bvh8Node& n, double tm, double* t) {
      c.nodes += 1;
      return rayproof::detail::wide_test_double<true>(n, br, 0.0, tm, t);
    };
    auto leaf = [&](std::uint32_t first, std::uint32_t n) {
      c.leaves += 1, c.groups += double((n + 3) / 4), c.tris += n;
      bool hit = false;
      for (std::uint32_t j = first; j < first + n; ++j) {
        const double t = mt(s.triangle(w.prim_ids[j]), ray);
        if (t >= 0 && t <= tmax) hit = true, tmax = Q == BvhQuery::closest ? t : tmax;
      }
      return hit;
    };
    rayproof::detail::wide_traverse_loop<Bvh8, double, Q>(w, test, [&] { return tmax; }, leaf);
  }
  const double n = double(std::max<std::size_t>(1, rays.size()));
  return {c.nodes / n, c.leaves / n, c.groups / n, c.tris / n};
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
  // Embree's binary tree (binned SAH, blocks of four, leaves of up to eight), collapsed as ours.
  std::string why;
  const auto embree_binary = compare::embree_binary_builder(2 * opt.max_leaf, opt.leaf_group, &why);
  Bvh8 embree;
  if (embree_binary) embree = collapse_wide_sah<8>(embree_binary(boxes, centers), boxes, k);
  else std::printf("no Embree tree: %s\n", why.c_str());
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
  std::printf("%-7s %8s %9s %8s %8s | %-7s %6s %6s %6s %6s | %-7s %6s %6s %6s %6s\n", "collapse", "nodes", "children", "leaves",
              "cost", "per ray", "nodes", "leaves", "groups", "tris", "", "nodes", "leaves", "groups", "tris");
  for (const auto* w : {&greedy, &sah, static_cast<const Bvh8*>(&embree)}) {
    if (w->nodes.empty()) continue;
    std::size_t leaves = 0;
    for (const auto& n : w->nodes)
      for (int i = 0; i < 8; ++i) leaves += (n.valid >> i & 1) && n.count[i];
    const char* name = w == &greedy ? "greedy" : w == &sah ? "sah" : "embree";
    const Counts pc = count<BvhQuery::closest>(*w, s, primary), rc = count<BvhQuery::closest>(*w, s, random);
    const Counts pa = count<BvhQuery::any>(*w, s, primary), ra = count<BvhQuery::any>(*w, s, random);
    std::printf("%-8s %8zu %9.2f %8zu %8.2f\n", name, w->nodes.size(), wide_fullness(*w), leaves, wide_sah_cost(*w, k));
    auto row = [&](const char* what, const Counts& a, const Counts& b) {
      std::printf("  %-6s %-15s primary %6.2f %6.2f %6.2f %6.2f | random %6.2f %6.2f %6.2f %6.2f\n", name, what, a.nodes, a.leaves,
                  a.groups, a.tris, b.nodes, b.leaves, b.groups, b.tris);
    };
    row("closest", pc, rc);
    row("any", pa, ra);
  }
  return 0;
}
