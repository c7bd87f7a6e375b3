#pragma once
/// SIMD leaves: each BVH leaf's triangles packed in groups of kLanes lanes,
/// structure of arrays, so one kernel call tests a group of triangles at once.
///
/// Layout. A leaf of the wide BVH is a range [child, child + count) of leaf-order slots; after
/// align_leaf_slots every leaf starts on a multiple of kLanes, so slot j is lane j % kLanes of
/// group j / kLanes, and a leaf covers groups [child / kLanes, (child + count - 1) / kLanes]. The
/// slots between two leaves are padding (their LeafPrim has id = kNoPrim; their lanes are marked
/// kPadLane and never reported).
///
/// A group holds the triangles' vertices rounded to float (what the `float` and `robust` kernels
/// intersect: docs/cases.md's "inputs rounded to float") and a tag per lane: the primitive's global
/// number, or kPadLane, or kScalarLane | number for a lane the group kernels leave to the
/// per-primitive kernel (not a triangle), or kDeadLane | number for a triangle the robust kernel
/// classes invalid or degenerate whatever the ray (a non-finite float vertex, or the double normal
/// of the float vertices is zero): robust reports nothing for it, other kernels test it as usual.
///
/// Kernels. `certified`: stage 1's volumes u0, u1, u2 and their static error bounds in four double
/// lanes (AVX2), from the double vertices (read through the leaf records' vertex indices: the groups
/// hold only floats); the lanes it proves missed report nothing, the others go to
/// certified::triangle. `float` (Möller–Trumbore): the miss screen mt_surely_no_crossing in four float lanes
/// (SSE, the x86-64 baseline), the full scalar kernel only for the lanes that pass it. `robust`:
/// the prepared watertight test in double, four lanes (AVX2 at run time, else lane by lane with the
/// scalar kernel): the same operations on the same values in the same order, no fused multiply-add
/// (the project compiles with -ffp-contract=off, and the AVX2 code uses separate multiply and add
/// instructions), so every lane's U, V, W, det, t_scaled and their signs are bit for bit the scalar
/// kernel's. Lanes with d . n = 0 (parallel or coplanar) go to the scalar front door, as the scalar
/// kernel does. On the SSE path, robust's float screen (robust_group_float_misses, four float
/// lanes, x86-64 baseline) first decides the lanes whose double edge functions are certain to have
/// mixed signs (an error bound covering the float and the double evaluation), and only the other
/// lanes go to the scalar kernel. On the AVX2 path the screen is off by default: in front of the
/// four double lanes it was measured 3-11% slower per ray (leaf_bench, bunny00).
///
/// Path selection: AVX2 when the CPU has it, unless the environment variable RAYPROOF_SIMD is
/// `sse` (robust's float screen then lane by lane, float's screen in SSE), `scalar` (every lane
/// through the scalar kernel) or `off` (no groups: slot by slot, as before them). Tests force a
/// path with force_leaf_simd.
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "rayproof/bvh.h"
#include "rayproof/contact.h"
#include "rayproof/ray.h"
#include "rayproof/triangle_common.h"

