#pragma once
/// `rayproof advise`: cast a scene's own rays (primary, leak, random, shadow) with every method,
/// compare each closest hit with `certified` (proven equal to exact), check a sample of certified
/// against `exact`, count which code paths the rays reached, and measure what a triangle-only scene
/// saves. The numbers only; the sentences are in cli/advise_text.h.
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "methods/method.h"
#include "scene/analysis.h"
#include "scene/scene.h"

namespace rayproof::scene {

struct AdviseOptions {
  std::size_t rays = 100000;       ///< per ray set (primary rays: the camera's pixels, strided to about this many)
  std::uint64_t seed = 1;
  int threads = 0;                 ///< 0: all hardware threads
  std::size_t slow_rays = 1000;    ///< per set, for registry (non-compiled) methods and the path counts
  std::size_t exact_sample = 200;  ///< rays of each set checked against `exact`
  double sliver_aspect = 1000;
  /// t error allowed (ulps of the method's precision) for methods that promise none (none: their t
  /// error is reported, not counted as an error).
  std::optional<std::uint64_t> t_tolerance;
  /// Methods to run (empty: every compiled scene method and every registry method but exact).
  std::vector<std::string> methods;
  /// Measure the triangle-only scene against the same plus one sphere: only on triangle-only scenes,
  /// on `rays` random rays clamped to [20000, 100000], each method warmed up once, best of 5.
  /// Runs of each candidate for the recommendation: 3, more (up to this) while a run is under 0.1 s.
  int max_timing_runs = 21;
  bool compare_kinds = true;
  std::size_t kind_cost_rays = 0;  ///< random rays for that (0: `rays` clamped to [20000, 100000])
  std::function<void(const std::string&)> progress;  ///< one line of progress (may be empty)
};

/// One ray set: its name ("primary", "leak", "random", "shadow") and size.
struct RaySetInfo {
  std::string name;
  std::size_t rays = 0;
  std::size_t reference_hits = 0;  ///< rays certified finds a hit for
  std::size_t invalid = 0;         ///< rays with a non-finite origin or direction, or d = 0 (no method hits them)
};

/// One method's closest hits against certified's on the scene's rays.
struct MethodTally {
  std::string name;
  bool compiled = false;        ///< a kernel compiled into the traversal (else the registry method, per case)
  bool float_precision = false; ///< t errors in float ulps
  /// The method's promise on the scene's kinds (Promise::describe): one text when the kinds share it,
  /// else "triangle: ...; sphere: ..."; "nothing" when none.
  std::string promise;
  /// The t error allowed on every kind of the scene (its promised ulps, else the options' tolerance);
  /// none when it differs between kinds or is not set.
  std::optional<std::uint64_t> tolerance;
  std::vector<std::string> unsupported;  ///< kinds in the scene the method has no code for ("sphere", ...)
  std::uint64_t rays = 0;       ///< rays compared (a strided subset for registry methods)
  std::uint64_t leak_rays = 0, leaks = 0;  ///< leak rays compared; those missed where certified hits
  std::uint64_t false_hits = 0, false_misses = 0;  ///< outside the leak set
  /// Both hit, another primitive, not at the same point: on the primary, random and shadow rays, and
  /// on the leak rays (aimed exactly at vertices and edge midpoints, where a ray that grazes the
  /// surface may pass it or not: a method on the other side of that hair hits another surface).
  std::uint64_t wrong_prims = 0, leak_wrong_prims = 0;
  /// Another primitive at the same point: the hit points within same_point_distance() along the
  /// ray, or one certified also crosses at exactly its t (a shared edge or vertex; not an error).
  std::uint64_t ties = 0;
  std::uint64_t wrong_class = 0;  ///< the right primitive with another contact class (edge as interior, ...)
  std::uint64_t t_compared = 0, t_over = 0;  ///< right primitive (or a tie): t beyond `tolerance`
  std::uint64_t max_ulps = 0;
  /// errors() per ray set, for the sets with any, in set order.
  std::vector<std::pair<std::string, std::uint64_t>> errors_by_set;     ///< the largest t error (ulps of its precision) on the right primitive
  /// Casting time of its rays (candidates for the recommendation: the fastest of `timing_runs`).
  double seconds = 0;
  int timing_runs = 1;
  [[nodiscard]] double mrays() const { return seconds > 0 ? double(rays) / seconds / 1e6 : 0; }
  /// Every error above; without the wrong primitives on leak rays when !count_leak_grazes.
  [[nodiscard]] std::uint64_t errors(bool count_leak_grazes = true) const {
    return leaks + false_hits + false_misses + wrong_prims + t_over + (count_leak_grazes ? leak_wrong_prims : 0);
  }
  /// No error (as errors()), rays compared, and code for every kind of the scene.
  [[nodiscard]] bool error_free(bool count_leak_grazes = true) const {
    return rays > 0 && errors(count_leak_grazes) == 0 && unsupported.empty();
  }
};

/// Which of certified's and robust's paths the rays reached (on the path-count sample).
struct PathCounts {
  std::uint64_t rays = 0;  ///< rays of the sample
  /// certified: primitive tests per kind (triangle, sphere, ellipsoid, disk, box) and those the
  /// floating-point filter could not decide (the exact GMP fallback).
  std::uint64_t certified_tests[5] = {}, certified_fallbacks[5] = {};
  /// robust on triangles: tests, degenerate triangles after rounding to float (skipped), and rays
  /// parallel to the triangle's plane in double (the front door's special case: coplanar or parallel).
  std::uint64_t robust_tests = 0, robust_degenerate = 0, robust_parallel = 0;
};

/// One method's speed on a triangle-only scene and on the same plus one sphere (same rays).
struct KindCost {
  std::string method;
  double triangles_only = 0, with_sphere = 0;  ///< Mrays/s, the best of `repeats`
  int repeats = 0;
  /// The triangle-only scene timed again in each round, after the sphere: its difference from
  /// `triangles_only` is the noise of the timings themselves.
  double triangles_only_again = 0;
  /// The timing noise: |triangles_only_again / triangles_only - 1|.
  [[nodiscard]] double noise() const {
    return triangles_only > 0 ? std::abs(triangles_only_again / triangles_only - 1) : 0;
  }
};

struct AdviseResult {
  SceneAnalysis analysis;
  std::vector<RaySetInfo> sets;
  std::size_t leak_components = 0;  ///< closed components the leak rays start in (at most AdviseOptions::rays)
  std::vector<MethodTally> methods;
  std::uint64_t reference_misses_on_leak_rays = 0;  ///< leak rays certified itself misses (origin not inside)
  std::uint64_t exact_checked = 0, exact_agree = 0;  ///< certified against exact: same primitive, class, t within 1 ulp
  PathCounts paths;
  std::vector<KindCost> kind_cost;  ///< empty unless measured
  std::size_t random_rays_for_kind_cost = 0;
  std::optional<std::string> recommended;  ///< the fastest error-free compiled method
  std::optional<std::string> recommended_except_grazes;  ///< the same, wrong primitives on leak rays not counted
  std::optional<std::uint64_t> t_tolerance;  ///< AdviseOptions::t_tolerance
  double same_point = 0;                     ///< same_point_distance() of the scene
  double seconds = 0;
};

/// How far apart two hit points may lie along a ray and count as the same point: 2^-20 of the
/// largest coordinate magnitude (16 float ulps of it; float methods see the scene rounded to float).
[[nodiscard]] double same_point_distance(const SceneAnalysis& a);

/// Runs everything above. Throws SceneError on an empty scene or an unknown method.
[[nodiscard]] AdviseResult advise(const Scene& s, const MethodRegistry& reg, const AdviseOptions& opt);

/// The fastest (Mrays/s) error-free method among compiled ones, else among all; none when none is.
[[nodiscard]] std::optional<std::string> cheapest_error_free(const std::vector<MethodTally>& methods,
                                                             bool count_leak_grazes = true);

}  // namespace rayproof::scene
