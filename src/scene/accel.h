#pragma once
/// Queries over a whole scene: a BVH over every primitive and one per-primitive method, for
/// closest hit, any hit (occlusion) and all hits (every crossing, sorted), each with [tmin, tmax],
/// one ray at a time or a batch over threads (TBB).
#include <cstdint>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "methods/method.h"
#include "rayproof/bvh_build.h"
#include "rayproof/bvh_traverse.h"
#include "rayproof/bvh_wide.h"
#include "scene/scene.h"

namespace rayproof::scene {

/// One crossing of a ray with a primitive: its class (CASES.md) and t. A miss has prim = kNoPrim.
struct PrimHit {
  static constexpr std::uint32_t kNoPrim = 0xffffffffu;
  Contact contact = Contact::miss;
  double t = kNaN<double>;
  std::uint32_t prim = kNoPrim;
  /// Equal classes, primitives and t (NaN t, as in a miss, equals NaN).
  friend bool operator==(const PrimHit& a, const PrimHit& b) {
    return a.contact == b.contact && a.prim == b.prim && (a.t == b.t || (a.t != a.t && b.t != b.t));
  }
  friend std::ostream& operator<<(std::ostream& os, const PrimHit& h) {
    return os << to_string(h.contact) << ' ' << h.t << ' ' << h.prim;
  }
};

/// Kernels compiled into the traversal (no per-primitive dispatch through the registry).
/// robust and certified are compiled for triangles and reach the registry method (`generic`) for
/// other kinds and, for certified, when the filter cannot decide (the exact fallback).
enum class FastKernel { none, mt_float, mt_double, cramer_float, cramer_double, watertight_float, watertight_double,
                        robust, certified };

/// How the scene's primitives are intersected: a compiled kernel, or any registry method through
/// its case interface (slower, used for exact, robust, certified and other methods).
struct SceneMethod {
  std::string name;
  FastKernel fast = FastKernel::none;
  const Method* generic = nullptr;
  BvhTraversal traversal = BvhTraversal::standard;
};

/// The scene method called `name`: a compiled kernel when there is one, else the registry's
/// method of that name (conservative traversal). Throws SceneError when neither exists.
[[nodiscard]] SceneMethod find_scene_method(const std::string& name, const MethodRegistry& reg);
/// Names with compiled kernels, for messages and the bench.
[[nodiscard]] std::vector<std::string> fast_scene_method_names();

/// A primitive in the BVH's leaf order: a triangle's vertex indices (unused for other kinds) and its
/// global number. Leaves read these contiguously instead of prim_ids -> triangles -> vertices.
struct LeafPrim {
  std::uint32_t v[3];
  std::uint32_t id;
};
static_assert(sizeof(LeafPrim) == 16);

struct QueryRange {
  double tmin = 0;
  double tmax = std::numeric_limits<double>::infinity();
};

class Accel {
 public:
  Accel(const Scene& s, const BvhBuildOptions& opt = {});

  [[nodiscard]] const Scene& scene() const { return scene_; }
  /// The four-wide BVH the queries traverse (the SAH or median binary tree, collapsed).
  [[nodiscard]] const Bvh4& bvh() const { return bvh_; }
  [[nodiscard]] double build_seconds() const { return build_seconds_; }
  /// BVH plus triangle data, per triangle (analytic primitives counted as triangles).
  [[nodiscard]] double bytes_per_primitive() const;
  /// Bytes of the BVH: its nodes and the leaf-order primitive records.
  [[nodiscard]] std::size_t bvh_bytes() const { return bvh_.bytes() + leaf_prims_.size() * sizeof(LeafPrim); }
  /// The leaf-order primitive records (slot j of the BVH's leaves).
  [[nodiscard]] const std::vector<LeafPrim>& leaf_prims() const { return leaf_prims_; }

  /// Closest crossing in [tmin, tmax] (ties: the lower primitive number); `invalid` for a ray
  /// with a NaN or infinite component or d = 0.
  [[nodiscard]] PrimHit closest(const Ray<double>& r, const SceneMethod& m, QueryRange q = {}) const;
  [[nodiscard]] bool any(const Ray<double>& r, const SceneMethod& m, QueryRange q = {}) const;
  /// Every crossing in [tmin, tmax], sorted by t then primitive.
  [[nodiscard]] std::vector<PrimHit> all(const Ray<double>& r, const SceneMethod& m, QueryRange q = {}) const;

  /// closest() for every ray, on `threads` threads (0: all hardware threads).
  void closest_batch(std::span<const Ray<double>> rays, std::span<PrimHit> out, const SceneMethod& m,
                     int threads = 0, QueryRange q = {}) const;
  void any_batch(std::span<const Ray<double>> rays, std::span<std::uint8_t> out, const SceneMethod& m,
                 int threads = 0, QueryRange q = {}) const;

 private:
  const Scene& scene_;
  Bvh4 bvh_;  ///< nodes only: prim_ids is folded into leaf_prims_
  std::vector<LeafPrim> leaf_prims_;
  double build_seconds_ = 0;
};

}  // namespace rayproof::scene