namespace rayproof::scene::detail {

inline constexpr int kLanes = 4;
inline constexpr std::uint32_t kPadLane = 0xffffffffu;
inline constexpr std::uint32_t kScalarLane = 0x80000000u;
inline constexpr std::uint32_t kDeadLane = 0x40000000u;
inline constexpr std::uint32_t kLaneIdMask = 0x3fffffffu;
/// Groups are built only when every global number fits below the tag bits.
inline constexpr std::uint32_t kMaxGroupPrims = kLaneIdMask;

struct alignas(32) TriGroup {
  float p[3][3][kLanes];        ///< p[vertex][axis][lane], rounded to float
  std::uint32_t tag[kLanes];    ///< global number, or kPadLane, kScalarLane | n, kDeadLane | n
};
static_assert(sizeof(TriGroup) == 160);

/// off: no groups, the queries go slot by slot through the per-primitive kernels (the reference);
/// scalar: the groups, every lane through the per-primitive kernel; sse: float's screen and robust's
/// float screen in SSE, the undecided lanes one by one; avx2: both in lanes.
/// A triangle lane's tag: `id`, with kDeadLane when robust classes the triangle invalid or
/// degenerate for every ray (its screens in kernels.h: a non-finite float vertex, or the double
/// normal cross(p1 - p0, p2 - p0) of the float vertices is zero).
[[nodiscard]] inline std::uint32_t triangle_lane_tag(const Triangle<float>& t, std::uint32_t id) {
  if (!triangle_finite(t)) return kDeadLane | id;
  const Vec3<double> p0 = t.p0.cast<double>(), p1 = t.p1.cast<double>(), p2 = t.p2.cast<double>();
  return is_zero(cross(p1 - p0, p2 - p0)) ? kDeadLane | id : id;
}

enum class LeafSimd { off, scalar, sse, avx2 };

/// The path the queries use: forced by force_leaf_simd, else RAYPROOF_SIMD, else the best the CPU has.
[[nodiscard]] LeafSimd leaf_simd();
/// Forces a path (tests); never above what the CPU has (avx2 on a CPU without it: sse).
void force_leaf_simd(LeafSimd s);
/// Back to the environment / CPU choice.
void unforce_leaf_simd();
[[nodiscard]] const char* to_string(LeafSimd s);

/// Rewrites the leaf references of `nodes` (fields child[i], count[i], valid: Bvh4Node, and any node
/// type with the same fields) so that every leaf starts on a multiple of `lanes`, keeping the
/// leaves' order. Returns, for each new slot, the old slot it holds (kPadLane for padding).
template <class Node>
std::vector<std::uint32_t> align_leaf_slots(std::span<Node> nodes, std::uint32_t lanes) {
  struct Ref {
    std::uint32_t first, count;
    Node* node;
    int i;
  };
  std::vector<Ref> refs;
  constexpr int kWidth = int(sizeof(Node::child) / sizeof(Node::child[0]));
  for (Node& n : nodes)
    for (int i = 0; i < kWidth; ++i)
      if ((n.valid >> i & 1) && n.count[i]) refs.push_back({n.child[i], n.count[i], &n, i});
  std::sort(refs.begin(), refs.end(), [](const Ref& a, const Ref& b) { return a.first < b.first; });
  std::vector<std::uint32_t> old_of;
  for (const Ref& r : refs) {
    while (old_of.size() % lanes) old_of.push_back(kPadLane);
    r.node->child[r.i] = static_cast<std::uint32_t>(old_of.size());
    for (std::uint32_t k = 0; k < r.count; ++k) old_of.push_back(r.first + k);
  }
  while (old_of.size() % lanes) old_of.push_back(kPadLane);
  return old_of;
}

/// The robust kernel's ray-dependent part for the group kernel (WatertightRay<float, double>), and
/// for its float screen (robust_group_float_misses): the float ray in the permuted axes (kx, ky,
/// kz) and three per-ray constants of the screen's error bounds (finish_lane_ray).
struct RobustLaneRay {
  double o[3], d[3];  ///< the float ray in double
  int kx, ky, kz;
  float so[3], sd[3];  ///< the float ray, axes kx, ky, kz
  float edge_k = 0;    ///< >= 2^-19 D^2, D = |d_z| + max(|d_x|, |d_y|): the edge functions' bound per |a| |b|
  float a_limit = 0;   ///< 2^39 / D: larger vertex offsets are left to double
  float dn_k = 0;      ///< >= 2^-45 d_z^2: the double d . n's error bound per A^2
  double edge_k_double = 0;  ///< WatertightRay<float, double>::edge_k: the double kernel's bounded zeros
};

/// Fills the screen's part of `r` from o, d, kx, ky, kz (once per ray).
void finish_lane_ray(RobustLaneRay& r);

/// robust's float screen (SSE, four float lanes): bit i set when lane i (of `live`: triangle
/// lanes, no pad, scalar or dead ones) is proven to have no crossing for robust, i.e. the double
/// d . n of the scalar kernel is nonzero and its double edge functions U, V, W have mixed signs.
/// The error bounds behind it are derived in leaf_simd.cpp. Lanes not set are undecided.
[[nodiscard]] unsigned robust_group_float_misses(const RobustLaneRay& r, const TriGroup& g, unsigned live);

/// certified's per-ray part of the same screen, from the double ray (its float rounding, the axis
/// permutation of its dominant direction, and the bound's constants; off for rays out of range).
void certified_lane_ray(const Ray<double>& ray, RobustLaneRay& r);

/// certified's float screen (SSE): bit i set when lane i (of `live`: triangle lanes; the group's
/// float vertices are the roundings of the double ones) is proven missed by the exact double ray,
/// so certified::triangle reports no crossing for it. Derivation in leaf_simd.cpp.
[[nodiscard]] unsigned certified_group_float_misses(const RobustLaneRay& r, const TriGroup& g, unsigned live);

/// Whether the AVX2 path runs the float screen before the double lanes (default off: measured not
/// to pay there, see leaf_simd.cpp); the SSE path always runs it. For benchmarks and tests.
void set_robust_screen_avx2(bool on);
[[nodiscard]] bool robust_screen_avx2();
/// Whether certified's leaves run its float screen (SSE and AVX2 paths). Default off: it decides
/// about 65% of the lanes certified's leaves test (bunny00), but reading the groups costs more than
/// the double vertices it spares, and AVX2 stage 1 decides those lanes anyway: per ray 1.2-1.4x
/// slower with it on both paths (leaf_bench, bunny00 and refined_elephant). For benchmarks and tests.
void set_certified_screen(bool on);
[[nodiscard]] bool certified_screen();
/// Whether robust makes its leaf kernels' per-ray part at the first leaf a ray reaches (default on)
/// or in prepare(), for every ray (off: as before; for the ablation bench).
void set_lazy_leaf_setup(bool on);
[[nodiscard]] bool lazy_leaf_setup();

/// One group's robust results, lane by lane: `hit` lanes have a crossing (class, t, b1, b2 as the
/// scalar kernel computes them); `special` lanes need the scalar front door (d . n = 0).
struct RobustLanes {
  unsigned hit = 0, special = 0;
  std::uint8_t contact[kLanes];
  float t[kLanes], b1[kLanes], b2[kLanes];
};

/// The AVX2 robust group kernel over the lanes in `live` (no pad, scalar or dead lanes).
/// Only call when leaf_simd() == LeafSimd::avx2.
void robust_group_avx2(const RobustLaneRay& r, const TriGroup& g, unsigned live, RobustLanes& out);

/// certified's stage 1 (certified_triangle.h, triangle_stage1) up to its miss decision, in four
/// double lanes (AVX2): bit i set when lane i is a proven miss (the scalar stage 1 returns miss for
/// it, so certified::triangle does). `p[vertex][axis][lane]` are the triangles' double vertices.
/// Only call when leaf_simd() == LeafSimd::avx2.
[[nodiscard]] unsigned certified_group_misses_avx2(const Ray<double>& ray, const double (&p)[3][3][kLanes], unsigned live);

/// Möller–Trumbore's miss screen in four float lanes (SSE): bit i set when lane i may cross (the
/// scalar screen mt_surely_no_crossing is false); only lanes in `live` are considered.
[[nodiscard]] unsigned mt_group_survivors(const Ray<float>& ray, const TriGroup& g, unsigned live);

}  // namespace rayproof::scene::detail
